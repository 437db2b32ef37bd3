"""The model from a file, TOML text and a dict, edited by parameter paths, and its errors."""

from __future__ import annotations

import pickle
import tomllib

import numpy as np
import pytest

import whirl
from conftest import REFERENCE


def test_the_three_ways_in_give_the_same_model():
    from_file = whirl.Model.from_file(REFERENCE)
    text = REFERENCE.read_text()
    from_text = whirl.Model.from_toml(text)
    from_dict = whirl.Model.from_dict(tomllib.loads(text))
    assert from_file.name == from_text.name == from_dict.name
    # The validated models, SI inside, are the same whichever way the tables came in.
    assert from_file.to_dict() == from_text.to_dict() == from_dict.to_dict()
    assert from_file.file == str(REFERENCE)
    assert from_text.file is None


def test_a_model_survives_pickling_as_its_text():
    model = whirl.Model.from_file(REFERENCE).with_values({"roller_bearing[*].clearance": "30 um"})
    again = pickle.loads(pickle.dumps(model))
    assert again.to_dict() == model.to_dict()
    assert again.file == model.file


def test_edits_by_path_change_every_selected_bearing_and_nothing_else():
    model = whirl.Model.from_file(REFERENCE)
    before = model.to_dict()
    edited = model.with_values({"roller_bearing[*].clearance": "30 um", "unbalance[0].phase": 90})
    after = edited.to_dict()
    assert len(after["roller_bearings"]) >= 2
    for b in after["roller_bearings"]:
        # 30 um written with its unit is 3e-5 m inside.
        assert b["clearance"] == {"Constant": pytest.approx(30e-6, rel=1e-12)}
    # The model file's phase is in degrees; whirl holds radians.
    assert after["unbalances"][0]["phase"] == pytest.approx(np.pi / 2, rel=1e-15)
    for key in ("sections", "disks", "bearings", "damping", "gravity"):
        assert after[key] == before[key]
    # The original is untouched: models are values.
    assert model.to_dict() == before


def test_a_bad_path_says_how_paths_are_written():
    model = whirl.Model.from_file(REFERENCE)
    with pytest.raises(whirl.InputError, match=r"roller_bearing\[7\]"):
        model.with_values({"roller_bearing[7].clearance": 1e-5})
    with pytest.raises(whirl.InputError, match="keys separated by dots"):
        model.with_values({"roller_bearing[*": 1e-5})


def test_a_bad_value_by_path_gets_the_model_files_message():
    model = whirl.Model.from_file(REFERENCE)
    with pytest.raises(whirl.InputError, match=r"`roller_bearing\[\*\]\.rollers` = 0 makes an invalid model"):
        model.with_values({"roller_bearing[*].rollers": 0})


def test_errors_carry_the_command_lines_located_message(tmp_path, run_cli_failing):
    bad = tmp_path / "bad.toml"
    # A negative disk mass, on a line of its own, so the message is located.
    text = REFERENCE.read_text()
    marker = "mass = "
    i = text.index(marker, text.index("[[disk]]"))
    j = text.index("\n", i)
    bad.write_text(text[:i] + "mass = -1.0" + text[j:])
    with pytest.raises(whirl.InputError) as raised:
        whirl.Model.from_file(bad)
    message = str(raised.value)
    line = text[:i].count("\n") + 1
    assert message.startswith(f"{bad}:{line}:"), message
    assert "`disk[0].mass`" in message or "mass" in message
    # The command line says the same first line (it shows the help apart, under the snippet).
    stderr = run_cli_failing("check", str(bad))
    first = message.splitlines()[0]
    # miette wraps long lines and draws a frame; the words, in order, are what counts.
    words = [w for w in stderr.split() if w not in ("×", "│")]
    assert first in " ".join(words), (first, stderr)


def test_a_missing_file_is_a_whirl_error():
    with pytest.raises(whirl.WhirlError, match="cannot read the model file"):
        whirl.Model.from_file("no/such/model.toml")


def test_node_positions_span_the_shaft():
    model = whirl.Model.from_file(REFERENCE)
    z = model.node_positions()
    assert isinstance(z, np.ndarray) and z.dtype == np.float64
    assert len(z) == model.node_count
    assert z[0] == 0.0 and z[-1] == pytest.approx(model.length, rel=1e-12)
    assert np.all(np.diff(z) > 0)
