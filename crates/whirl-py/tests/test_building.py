"""Models built in code: the model file's tables as a dict and back, pint quantities, and
an unbalance and roller bearings added to a rotor read from ROSS."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import whirl
from conftest import REFERENCE, ROOT

ROSS_ROTOR = ROOT / "crates" / "whirl" / "tests" / "fixtures" / "ross" / "rotor_example.toml"


def ross_rotor() -> whirl.Model:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", whirl.WhirlWarning)
        return whirl.read_ross(ROSS_ROTOR)


def test_the_tables_read_back_as_the_same_model():
    model = whirl.Model.from_file(REFERENCE)
    tables = model.to_tables()
    assert tables["roller_bearing"][0]["clearance"] == model.to_tables()["roller_bearing"][0]["clearance"]
    assert whirl.Model.from_dict(tables).to_dict() == model.to_dict()


def test_pint_quantities_are_read_in_the_model_files_units():
    pint = pytest.importorskip("pint")
    u = pint.UnitRegistry()
    model = whirl.Model.from_file(REFERENCE)
    by_text = model.with_values({"roller_bearing[*].clearance": "30 um", "unbalance[0].phase": 90})
    by_pint = model.with_values({"roller_bearing[*].clearance": 0.03 * u.mm, "unbalance[0].phase": 90 * u.degree})
    assert by_pint.to_dict() == by_text.to_dict()
    tables = model.to_tables()
    tables["operating"] = {"min_speed": 3000 * u.rpm, "max_speed": 100 * u.Hz}
    operating = whirl.Model.from_dict(tables).to_dict()["operating"]
    # whirl's Hz is revolutions per second (pint's a plain 1/s): 100 Hz is 200 pi rad/s.
    np.testing.assert_allclose(operating, [100 * np.pi, 200 * np.pi], rtol=1e-15)


def test_an_unbalance_on_a_rotor_read_from_ross():
    rotor = ross_rotor()
    # ROSS's rotor_example carries its disks at nodes 2 and 4.
    unbalanced = rotor.extended({"unbalance": [{"node": 2, "eccentricity": "50 um"}]})
    response = whirl.unbalance(unbalanced, "1:200Hz:40", nodes=[2])
    assert np.all(response.node(2).major > 0)
    assert "unbalance" not in rotor.to_tables(), "the original model is a value, left as it was"


def test_roller_bearings_in_place_of_a_ross_rotors_linear_bearings():
    tables = ross_rotor().to_tables()
    nodes = [b["node"] for b in tables.pop("bearing")]
    roller = whirl.Model.from_file(REFERENCE).to_tables()["roller_bearing"][0]
    tables["roller_bearing"] = [{**roller, "name": f"roller {n}", "node": n} for n in nodes]
    model = whirl.Model.from_dict(tables)
    assert model.bearing_nodes() == nodes
    assert np.all(whirl.check(model).frequencies_hz > 0)
