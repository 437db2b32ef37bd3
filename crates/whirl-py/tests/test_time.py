"""A simulation from Python against the command line's, digit for digit."""

from __future__ import annotations

import numpy as np
import pytest

import whirl
from conftest import REFERENCE, assert_same_table


def test_simulate_equals_the_command_line(run_cli):
    args = ["--speed", "50Hz", "--duration", "0.3s", "--reduce", "12", "--nodes", "10"]
    cli = run_cli("simulate", str(REFERENCE), *args)
    result = whirl.simulate(REFERENCE, "50Hz", duration="0.3s", reduce=12, nodes=[10], progress=False)
    assert result.status == {"status": "completed"}
    # The roller bearings' nodes are recorded too, with a contact law.
    assert result.names[:2] == ["n10.ux", "n10.uy"] and len(result.names) > 2
    assert_same_table(result.to_pandas(), cli.table("time_history"))
    summary = cli.summary()
    assert (result.step, result.contact) == (summary["step_s"], summary["contact"])


def test_a_linear_rotor_settles_to_its_unbalance_response():
    model = whirl.Model.from_file(REFERENCE)
    run = whirl.simulate(model, "20Hz", duration="2s", contact="linear", nodes=[10], progress=False)
    steady = whirl.unbalance(model, np.array([2 * np.pi * 20.0]), nodes=[10])
    # On linear bearings the settled orbit is the harmonic unbalance response: its vertical
    # amplitude (half the peak-to-peak over the last 0.5 s, whole turns at 20 Hz) equals the
    # frequency-domain one to the decay of the start (e^(-zeta w t) after 1.5 s: below 1 %).
    y = run.channel("n10.uy")[run.time >= 1.5]
    amplitude = 0.5 * (y.max() - y.min())
    assert amplitude == pytest.approx(steady.node(10).uy_amplitude[0], rel=0.01)


def test_a_step_above_the_stability_limit_is_refused():
    with pytest.raises(whirl.InputError, match="step"):
        whirl.simulate(REFERENCE, "50Hz", duration="0.1s", step="1ms", progress=False)
