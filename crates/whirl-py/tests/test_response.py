"""The unbalance response from Python against the command line's, digit for digit."""

from __future__ import annotations

import numpy as np
import pytest

import whirl
from conftest import REFERENCE, assert_matches_cli


def test_unbalance_equals_the_command_line(run_cli):
    cli = run_cli("unbalance", str(REFERENCE), "--speeds", "1:300Hz:150", "--nodes", "10,0")
    assert_matches_cli(whirl.unbalance(REFERENCE, "1:300Hz:150", nodes=[10, 0]), cli)


def test_unbalance_default_nodes_are_the_disks_and_bearings(run_cli):
    cli = run_cli("unbalance", str(REFERENCE), "--speeds", "1:100Hz:20")
    result = whirl.unbalance(whirl.Model.from_file(REFERENCE), "1:100Hz:20")
    assert [n["node"] for n in result.to_dict()["nodes"]] == [n["node"] for n in cli.summary()["nodes"]]


def test_the_response_is_linear_in_the_unbalance():
    model = whirl.Model.from_file(REFERENCE)
    base = whirl.unbalance(model, "1:50Hz:10", nodes=[10])
    # Doubling the unbalance doubles the linear response (to rounding).
    doubled = model.with_values({"unbalance[*].eccentricity": "80 um"})
    twice = whirl.unbalance(doubled, "1:50Hz:10", nodes=[10])
    np.testing.assert_allclose(twice.node(10).major, 2 * base.node(10).major, rtol=1e-12)


def test_a_node_off_the_shaft_is_refused():
    with pytest.raises(whirl.InputError, match="node 999 is not on the shaft"):
        whirl.unbalance(REFERENCE, "1:50Hz:10", nodes=[999])
