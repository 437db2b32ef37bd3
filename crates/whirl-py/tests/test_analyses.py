"""The analyses the library reports whole, from Python against the command line's own
outputs, digit for digit, and against what they must hold."""

from __future__ import annotations

import numpy as np
import pytest

import whirl
from conftest import REFERENCE, assert_matches_cli


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
