"""check and campbell from Python against the command line's own outputs, digit for digit,
and against the physics they must hold."""

from __future__ import annotations

import numpy as np
import pytest

import whirl
from conftest import REFERENCE, assert_matches_cli


def test_check_equals_the_command_line(run_cli):
    cli = run_cli("check", str(REFERENCE))
    assert_matches_cli(whirl.check(whirl.Model.from_file(REFERENCE)), cli)


def test_campbell_equals_the_command_line(run_cli):
    cli = run_cli("campbell", str(REFERENCE), "--speeds", "0:800Hz:41", "--orders", "1,2")
    assert_matches_cli(whirl.campbell(REFERENCE, "0:800Hz:41", orders=[1, 2]), cli)


def test_campbell_default_speeds_are_the_command_lines(run_cli):
    cli = run_cli("campbell", str(REFERENCE), "--modes", "4")
    diagram = whirl.campbell(whirl.Model.from_file(REFERENCE), modes=4)
    assert diagram.to_dict() == cli.summary()


def test_campbell_at_rest_starts_from_the_undamped_frequencies():
    model = whirl.Model.from_file(REFERENCE)
    f0 = whirl.check(model).frequencies_hz
    diagram = whirl.campbell(model, np.array([0.0, 10.0]), modes=4, full=True)
    branches = sorted(diagram.branches, key=lambda b: b.frequency_hz[0])
    wd = np.array([b.frequency_hz[0] for b in branches])
    zeta = np.array([b.damping_ratio[0] for b in branches])
    # At rest the gyroscopic coupling vanishes: each undamped frequency (itself a pair, x
    # and y) is a forward and a backward branch at once, and w_d / sqrt(1 - zeta^2) is the
    # undamped frequency. The bearings' damping is not proportional, which moves the
    # natural frequencies at second order in zeta (zeta^2 = 4e-4 here): within 1e-4.
    assert zeta.min() > 0.01
    np.testing.assert_allclose(wd / np.sqrt(1 - zeta**2), f0[:4], rtol=1e-4)


def test_speeds_in_rpm_and_rad_per_s_agree():
    model = whirl.Model.from_file(REFERENCE)
    a = whirl.campbell(model, "0:6000rpm:5", modes=2)
    b = whirl.campbell(model, np.linspace(0, 2 * np.pi * 100, 5), modes=2)
    np.testing.assert_allclose(a.speeds_hz, b.speeds_hz, rtol=1e-14)
    np.testing.assert_allclose(a.branches[0].frequency_hz, b.branches[0].frequency_hz, rtol=1e-12)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"modes": 0}, "invalid `modes`"),
        ({"orders": [0]}, "invalid `orders`"),
        ({"speeds": "0:800:x"}, "invalid `speeds`"),
        ({"speeds": [10.0, 5.0]}, "ascending"),
    ],
)
def test_bad_options_are_input_errors(options, message):
    with pytest.raises(whirl.InputError, match=message):
        whirl.campbell(REFERENCE, **options)


def test_convergence_equals_the_command_line(run_cli):
    cli = run_cli("convergence", str(REFERENCE), "--counts", "2,5,10,20,40", "--modes", "4")
    assert_matches_cli(whirl.convergence(REFERENCE, [2, 5, 10, 20, 40], modes=4), cli)


def test_convergence_counts_are_checked_by_the_library():
    # The range and its reason come from the library, named as the keyword.
    with pytest.raises(whirl.InputError, match=r"invalid `counts`: 10001 elements.*from 1 to 10000"):
        whirl.convergence(REFERENCE, [20, 10001])
    with pytest.raises(whirl.InputError, match=r"invalid `counts`: `-3` is not a whole number"):
        whirl.convergence(REFERENCE, [-3])


def test_convergence_frequencies_settle_as_the_mesh_is_refined():
    result = whirl.convergence(REFERENCE, [10, 20, 40], modes=2)
    # Cubic beam elements converge fast: the first frequency moves by less than 1e-3 from
    # 20 to 40 elements, and each refinement changes it less than the one before.
    change = result.relative_change[:, 0]
    assert change[2] < 1e-3
    assert change[2] < change[1]


def test_modal_equals_the_command_line(run_cli):
    cli = run_cli("modal", str(REFERENCE), "--speed", "300Hz", "--modes", "6")
    assert_matches_cli(whirl.modal(REFERENCE, "300Hz", modes=6), cli)


def test_modes_come_in_pairs_on_isotropic_bearings():
    result = whirl.modal(REFERENCE, 0.0, modes=4)
    # Each undamped frequency is a pair (x and y) on the isotropic bearings, and at rest the
    # damped forward and backward modes of a pair split by less than 1e-6 relative (the
    # 1e-3 rad/s floor's gyroscopic effect).
    f = result.undamped_frequencies_hz
    np.testing.assert_allclose(f[0], f[1], rtol=1e-9)
    d = [m["damped_frequency_hz"] for m in result.damped]
    np.testing.assert_allclose(d[0], d[1], rtol=1e-6)


def test_an_explicit_speed_array_has_the_ranges_cap():
    # A 10-million array ran on for minutes where the range string is refused above
    # 100,000 values; the library checks the count before any solve.
    speeds = np.linspace(1.0, 5000.0, 100_001)
    with pytest.raises(whirl.InputError, match="at most 100000"):
        whirl.campbell(REFERENCE, speeds, modes=2)


@pytest.mark.parametrize(
    "call",
    [
        "whirl.campbell(REFERENCE, '0:750Hz:100000')",
        "whirl.unbalance(REFERENCE, '1:750Hz:100000')",
    ],
)
def test_ctrl_c_stops_a_long_linear_analysis(call):
    # 100,000 speeds take minutes (a Campbell diagram 373 s, the unbalance response 51 s
    # before they listened); Ctrl-C must end them within a poll and a speed or two.
    import signal
    import subprocess
    import sys
    import time

    script = f"import whirl\nREFERENCE = {str(REFERENCE)!r}\nprint('started', flush=True)\n{call}\n"
    child = subprocess.Popen(
        [sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    assert child.stdout.readline().strip() == "started"
    time.sleep(1.5)
    asked = time.monotonic()
    child.send_signal(signal.SIGINT)
    _, err = child.communicate(timeout=60)
    took = time.monotonic() - asked
    assert child.returncode != 0
    assert "KeyboardInterrupt" in err, err[-2000:]
    assert took < 20, f"stopped {took:.1f} s after Ctrl-C"


def test_the_modes_are_read_from_the_librarys_tables_in_their_layout():
    # The result is read off the report's tables (the numbers cross from Rust once): the
    # undamped shapes as [dof, mode] with the DOFs node by node, and each damped mode's
    # orbit per node scaled so that its largest translation is 1.
    result = whirl.modal(REFERENCE, "300Hz", modes=4)
    nodes = result.model.node_count
    assert result.undamped_shapes.shape == (4 * nodes, 4)
    table = result.to_pandas("undamped_shapes")
    second = table[table["mode"] == 2]
    np.testing.assert_array_equal(result.undamped_shapes[1::4, 1], second["uy"].to_numpy())
    for mode in result.damped:
        assert len(mode["ux_amplitude"]) == nodes
        largest = max(mode["ux_amplitude"].max(), mode["uy_amplitude"].max())
        assert abs(largest - 1.0) < 1e-12, mode["label"]
