"""A simulation from Python against the command line's, digit for digit."""

from __future__ import annotations

import numpy as np
import pytest

import whirl
from conftest import REFERENCE, assert_same_table, timeless


def test_simulate_equals_the_command_line(run_cli):
    args = ["--speed", "50Hz", "--duration", "0.3s", "--reduce", "12", "--nodes", "10"]
    cli = run_cli("simulate", str(REFERENCE), *args)
    result = whirl.simulate(REFERENCE, "50Hz", duration="0.3s", reduce=12, nodes=[10], progress=False)
    assert result.status == "completed"
    # The roller bearings' nodes are recorded too, with a contact law, and each has its
    # table of roller contacts.
    assert result.names[:2] == ["n10.ux", "n10.uy"] and len(result.names) > 2
    assert result.tables[:3] == ("time_history", "spectrum", "peaks")
    assert [t for t in result.tables if t.startswith("contacts_")] == ["contacts_bearing_a",
                                                                      "contacts_bearing_b"]
    assert timeless(result.to_dict()) == timeless(cli.summary())
    for table in result.tables:
        assert_same_table(result.to_pandas(table), cli.table(table))
    assert result.to_pandas("contacts_bearing_a")["in_contact"].dtype == np.int64
    np.testing.assert_array_equal(result.to_pandas()["n10.uy"], result.channel("n10.uy"))


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


@pytest.mark.parametrize(
    ("options", "named"),
    [
        ({"hht_alpha": -0.1}, "invalid `hht_alpha`: applies to the newmark method only"),
        ({"method": "newmark", "hht_alpha": -0.5}, r"invalid `hht_alpha`: -0.5 is outside \[-1/3, 0\]"),
        ({"settle": "0.1s"}, "invalid `settle`: the settling time 0.1 s is not shorter"),
        ({"ramp_to": "60Hz", "settle": 0}, "invalid `ramp_to`"),
        ({"nodes": [99]}, "invalid `nodes`"),
    ],
)
def test_bad_settings_are_named_by_their_keyword(options, named):
    # The library checks each setting once and names it; Python shows the keyword (the
    # command line shows the same check as its flag).
    with pytest.raises(whirl.InputError, match=named):
        whirl.simulate(REFERENCE, "50Hz", duration="0.1s", progress=False, **options)
