"""Rotors written by ROSS itself, read by whirl: the natural frequencies equal ROSS's.

The fixtures (crates/whirl/tests/fixtures/ross) were saved by ROSS 2.3.0's ``Rotor.save``
with ROSS's own frequencies beside them; make_fixtures.py there is the script that made
them. ROSS is not needed to run these tests.
"""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

import whirl
from conftest import ROOT

FIXTURES = ROOT / "crates" / "whirl" / "tests" / "fixtures" / "ross"


def ross_frequencies(name: str) -> np.ndarray:
    return np.array(json.loads((FIXTURES / f"{name}.frequencies.json").read_text())["frequencies_hz"])


@pytest.mark.parametrize("name", ["rotor_example_eb", "rotor_example", "rotor_example_with_damping"])
def test_frequencies_equal_ross(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", whirl.WhirlWarning)
        model = whirl.read_ross(FIXTURES / f"{name}.toml")
    ross = ross_frequencies(name)
    found = whirl.check(model).frequencies_hz
    # Both build the same element matrices and solve the same symmetric eigenproblem in
    # double precision: measured 1e-13 to 1e-11 on rotor_example, 2e-9 on the damped
    # example's 1-cm elements (crates/whirl/tests/suite/ross.rs); 1e-6 leaves room above both.
    np.testing.assert_allclose(found, ross[: len(found)], rtol=1e-6)


def test_a_live_rotor_goes_through_its_own_save():
    class Saved:
        """Stands for a ross.Rotor: what from_ross needs of one is its save(path)."""

        def save(self, path):
            path.write_bytes((FIXTURES / "rotor_example_eb.toml").read_bytes())

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", whirl.WhirlWarning)
        live = whirl.from_ross(Saved(), name="rotor_example_eb")
        read = whirl.read_ross(FIXTURES / "rotor_example_eb.toml")
    assert live.to_dict() == read.to_dict()


def test_what_whirl_cannot_represent_is_refused_by_element():
    with pytest.raises(whirl.InputError, match="bearing|seal"):
        whirl.read_ross(FIXTURES / "compressor_example.toml")
