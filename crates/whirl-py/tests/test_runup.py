"""whirl.runup: the command line's run-up, every option left out at the library's default."""

from __future__ import annotations

import pytest

import whirl
from conftest import REFERENCE, assert_same_table, timeless

#: A short sweep both ways at 40 Hz/s with a steady cascade of three speeds from one start.
SHORT = {"speeds": "100:140Hz", "rate": "40Hz/s", "steady": "cascade", "steady_speeds": 3}


def test_runup_equals_the_command_line(run_cli):
    cli = run_cli(
        "runup", str(REFERENCE), "--speeds", "100:140Hz", "--rate", "40Hz/s",
        "--steady", "cascade", "--steady-speeds", "3",
    )
    result = whirl.runup(REFERENCE, **SHORT)
    assert timeless(result.to_dict()) == timeless(cli.summary())
    for table in ("runup", "steady", "hysteresis", "bands"):
        assert_same_table(result.to_pandas(table), cli.table(table))


def test_a_rate_in_rpm_per_second_is_the_same_sweep():
    # 2400 rpm/s is 40 Hz/s: the same run, so the same readings.
    hz = whirl.runup(REFERENCE, **{**SHORT, "steady": "none"}).to_pandas("runup")
    rpm = whirl.runup(REFERENCE, **{**SHORT, "steady": "none", "rate": "2400rpm/s"}).to_pandas("runup")
    assert hz["one_x_m"].tolist() == rpm["one_x_m"].tolist()


@pytest.mark.parametrize(
    "bad, field",
    [({"rate": 0.0}, "rate"), ({"rate": "-5Hz/s"}, "rate"), ({"speeds": "140:100Hz"}, "speeds"),
     ({"direction": "sideways"}, "direction"), ({"overlap": 1.0}, "overlap")],
)
def test_bad_sweeps_name_the_keyword(bad, field):
    with pytest.raises(whirl.InputError, match=field):
        whirl.runup(REFERENCE, **{**SHORT, "steady": "none", **bad})
