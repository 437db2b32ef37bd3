"""The figures draw (Agg backend) from real results, with the lines they promise."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

import whirl  # noqa: E402
import whirl.plot  # noqa: E402
from conftest import REFERENCE  # noqa: E402


def test_every_figure_draws(tmp_path):
    model = whirl.Model.from_file(REFERENCE)
    diagram = whirl.campbell(model, "0:400Hz:21", modes=4)
    response = whirl.unbalance(model, "1:100Hz:40", nodes=[10])
    run = whirl.simulate(model, "50Hz", duration="0.4s", reduce=12, nodes=[10], progress=False)
    cascade = whirl.cascade(
        model, "100Hz:300Hz:4", no_refine=True, max_records=1, compare_starts=True, progress=False
    )
    # The command line's figures in its order: the two starts' first, when compared.
    assert cascade.figures == ("starts", "waterfall", "cascade_map", "nsv")
    branch = whirl.hbm(model, "1:60Hz", harmonics=2, progress=False)
    reduced = whirl.reduce(model)
    axes = [
        whirl.plot.campbell(diagram),
        whirl.plot.bode(response),
        whirl.plot.polar(response),
        whirl.plot.orbit(run),
        whirl.plot.spectrum(run),
        whirl.plot.waterfall(cascade),
        whirl.plot.cascade_map(cascade),
        whirl.plot.nsv(cascade),
        whirl.plot.starts(cascade),
        whirl.plot.hb_branch(branch),
        whirl.plot.hb_stability(branch),
        whirl.plot.reduction_error(reduced),
        whirl.plot.static_response(whirl.static(model)),
        whirl.plot.ucs(whirl.ucs(model)),
        whirl.plot.frf(whirl.frf(model, "10:uy", frequencies="0:400Hz:101")),
        whirl.plot.orbit_major(response),
    ]
    bearing = whirl.stiffness(model, clearances="10um:60um:3", cage_steps=2, grid=5)
    axes += [whirl.plot.stiffness(bearing), whirl.plot.force_surface(bearing, "60um")]
    for i, ax in enumerate(axes):
        assert ax.lines or ax.collections, f"figure {i} drew nothing"
        ax.figure.savefig(tmp_path / f"{i}.png")
    # The Campbell figure has a line per branch and per order.
    assert len(axes[0].lines) >= len(diagram.branches) + len(diagram.orders)
    np.testing.assert_array_equal(axes[0].lines[0].get_xdata(), diagram.speeds_hz)
    # The branch figure has a line per harmonic and stability run: solid and dashed both
    # (the branch loses stability in the first resonance).
    styles = {line.get_linestyle() for line in axes[9].lines}
    assert {"-", "--"} <= styles, styles
    # The spectrum is the library's (spectrum.csv), over ten orders of the 50 Hz running
    # speed rather than up to the sampling's Nyquist frequency (15.4 kHz).
    assert axes[4].get_xlim()[1] == pytest.approx(525.0)
    np.testing.assert_array_equal(
        axes[4].lines[0].get_xdata(), run.columns("spectrum")["frequency_hz"][: len(axes[4].lines[0].get_xdata())]
    )
    # The cascade map has the bearing's lines (BPFO = N_b w_c among them) and the NSV peaks.
    labels = [line.get_label() for line in axes[6].lines]
    assert "BPFO = N_b w_c" in labels, labels
    assert "NSV >= threshold" in labels
    # The waterfall the same lines, frequency over speed.
    assert [line.get_label() for line in axes[5].lines if not line.get_label().startswith("_")] == labels[:-1]
    # The Bode plot has the amplitude above the phase, ux and uy of each node in both (and
    # the operating speed range's two lines).
    amplitude, phase = axes[1].figure.axes
    assert len(amplitude.lines) == len(phase.lines) == 2 * len(response.nodes) + 2
    assert phase.get_ylabel() == "Phase [deg]"
    # Its bifurcations where stability is lost, labelled by initials as the command line
    # does (whole names of close speeds ran into each other).
    labels = [t.get_text().rstrip("?") for t in axes[9].texts]
    assert len(labels) == sum(b["loses_stability"] for b in branch.bifurcations) > 0
    assert set(labels) <= {"SB", "NS", "PD", "F"}, labels
