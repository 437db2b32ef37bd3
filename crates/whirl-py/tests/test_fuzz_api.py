"""The Python API fed what a new user's mistakes (and worse) give it: wrong types, NaN and
infinity, None, unknown keys, huge lists. Each call must either answer with finite
numbers or raise one of whirl's errors (or TypeError/ValueError for a Python value of the
wrong kind) with a message; never crash, hang or answer with NaN, inf or a 0 Hz mode."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest

import whirl
from conftest import REFERENCE

EXPECTED = (whirl.WhirlError, TypeError, ValueError)

# Values that broke parsers and solvers elsewhere: wrong types, non-numbers, extremes.
VALUES = [None, float("nan"), float("inf"), -1.0, 0, 1e308, "abc", "20 parsecs", [], {}, True,
          [1.0] * 1000, "1e999", -0.0, 2**70]


def _mutants(seed: int, count: int):
    """Model dicts: the reference rotor with one value replaced, or an unknown key added."""
    rng = random.Random(seed)
    base = _reference_tables()
    leaves = []

    def walk(node, path):
        if isinstance(node, dict):
            for k, v in node.items():
                walk(v, path + [k])
        elif isinstance(node, list):
            for i, v in enumerate(node):
                walk(v, path + [i])
        else:
            leaves.append(path)

    walk(base, [])
    for _ in range(count):
        tables = _reference_tables()
        path = rng.choice(leaves)
        node = tables
        for key in path[:-1]:
            node = node[key]
        if rng.random() < 0.2:
            node["no_such_key"] = 1.0
        else:
            node[path[-1]] = rng.choice(VALUES)
        yield tables


def _outcome(call):
    try:
        result = call()
    except EXPECTED as e:
        assert str(e).strip(), f"{type(e).__name__} without a message"
        return type(e).__name__
    return result


def test_mutated_model_dicts_are_answered_or_refused_with_a_reason():
    outcomes: dict[str, int] = {}
    for tables in _mutants(seed=34, count=120):
        model = _outcome(lambda: whirl.Model.from_dict(tables))
        if isinstance(model, str):
            outcomes[model] = outcomes.get(model, 0) + 1
            continue
        checked = _outcome(lambda: whirl.check(model))
        if isinstance(checked, str):
            outcomes["check: " + checked] = outcomes.get("check: " + checked, 0) + 1
            continue
        frequencies = checked.to_dict()["undamped_frequencies_hz"]
        assert all(math.isfinite(f) for f in frequencies), frequencies
        assert frequencies[0] >= 0.1, f"a rigid-body mode answered as a frequency: {frequencies}"
        outcomes["accepted"] = outcomes.get("accepted", 0) + 1
    print("from_dict/check outcomes:", outcomes)
    assert outcomes.get("accepted", 0) > 0 and len(outcomes) > 1


def _reference_tables():
    """The reference rotor as the dict of its model file's tables."""
    import tomllib

    return tomllib.loads(REFERENCE.read_text())


def test_nan_and_inf_in_from_dict_name_their_key():
    tables = _reference_tables()
    for bad in (float("nan"), float("inf")):
        tables["disk"][0]["mass"] = bad
        with pytest.raises(whirl.InputError, match=r"`disk\[0\]\.mass`"):
            whirl.Model.from_dict(tables)


@pytest.mark.parametrize(
    "speeds",
    [
        "abc",
        [float("nan"), 10.0],
        [float("inf")],
        [-5.0, 10.0],
        [30.0, 10.0],
        [],
        np.linspace(1.0, 100.0, 100_001),
        "1:750Hz:10000000000",
        {"a": 1},
    ],
)
def test_bad_speed_lists_are_refused_with_a_reason(speeds):
    outcome = _outcome(lambda: whirl.campbell(REFERENCE, speeds, modes=2))
    assert isinstance(outcome, str), f"{speeds!r} was answered"


# None is no mistake: it asks for the library's default, as every option's None does.
@pytest.mark.parametrize("modes", [0, -1, 10**9, "six", 2.5, float("nan")])
def test_bad_mode_counts_are_refused_with_a_reason(modes):
    outcome = _outcome(lambda: whirl.modal(REFERENCE, 0.0, modes=modes))
    assert isinstance(outcome, str), f"modes={modes!r} was answered"
