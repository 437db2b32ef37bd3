"""The NSV map from Python against the command line's own outputs, digit for digit."""

from __future__ import annotations

import pytest

import whirl
from conftest import REFERENCE, assert_same_table, timeless

#: Two clearances through the first resonance with H = 2 on a 12-mode model (seconds), and
#: the 20 um cascade below 30 Hz checked against it (its varying-compliance resonance).
FLAGS = ["--values", "20um,60um", "--speeds", "1:30Hz", "--harmonics", "2", "--reduce", "12", "--check", "20um"]


@pytest.fixture(scope="module")
def result():
    return whirl.map(REFERENCE, ["20um", "60um"], "1:30Hz", harmonics=2, reduce=12, check="20um", progress=False)


def test_map_equals_the_command_line(run_cli, result):
    cli = run_cli("map", str(REFERENCE), *FLAGS)
    assert result.tables == ("bands", "lines", "values", "checks")
    assert len(result.to_pandas("lines")) > 0, "no resonance line: the test would miss them"
    assert timeless(result.to_dict()) == timeless(cli.summary())
    for table in result.tables:
        # Each sweep's cost differs between runs.
        times = ["cpu_s", "wall_s"] if table == "values" else []
        assert_same_table(result.to_pandas(table).drop(columns=times), cli.table(table).drop(columns=times))


def test_options_left_out_are_the_librarys_defaults(result):
    # H and the contact law were given or left to the library; the summary says which
    # were used: the command line's defaults.
    assert result.harmonics == 2
    assert result.stability_modes == whirl._whirl.DEFAULT_STABILITY_MODES
    assert "hertz" in result.bearings.lower()


def test_bad_map_options_name_the_keyword():
    with pytest.raises(whirl.InputError, match="check"):
        whirl.map(REFERENCE, "20um", "1:30Hz", check="30um", progress=False)
    with pytest.raises(whirl.InputError, match="parameter"):
        whirl.map(REFERENCE, "20um", "1:30Hz", parameter="roller_bearing[0].nonsense", progress=False)
    with pytest.raises(whirl.InputError, match="invalid `harmonics`"):
        whirl.map(REFERENCE, "20um", "1:30Hz", harmonics=0, progress=False)
