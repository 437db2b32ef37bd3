"""The cascade from Python against the command line's, digit for digit; its checkpoint,
resume and stop."""

from __future__ import annotations

import numpy as np
import pytest

import whirl
from conftest import EXAMPLES, REFERENCE, assert_same_table

#: A small cascade with everything that matters: requested and refined speeds, averaged
#: records, the full spectrum. Seconds of computing.
SPEEDS = "100Hz:400Hz:4"
OPTIONS = {"max_records": 2, "settle_max": "1s", "refine_budget": 3, "full": True}
FLAGS = ["--max-records", "2", "--settle-max", "1s", "--refine-budget", "3", "--full"]

#: Keys of summary.json that say where and how long, not what: they differ between runs.
CIRCUMSTANCES = ("wall_time_s", "checkpoint_folder", "resumed_speeds")


def what(summary: dict) -> dict:
    return {k: v for k, v in summary.items() if k not in CIRCUMSTANCES}


def assert_same_cascade(a: whirl.CascadeResult, b: whirl.CascadeResult):
    assert what(a.to_dict()) == what(b.to_dict())
    for table in ("nsv", "cascade", "full_cascade"):
        x, y = a.to_pandas(table), b.to_pandas(table)
        assert list(x.columns) == list(y.columns)
        for column in x.columns:
            np.testing.assert_array_equal(x[column].to_numpy(), y[column].to_numpy(), err_msg=column)


def test_cascade_equals_the_command_line(run_cli):
    cli = run_cli("cascade", str(REFERENCE), "--speeds", SPEEDS, *FLAGS)
    result = whirl.cascade(REFERENCE, SPEEDS, progress=False, **OPTIONS)
    assert len(result.speeds_hz) > 4, "the refinement added no speed: the test would miss it"
    assert what(result.to_dict()) == what(cli.summary())
    assert result.tables == ("cascade", "full_cascade", "nsv")
    for table in result.tables:
        assert_same_table(result.to_pandas(table), cli.table(table))
    # Counts and flags are integers, as the CSV writes them.
    nsv = result.to_pandas("nsv")
    assert all(nsv[c].dtype == np.int64 for c in ("added", "settled", "records"))


def test_a_resumed_cascade_is_the_same_to_the_bit(tmp_path):
    first = whirl.cascade(REFERENCE, SPEEDS, checkpoint=tmp_path, progress=False, **OPTIONS)
    again = whirl.cascade(REFERENCE, SPEEDS, checkpoint=tmp_path, progress=False, **OPTIONS)
    assert first.resumed_speeds == 0
    assert again.resumed_speeds == len(again.speeds_hz)
    assert again.checkpoint_folder == first.checkpoint_folder
    assert again.checkpoint_folder.startswith(str(tmp_path))
    assert_same_cascade(first, again)
    fresh = whirl.cascade(REFERENCE, SPEEDS, checkpoint=tmp_path, restart=True, progress=False, **OPTIONS)
    assert fresh.resumed_speeds == 0


def test_a_stopped_cascade_keeps_its_speeds_and_resumes(tmp_path):
    told = []

    def stop_after_two(done, total):
        told.append((done, total))
        return done >= 2

    # 24 speeds: the stop (seen within a 100 ms poll) must come while speeds are left;
    # with four, a quiet machine finished them all first and nothing was stopped.
    speeds = "100Hz:400Hz:24"
    with pytest.raises(KeyboardInterrupt, match="stopped after"):
        whirl.cascade(REFERENCE, speeds, checkpoint=tmp_path, progress=stop_after_two, **OPTIONS)
    assert told and told[-1][1] >= 24
    resumed = whirl.cascade(REFERENCE, speeds, checkpoint=tmp_path, progress=False, **OPTIONS)
    assert resumed.resumed_speeds >= 2
    whole = whirl.cascade(REFERENCE, speeds, progress=False, **OPTIONS)
    assert_same_cascade(resumed, whole)


def test_default_speeds_are_the_command_lines():
    # One definition in the library (as for the command line and a study): 150 speeds over
    # the reference rotor's [operating] range, 1 to 750 Hz, to the bit.
    model = whirl.Model.from_file(REFERENCE)
    w = whirl.nsv.default_speeds(model)
    np.testing.assert_array_equal(w, whirl._whirl.parse_speeds("1Hz:750Hz:150"))
    assert whirl.nsv.options(model)["speeds"] == list(w)


def test_bad_cascade_options_name_the_keyword():
    with pytest.raises(whirl.InputError, match="invalid `contact`: `glue` is not one of"):
        whirl.cascade(REFERENCE, SPEEDS, contact="glue")
    with pytest.raises(whirl.InputError, match="invalid `settle`"):
        whirl.cascade(REFERENCE, SPEEDS, settle="half a second")


def test_study_equals_the_command_line(run_cli, tmp_path):
    # The quick study with a straight line fitted through its two points: every table.
    study = tmp_path / "study.toml"
    text = (EXAMPLES / "quick_study.toml").read_text()
    text = text.replace('model = "reference_rotor.toml"', f"model = {str(REFERENCE)!r}")
    study.write_text(text.replace('values = ["20 um", "60 um"]', 'values = ["20 um", "60 um"]\nfit = "linear"'))
    cli = run_cli("study", str(study), "--checkpoint", str(tmp_path / "cli.points"))
    result = whirl.study(study, checkpoint=tmp_path / "py.points", progress=False)
    timeless = lambda s: {  # noqa: E731
        **{k: v for k, v in s.items() if k not in ("checkpoint", "wall_time_s", "cascade_time_s")},
        "points": [{k: v for k, v in p.items() if k != "wall_time_s"} for p in s["points"]],
    }
    assert timeless(result.to_dict()) == timeless(cli.summary())
    assert len(result.to_pandas("fits")) == 1, "no fit: the test would miss the fits table"
    for table in result.tables:
        python, written = result.to_pandas(table), cli.table(table)
        if table == "points":
            python, written = python.drop(columns="wall_time_s"), written.drop(columns="wall_time_s")
        assert_same_table(python, written)


def test_compare_starts_equals_the_command_line(run_cli):
    cli = run_cli("cascade", str(REFERENCE), "--speeds", SPEEDS, *FLAGS, "--compare-starts")
    result = whirl.cascade(REFERENCE, SPEEDS, compare_starts=True, progress=False, **OPTIONS)
    assert result.starts["compared_speeds"] > 0, "no speed compared: the test would miss them"
    assert what(result.to_dict()) == what(cli.summary())
    for table in ("nsv", "starts"):
        assert_same_table(result.to_pandas(table), cli.table(table))


def test_keywords_left_out_take_the_librarys_defaults_and_unknown_ones_are_named():
    # The keywords pass through to the library's request as given: one left out is the
    # library's default (its resolved options), one given is read with its unit, and a
    # name the cascade does not have is refused by name, listing those it has.
    model = whirl.Model.from_file(REFERENCE)
    default = whirl.nsv.options(model, SPEEDS)
    given = whirl.nsv.options(model, SPEEDS, settle="1s", window="flat-top")
    assert given["settle"] == 1.0 and default["settle"] != 1.0
    assert given["window"] == "flat-top" and default["window"] == "hann"
    assert {k: v for k, v in given.items() if k not in ("settle", "window")} == {
        k: v for k, v in default.items() if k not in ("settle", "window")
    }
    with pytest.raises(whirl.InputError, match="invalid `setle`: the cascade has no option `setle`"):
        whirl.cascade(REFERENCE, SPEEDS, setle="1s")
