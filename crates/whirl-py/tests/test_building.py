"""Models built in code: parts (whirl.Shaft, whirl.Disk, ...) and the model file's tables as
a dict, each round-tripping to the model; pint quantities; and an unbalance and roller
bearings added to a rotor read from ROSS."""

from __future__ import annotations

import math
import pickle
import warnings

import numpy as np
import pytest

import whirl
from conftest import EXAMPLES, REFERENCE, ROOT

MODELS = sorted(p for p in EXAMPLES.glob("*.toml") if "study" not in p.name)

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


def test_a_pinned_shaft_built_from_parts_has_the_beams_first_frequency():
    # A uniform Euler-Bernoulli shaft on two stiff supports at its ends: pinned-pinned,
    # f1 = (pi / L)^2 sqrt(E I / (rho A)) / (2 pi).
    length, diameter, young, density = 1.0, 0.05, 2.11e11, 7810.0
    model = whirl.Model.build(
        "pinned shaft",
        [
            whirl.Material(name="steel", young_modulus=young, density=density),
            whirl.Shaft(length=f"{length} m", outer_diameter=f"{1e3 * diameter} mm", material="steel", elements=20),
            whirl.Elements(rotary_inertia=False, gyroscopic=False),
            [whirl.Bearing(node=n, kxx=1e13, kyy=1e13) for n in (0, 20)],
        ],
        gravity=0,
    )
    area, inertia = math.pi * diameter**2 / 4, math.pi * diameter**4 / 64
    exact = (math.pi / length) ** 2 * math.sqrt(young * inertia / (density * area)) / (2 * math.pi)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", whirl.WhirlWarning)
        first = whirl.check(model).frequencies_hz[0]
    # 20 cubic elements put the first mode 3e-7 high (measured); supports 3e6 times the shaft's
    # midspan stiffness (48 E I / L^3) lower it by about 1e-7: 1e-5 leaves a wide margin
    # and still fails on a wrong unit, boundary or section (each moves it by percent).
    assert first == pytest.approx(exact, rel=1e-5)


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.name)
def test_every_example_is_the_same_model_built_from_its_parts(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", whirl.WhirlWarning)
        model = whirl.Model.from_file(path)
        tables = model.to_tables()
        rebuilt = whirl.Model.build(model.name, model.parts(), model.gravity)
    assert rebuilt.to_dict() == model.to_dict()
    assert rebuilt.to_tables() == tables
    # And through the model file's text: the parts read back are the parts given.
    assert whirl.Model.from_toml(rebuilt.toml).parts() == model.parts()


def test_a_built_model_writes_its_tables_in_the_order_given():
    model = whirl.Model.build(
        "order",
        [
            whirl.Material(name="steel", young_modulus=2.11e11, density=7810),
            whirl.Shaft(length="1 m", outer_diameter="50 mm", material="steel", elements=4),
            whirl.Disk(node=2, mass="10 kg", polar_inertia=0.05, diametral_inertia=0.025),
            [whirl.Bearing(node=n, kxx=1e8, kyy=1e8) for n in (0, 4)],
        ],
    )
    headers = [line for line in model.toml.splitlines() if line.startswith("[")]
    assert headers == ["[[material]]", "[[shaft]]", "[[disk]]", "[[bearing]]", "[[bearing]]"]
    assert list(model.to_tables()["disk"][0]) == ["node", "mass", "polar_inertia", "diametral_inertia"]


def test_parts_hold_their_tables_nested_parts_and_pickle():
    model = whirl.Model.from_file(EXAMPLES / "reference_rotor_waviness.toml")
    bearing = next(p for p in model.parts() if isinstance(p, whirl.RollerBearing))
    assert all(isinstance(w, whirl.Waviness) for w in bearing.waviness)
    assert bearing.to_dict()["waviness"] == model.to_tables()["roller_bearing"][0]["waviness"]
    assert pickle.loads(pickle.dumps(bearing)) == bearing
    assert repr(whirl.Disk(node=10, mass="10 kg")) == "Disk(node=10, mass='10 kg')"


def test_a_wrong_part_is_named():
    parts = whirl.Model.from_file(REFERENCE).parts()
    shaft = next(i for i, p in enumerate(parts) if isinstance(p, whirl.Shaft))
    parts[shaft] = whirl.Shaft(**{**parts[shaft].fields, "lenght": "1 m"})
    # Named by its key, not by a line of text the caller never saw.
    with pytest.raises(whirl.InputError, match=r"^`shaft\[0\]\.lenght`: unknown field"):
        whirl.Model.build("typo", parts)
    with pytest.raises(TypeError, match="waviness"):
        whirl.Model.build("loose", [*parts, whirl.Waviness(ring="outer", order=5, amplitude="1 um")])
    with pytest.raises(ValueError, match=r"one \[damping\]"):
        whirl.Model.build("twice", [*parts, whirl.Damping(alpha=1.0)])


def test_pint_quantities_in_parts_are_their_text():
    pint = pytest.importorskip("pint")
    u = pint.UnitRegistry()
    assert whirl.Disk(node=1, mass=10 * u.kg).to_dict() == whirl.Disk(node=1, mass="10.0 kg").to_dict()


def test_parts_added_to_a_ross_rotor():
    rotor = ross_rotor()
    unbalanced = rotor.extended([whirl.Unbalance(node=2, eccentricity="50 um")])
    assert unbalanced.to_tables()["unbalance"] == [{"node": 2, "eccentricity": "50 um"}]
    # Roller bearings in place of its linear ones, as parts.
    roller = whirl.Model.from_file(REFERENCE).to_tables()["roller_bearing"][0]
    linear = [p for p in rotor.parts() if isinstance(p, whirl.Bearing)]
    parts = [p for p in rotor.parts() if not isinstance(p, whirl.Bearing)]
    parts += [whirl.RollerBearing(**{**roller, "name": f"roller {b.node}", "node": b.node}) for b in linear]
    model = whirl.Model.build(rotor.name, parts)
    assert model.bearing_nodes() == sorted(b.node for b in linear)
    assert np.all(whirl.check(model).frequencies_hz > 0)


def test_the_docs_parts_example_runs_as_written():
    # docs/python.md's block after "built in code from parts", run as a reader would.
    text = (ROOT / "docs" / "python.md").read_text()
    after = text[text.index("A model is also built in code from parts") :]
    block = after[after.index("```python\n") + len("```python\n") :]
    block = block[: block.index("```")]
    scope: dict = {}
    exec(compile(block, "docs/python.md", "exec"), scope)
    assert scope["same"].to_dict() == scope["rotor"].to_dict()
    assert [type(p).__name__ for p in scope["parts"]] == [
        "Material", "Shaft", "Elements", "Disk", "Bearing", "Bearing", "Unbalance"
    ]
