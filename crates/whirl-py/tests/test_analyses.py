"""The analyses the library reports whole, from Python against the command line's own
outputs, digit for digit, and against what they must hold."""

from __future__ import annotations

import numpy as np
import pytest

import whirl
from conftest import REFERENCE, assert_matches_cli, assert_same_table, timeless


def test_reduce_equals_the_command_line(run_cli):
    cli = run_cli("reduce", str(REFERENCE), "--modes", "8", "--nodes", "10")
    assert_matches_cli(whirl.reduce(REFERENCE, modes=8, nodes=[10]), cli)


def test_reduction_errors_fall_as_modes_are_kept():
    result = whirl.reduce(REFERENCE, modes=12)
    full, reduced = np.array(result.full_frequencies_hz), np.array(result.reduced_frequencies_hz)
    # Craig-Bampton is a Rayleigh-Ritz method: the reduced frequencies bound the full ones
    # from above, and adding modes to the (nested) basis never raises them. Both hold to the
    # eigen-solver's accuracy, which the full model's repeated pairs show: a pair (x and y
    # on isotropic bearings) differs by 2e-10 relative, so 1e-9 is the tolerance.
    assert np.all(reduced >= full * (1 - 1e-9))
    error = result.to_pandas("study")["mode1_relative_error"].to_numpy()
    assert np.all(np.diff(error) <= 1e-9)
    assert error[-1] < 1e-3 * error[0]


def test_bad_reduce_options_name_the_keyword():
    with pytest.raises(whirl.InputError, match="invalid `modes`"):
        whirl.reduce(REFERENCE, modes=0)
    with pytest.raises(whirl.InputError, match="invalid `nodes`"):
        whirl.reduce(REFERENCE, nodes=[999])


def test_static_equals_the_command_line(run_cli):
    cli = run_cli("static", str(REFERENCE))
    result = whirl.static(REFERENCE)
    assert "rollers" in result.tables, "no roller table: the test would miss it"
    assert_matches_cli(result, cli)


def test_static_reactions_carry_the_weight():
    result = whirl.static(REFERENCE, rollers="linear")
    # Equilibrium: the bearings' vertical reactions sum to the weight, to the linear
    # solve's round-off (1e-9 relative).
    assert result.reaction_sum_over_weight == pytest.approx(1.0, rel=1e-9)


def test_ucs_equals_the_command_line(run_cli):
    cli = run_cli("ucs", str(REFERENCE), "--modes", "3")
    assert_matches_cli(whirl.ucs(REFERENCE, modes=3), cli)
    cli = run_cli("ucs", str(REFERENCE), "--stiffness", "1e6:1e9:7", "--at-rest")
    assert_matches_cli(whirl.ucs(REFERENCE, stiffness="1e6:1e9:7", at_rest=True), cli)


def test_frf_equals_the_command_line(run_cli):
    flags = ["--input", "10:uy", "--output", "10:uy,0:ux", "--speed", "100Hz",
             "--frequencies", "0:400Hz:201", "--force", "2kN"]
    cli = run_cli("frf", str(REFERENCE), *flags)
    result = whirl.frf(REFERENCE, "10:uy", output=["10:uy", "0:ux"], speed="100Hz",
                       frequencies="0:400Hz:201", force="2kN")
    assert_matches_cli(result, cli)
    cli = run_cli("frf", str(REFERENCE), "--input", "10:ux")
    assert_matches_cli(whirl.frf(REFERENCE, (10, "ux")), cli)


def test_fit_forcing_equals_the_command_line(run_cli):
    cli = run_cli("fit-forcing", str(REFERENCE), "--speeds", "200Hz:300Hz:2", "--duration", "0.2s",
                  "--settle", "0.1s")
    result = whirl.fit_forcing(REFERENCE, "200Hz:300Hz:2", duration="0.2s", settle="0.1s")
    assert timeless(result.to_dict()) == timeless(cli.summary())
    assert_same_table(result.to_pandas("fit"), cli.table("fit"))


def test_bad_options_of_the_reports_name_the_keyword():
    with pytest.raises(whirl.InputError, match="invalid `rollers`"):
        whirl.static(REFERENCE, rollers="glued")
    with pytest.raises(whirl.InputError, match="invalid `stiffness`"):
        whirl.ucs(REFERENCE, stiffness="1e9:1e6:7")
    with pytest.raises(whirl.InputError, match="invalid `input`"):
        whirl.frf(REFERENCE, "10:uz")
    with pytest.raises(whirl.InputError, match="invalid `output`: node 99"):
        whirl.frf(REFERENCE, "10:uy", output=["99:uy"])
    with pytest.raises(whirl.InputError, match="roller bearing 5 does not exist"):
        whirl.fit_forcing(REFERENCE, "200Hz:300Hz:2", bearing=5)


def test_stiffness_equals_the_command_line(run_cli):
    # The defaults (the weight's share of the load, 12 clearances, two surfaces), with a
    # coarse passage and grid to keep the test short.
    cli = run_cli("stiffness", str(REFERENCE), "--cage-steps", "4", "--grid", "5")
    result = whirl.stiffness(REFERENCE, cage_steps=4, grid=5)
    assert result.tables == ("stiffness", "passage", "surfaces_20um", "surfaces_60um")
    assert_matches_cli(result, cli)
    flags = ["--bearing", "1", "--clearances", "5um:50um:4", "--load", "2kN", "--load-angle",
             "-60", "--cage-angle", "10", "--cage-steps", "3", "--surface-clearances",
             "0um,30um,30um", "--grid", "4"]
    cli = run_cli("stiffness", str(REFERENCE), *flags)
    result = whirl.stiffness(REFERENCE, bearing=1, clearances="5um:50um:4", load="2kN",
                             load_angle=-60, cage_angle=10, cage_steps=3,
                             surface_clearances=["0um", 30e-6, "30um"], grid=4)
    assert_matches_cli(result, cli)


def test_stiffness_counts_come_back_as_integers():
    result = whirl.stiffness(REFERENCE, clearances="10um:20um:2", cage_steps=2, grid=3)
    assert result.to_pandas("stiffness")["averaged_most_rollers"].dtype == np.int64
    surface = result.to_pandas("surfaces_20um")
    assert surface["rollers_in_contact"].dtype == np.int64
    assert surface["fr_n"].dtype == np.float64


def test_bad_stiffness_options_name_the_keyword():
    with pytest.raises(whirl.InputError, match="invalid `bearing`: .*there is no bearing 5"):
        whirl.stiffness(REFERENCE, bearing=5)
    with pytest.raises(whirl.InputError, match="invalid `clearances`: .*must not be negative"):
        whirl.stiffness(REFERENCE, clearances=[-1e-6])
    with pytest.raises(whirl.InputError, match="invalid `load`: .*more than a tenth"):
        whirl.stiffness(REFERENCE, load="1e30N")
    with pytest.raises(whirl.InputError, match="invalid `cage_steps`"):
        whirl.stiffness(REFERENCE, cage_steps=0)
    with pytest.raises(whirl.InputError, match="invalid `grid`"):
        whirl.stiffness(REFERENCE, grid=1)
