"""Harmonic balance from Python against the command line's own outputs, digit for digit."""

from __future__ import annotations

import numpy as np
import pytest

import whirl
from conftest import REFERENCE, assert_same_table, timeless

#: Through the first resonance with H = 2 (seconds): the branch folds there and loses
#: stability (a bifurcation), time marching compared at 60 Hz, and H = 1 and 2 studied.
FLAGS = ["--speeds", "1:60Hz", "--harmonics", "2", "--compare-time", "60Hz", "--harmonics-study", "1..2"]


@pytest.fixture(scope="module")
def result():
    return whirl.hbm(
        REFERENCE, "1:60Hz", harmonics=2, compare_time=["60Hz"], harmonics_study="1..2", progress=False
    )


def test_hbm_equals_the_command_line(run_cli, result):
    cli = run_cli("hbm", str(REFERENCE), *FLAGS)
    assert len(result.to_pandas("bifurcations")) > 0, "no bifurcation: the test would miss them"
    assert result.tables == ("branch", "bifurcations", "compare_time", "harmonics_study")
    assert timeless(result.to_dict()) == timeless(cli.summary())
    for table in result.tables:
        assert_same_table(result.to_pandas(table), cli.table(table))


def test_the_branch_runs_over_the_speeds_asked_for(result):
    branch = result.columns("branch")
    # Continuation starts at the first speed and ends at the last (the summary says it
    # reached it): 1 Hz and 60 Hz to round-off.
    assert result.end == "reached the last speed"
    np.testing.assert_allclose(branch["speed_hz"][[0, -1]], [1.0, 60.0], rtol=1e-12)
    assert branch["stable"].dtype == bool


def test_every_bifurcation_says_whether_it_holds_at_twice_the_samples(result):
    # The resolution check runs with the sweep: each bifurcation, in the summary and in
    # the table, is resolved or not at twice the sweep's samples.
    assert result.resolution_samples == 2 * result.samples_per_period
    assert all(b["resolved"] in (True, False) for b in result.bifurcations)
    table = result.columns("bifurcations")
    assert list(table["resolved"]) == [b["resolved"] for b in result.bifurcations]


def test_contact_smoothing_equals_the_command_line(run_cli):
    # The smoothed Hertz law through the first resonance: the branch, its bifurcations and
    # the summary as `--contact-smoothing` gives them, to the last bit.
    smoothed = whirl.hbm(REFERENCE, "1:60Hz", harmonics=2, contact_smoothing="0.01um", progress=False)
    cli = run_cli("hbm", str(REFERENCE), "--speeds", "1:60Hz", "--harmonics", "2", "--contact-smoothing", "0.01um")
    assert "blended to bounded curvature below an approach of 0.010 um" in smoothed.bearings
    assert timeless(smoothed.to_dict()) == timeless(cli.summary())
    for table in smoothed.tables:
        assert_same_table(smoothed.to_pandas(table), cli.table(table))


def test_bad_hbm_options_name_the_keyword():
    with pytest.raises(whirl.InputError, match="invalid `harmonics`"):
        whirl.hbm(REFERENCE, "1:60Hz", harmonics=0)
    with pytest.raises(whirl.InputError, match="invalid `speeds`"):
        whirl.hbm(REFERENCE, "60Hz:1Hz")
    with pytest.raises(whirl.InputError, match="invalid `cage`"):
        whirl.hbm(REFERENCE, "1:60Hz", cage="loose")
    with pytest.raises(whirl.InputError, match="invalid `samples`"):
        whirl.hbm(REFERENCE, "1:60Hz", harmonics=5, samples=10)
    with pytest.raises(whirl.InputError, match="invalid `contact_smoothing`"):
        whirl.hbm(REFERENCE, "1:60Hz", contact_smoothing="-0.01um")
    with pytest.raises(whirl.InputError, match="invalid `contact_smoothing`"):
        whirl.hbm(REFERENCE, "1:60Hz", contact_smoothing="0.01s")
