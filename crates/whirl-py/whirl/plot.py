"""The command line's figures drawn with matplotlib.

Each analysis's figures are defined once, in Rust (the crate whirl-figures): what series,
axes, marks and labels they have. A result hands them out as specifications
(``result.figure_spec("campbell")``), :func:`draw` draws one with matplotlib, and
``result.save_figures(folder)`` writes the command line's own PNG and SVG files. The
functions named as a command line figure (``campbell``, ``bode``, ...) draw its
specification; the others (``orbit``, ``spectrum``, ``hb_branch``, ...) are drawn here, with
options the command line does not have. Each takes a result (and optionally the Axes to draw
on) and returns the Axes.

    import whirl.plot
    whirl.plot.campbell(whirl.campbell("examples/reference_rotor.toml"))
"""

from __future__ import annotations

from typing import Any

import numpy as np

from . import _whirl


def _axes(ax: Any, **kwargs: Any) -> Any:
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    return plt.figure(**kwargs).add_subplot()


#: A specification's line kinds and markers as matplotlib's (markers: symbol, filled).
_LINES = {"solid": "-", "dashed": "--", "dotted": ":", "none": ""}
_MARKERS = {
    "none": ("", True),
    "circle": ("o", True),
    "open_circle": ("o", False),
    "triangle": ("^", True),
    "square": ("s", False),
    "cross": ("x", True),
}
_LEGEND = {
    "upper_right": "upper right",
    "upper_left": "upper left",
    "lower_left": "lower left",
    "lower_right": "lower right",
    "upper_middle": "upper center",
    "lower_middle": "lower center",
    "middle_right": "center right",
    "middle_left": "center left",
}
#: Pixels of the command line's 1000 x 700 figure per point of matplotlib's default
#: 6.4 x 4.8 in figure: line widths and marker sizes scaled alike.
_POINTS_PER_PIXEL = 0.6
#: Inches of a matplotlib figure per pixel of the command line's.
_INCHES_PER_PIXEL = 1 / 150


def draw(spec: dict[str, Any], ax: Any = None) -> Any:
    """Draws a figure specification (``result.figure_spec(name)``, or the ``figure`` of one)
    with matplotlib and returns its Axes: for panels (a grid), the first panel's; all of
    them are ``ax.figure.axes``. ``ax`` is the Axes to draw a single figure on (a sequence of
    Axes for panels); default a new figure of the command line's proportions."""
    figure = spec.get("figure", spec)
    kind = figure["kind"]
    if kind == "plot":
        ax = _axes(ax, figsize=_inches(figure["size"]))
        _draw_plot(figure, ax)
        return ax
    if kind == "heat_map":
        ax = _axes(ax, figsize=_inches(figure["size"]))
        _draw_heat_map(figure, ax)
        return ax
    draw_panel = {"grid": _draw_plot, "heat_map_grid": _draw_heat_map}[kind]
    axes = _panel_axes(figure, ax)
    for panel, panel_ax in zip(figure["panels"], axes):
        if panel is None:
            panel_ax.set_axis_off()
        else:
            draw_panel(panel, panel_ax)
    for unused in axes[len(figure["panels"]) :]:
        unused.set_axis_off()
    if figure["title"]:
        axes[0].figure.suptitle(figure["title"])
    return axes[0]


def _inches(size: list[int]) -> tuple[float, float]:
    return (size[0] * _INCHES_PER_PIXEL, size[1] * _INCHES_PER_PIXEL)


def _panel_axes(figure: dict[str, Any], ax: Any) -> list[Any]:
    if ax is not None:
        axes = list(np.ravel(ax))
        if len(axes) < len(figure["panels"]):
            raise ValueError(f"the figure has {len(figure['panels'])} panels: give as many Axes, not {len(axes)}")
        return axes
    import matplotlib.pyplot as plt

    _, axes = plt.subplots(figure["rows"], figure["cols"], squeeze=False, figsize=_inches(figure["size"]),
                           layout="constrained")
    return list(axes.flat)


def _series(ax: Any, series: dict[str, Any], index: int) -> None:
    style = series["style"]
    colour = style["colour"] or _whirl.PALETTE[index % len(_whirl.PALETTE)]
    marker, filled = _MARKERS[style["marker"]]
    ax.plot(
        series["x"],
        series["y"],
        linestyle=_LINES[style["line"]] or "none",
        marker=marker or None,
        color=colour,
        markerfacecolor=colour if filled else "none",
        linewidth=_POINTS_PER_PIXEL * style["line_width"],
        markersize=2 * _POINTS_PER_PIXEL * style["marker_size"],
        label=series["label"] if series["label"] is not None else "_nolegend_",
    )


def _legend(ax: Any, position: str) -> None:
    labelled = any(not h.get_label().startswith("_") for h in ax.get_legend_handles_labels()[0])
    if position != "hidden" and labelled:
        ax.legend(loc=_LEGEND[position], fontsize="small")


def _draw_plot(figure: dict[str, Any], ax: Any) -> None:
    for i, series in enumerate(figure["series"]):
        _series(ax, series, i)
    for line in figure["vertical_lines"]:
        ax.axvline(line["value"], color=line["colour"], ls="--", lw=0.8)
        if line["label"]:
            ax.annotate(line["label"], (line["value"], 1), xycoords=("data", "axes fraction"), rotation=90,
                        va="top", ha="right", fontsize="x-small", color=line["colour"])
    for line in figure["horizontal_lines"]:
        ax.axhline(line["value"], color=line["colour"], ls="--", lw=0.8)
        if line["label"]:
            ax.annotate(line["label"], (1, line["value"]), xycoords=("axes fraction", "data"), va="bottom",
                        ha="right", fontsize="x-small", color=line["colour"])
    for note in figure["annotations"]:
        if note["mark"]:
            ax.plot(note["x"], note["y"], "o", color="black", ms=3, label="_nolegend_")
        ax.annotate(note["text"], (note["x"], note["y"]), textcoords="offset points", xytext=(3, 3),
                    fontsize="x-small")
    if figure["log_x"]:
        ax.set_xscale("log")
    if figure["log_y"]:
        ax.set_yscale("log")
    if figure["x_range"] is not None:
        ax.set_xlim(*figure["x_range"])
    if figure["y_range"] is not None:
        ax.set_ylim(*figure["y_range"])
    if figure["equal_aspect"]:
        ax.set_aspect("equal", adjustable="datalim")
    ax.set(xlabel=figure["x_label"], ylabel=figure["y_label"], title=figure["title"])
    _legend(ax, figure["legend"])


def _draw_heat_map(figure: dict[str, Any], ax: Any) -> None:
    from matplotlib.colors import LogNorm, Normalize

    z = np.asarray(figure["z"], dtype=float).reshape(len(figure["y"]), len(figure["x"]))
    lo, hi = figure["z_range"] if figure["z_range"] is not None else (None, None)
    if figure["log_colour"]:
        z = np.ma.masked_less_equal(z, 0.0)
        norm = LogNorm(vmin=lo, vmax=hi)
    else:
        norm = Normalize(vmin=lo, vmax=hi)
    mesh = ax.pcolormesh(figure["x"], figure["y"], np.ma.masked_invalid(z), norm=norm, shading="nearest")
    ax.figure.colorbar(mesh, ax=ax, label=figure["colour_label"])
    for i, series in enumerate(figure["overlays"]):
        _series(ax, series, i)
    ax.set(xlabel=figure["x_label"], ylabel=figure["y_label"], title=figure["title"],
           xlim=(figure["x"][0], figure["x"][-1]), ylim=(figure["y"][0], figure["y"][-1]))
    _legend(ax, figure["legend"])


def _spec_drawer(name: str, what: str, function: str | None = None):
    """The function of :mod:`whirl.plot` (named ``function``, default ``name``) that draws a
    result's command line figure ``name``."""

    def drawn(result, ax=None):
        return draw(result.figure_spec(name), ax)

    drawn.__name__ = drawn.__qualname__ = function or name
    drawn.__doc__ = f"{what} (the command line's ``{name}`` figure, from its specification)."
    return drawn


def orbit(run, node=None, ax=None):
    """The settled orbit (uy over ux) of a node of a simulation (default the first)."""
    ax = _axes(ax)
    node = run.nodes[0] if node is None else node
    settled = run.time >= run.settle
    x, y = run.channel(f"n{node}.ux")[settled], run.channel(f"n{node}.uy")[settled]
    ax.plot(x, y)
    ax.set(xlabel="ux [m]", ylabel="uy [m]", title=f"orbit, node {node}", aspect="equal")
    return ax


#: A peak within this fraction of its channel's largest widens the spectrum to show it,
#: and at most this many orders are marked, as on the command line.
_SHOWN_PEAK_RELATIVE = 0.1
_MAX_ORDER_LINES = 12


def spectrum(run, channel=None, ax=None):
    """The library's amplitude spectrum of the settled part of a channel (default the second,
    the first node's uy), the command line's ``spectrum.csv``, over ten orders of the running
    speed or past the highest peak within a decade of its channel's largest; the orders
    (at most 12) marked."""
    ax = _axes(ax)
    name = run.names[1] if channel is None else channel
    table = run.columns("spectrum")
    frequency, amplitude = table["frequency_hz"], table[name]
    running = run.running_speed_hz
    peaks = run.columns("peaks")
    channels = np.asarray(peaks["channel"])
    peak_amplitude = peaks["amplitude_m"]
    largest = {c: peak_amplitude[channels == c].max() for c in set(channels)}
    shown = [f for c, f, a in zip(channels, peaks["frequency_hz"], peak_amplitude)
             if a >= _SHOWN_PEAK_RELATIVE * largest[c]]
    top = max(10.5 * running, 1.2 * max(shown, default=0.0))
    top = min(top, frequency[-1]) if top > 0 else frequency[-1]
    keep = frequency <= top
    ax.semilogy(frequency[keep], 1e6 * amplitude[keep])
    orders = min(int(top // running), _MAX_ORDER_LINES) if running > 0 else 0
    for k in range(1, orders + 1):
        ax.axvline(k * running, color="grey", lw=0.6, ls=":")
    ax.set(xlabel="frequency [Hz]", ylabel="amplitude, zero-to-peak [um]", xlim=(0, top),
           title=f"spectrum of {name} ({run.spectrum_window} window)")
    return ax


def _stable_runs(stable: list) -> list[tuple[int, int, bool]]:
    """(first, last + 1, stable) of each run of points of equal stability; a point whose
    stability was not computed counts as stable."""
    runs: list[tuple[int, int, bool]] = []
    for i, s in enumerate(stable):
        s = s not in (False, "false")
        if runs and runs[-1][2] == s:
            runs[-1] = (runs[-1][0], i + 1, s)
        else:
            # Each run starts at the last point of the one before, so the line is unbroken.
            runs.append((max(i - 1, 0), i + 1, s))
    return runs


def _initials(kind: str) -> str:
    """A bifurcation's kind by its initials, as the command line labels it: SB, NS, PD, F."""
    return "".join(word[0].upper() for word in kind.replace("-", " ").split())


def hb_branch(result, node=None, direction="uy", ax=None):
    """Harmonic balance (``whirl.hbm``): the amplitude of each harmonic of ``direction`` at
    ``node`` (default the first reported) along the branch over speed, in um over the four
    decades below the largest, stable solid and unstable dashed; a line where stability is
    lost, labelled by the bifurcation's initials (SB symmetry breaking, NS Neimark-Sacker,
    PD period doubling, F fold; `?` where not resolved at twice the samples)."""
    ax = _axes(ax)
    node = result.nodes[0] if node is None else node
    branch = result.columns("branch")
    speed, runs = branch["speed_hz"], _stable_runs(branch["stable"])
    top = 0.0
    for r in range(1, result.harmonics + 1):
        y = 1e6 * branch[f"n{node}_{direction}_{r}x_m"]
        top = max(top, float(np.nanmax(y)))
        line = None
        for a, b, stable in runs:
            kwargs = {"color": line.get_color()} if line is not None else {"label": f"{r}X"}
            (drawn,) = ax.semilogy(speed[a:b], y[a:b], "-" if stable else "--", **kwargs)
            line = line or drawn
    lost = [b for b in result.bifurcations if b["loses_stability"]]
    for i, b in enumerate(lost):
        ax.axvline(b["speed_hz"], color="grey", lw=0.8, ls="--")
        label = _initials(b["kind"]) + ("?" if b.get("resolved") is False else "")
        # Staggered down the top edge, so that labels of close speeds do not overlap.
        ax.annotate(label, (b["speed_hz"], 0.97 - 0.06 * (i % 4)), xycoords=("data", "axes fraction"),
                    ha="left", va="top", fontsize="small", color="dimgrey")
    if top > 0:
        ax.set_ylim(1e-4 * top, 3 * top)
    ax.set(xlabel="speed [Hz]", ylabel=f"{direction} amplitude [um]",
           title=f"harmonic balance, node {node} (dashed: unstable)")
    ax.legend(fontsize="small", loc="lower right")
    return ax


def frf(result, kind="receptance", ax=None):
    """Frequency response functions (``whirl.frf``): the command line's figure of ``kind``
    (receptance, mobility or accelerance), magnitude, phase, real and imaginary parts of
    each output over frequency, from its specification."""
    return draw(result.figure_spec(kind), ax)


def stiffness(result, entry="kyy", ax=None):
    """Roller bearing stiffness (``whirl.stiffness``): ``entry`` (kxx, kxy, kyx or kyy) of
    the frozen, passage-averaged (its spread shaded) and fixed-displacement stiffness over
    the clearance, MN/m."""
    ax = _axes(ax)
    t = result.columns("stiffness")
    c = t["clearance_um"]
    for kind, style in (("frozen", "o-"), ("averaged", "s-"), ("fixed", "^-")):
        ax.plot(c, 1e-6 * t[f"{kind}_{entry}_n_per_m"], style, ms=3, label=kind)
    if entry in ("kxx", "kyy"):
        low, high = t[f"averaged_{entry}_min_n_per_m"], t[f"averaged_{entry}_max_n_per_m"]
        ax.fill_between(c, 1e-6 * low, 1e-6 * high, alpha=0.2, label="passage spread")
    ax.set(xlabel="clearance [um]", ylabel=f"{entry} [MN/m]",
           title=f"stiffness of {result.bearing['name']} versus clearance")
    ax.legend(fontsize="small")
    return ax


def force_surface(result, clearance=None, component="fr", ax=None):
    """A force-deflection surface (``whirl.stiffness``): the command line's heat map of
    ``component`` (fx, fy or fr, N) over the journal displacement at ``clearance`` (a table's
    label such as ``"20um"``; default the first surface), from its specification."""
    names = [n for n in result.tables if n.startswith("surfaces_")]
    label = names[0].removeprefix("surfaces_") if clearance is None else clearance
    return draw(result.figure_spec(f"surface_{label}_{component}"), ax)


campbell = _spec_drawer(
    "campbell",
    "The Campbell diagram: whirl frequencies over speed (forward solid, backward dashed), the excitation orders, the first roller bearing's characteristic frequencies and the critical speeds",
)
log_decrement = _spec_drawer(
    "log_decrement",
    "The logarithmic decrement of each whirl branch over speed, with API 617's minimum of 0.1",
)
bode = _spec_drawer(
    "bode",
    "The unbalance response's Bode plot: the amplitude of ux (solid) and uy (dashed) at each node over speed, log scale, above their unwrapped phase",
)
orbit_major = _spec_drawer(
    "orbit_major",
    "The unbalance response's orbit size over speed at each node, each peak labelled with its speed and amplification factor",
)
polar = _spec_drawer(
    "polar",
    "The unbalance response of ux at each node in the complex plane, peaks labelled with their speed",
)
waterfall = _spec_drawer(
    "waterfall",
    "A cascade's spectra stacked along speed, with the order lines and the first roller bearing's characteristic frequencies",
)
cascade_map = _spec_drawer(
    "cascade_map",
    "A cascade's map: frequency over speed, colour the log amplitude, the order and bearing lines and the NSV peaks at or above the threshold",
)
nsv = _spec_drawer(
    "nsv",
    "A cascade's 1X and largest non-synchronous amplitude over speed, with the threshold",
)
starts = _spec_drawer(
    "starts",
    "A cascade's NSV from both starts over speed (``compare_starts=True``)",
)
reduction_error = _spec_drawer(
    "reduction_error",
    "Craig-Bampton (``whirl.reduce``): each mode's relative frequency error over the number of modes",
)
static_response = _spec_drawer(
    "static_response",
    "The static response (``whirl.static``): the deflected rotor and the bearing reactions",
)
ucs = _spec_drawer(
    "ucs",
    "The undamped critical-speed map (``whirl.ucs``): each critical speed over the bearing stiffness",
)
convergence = _spec_drawer(
    "convergence",
    "Each natural frequency over the number of elements (``whirl.convergence``), one panel per mode",
)
mode_shapes = _spec_drawer(
    "mode_shapes",
    "The undamped mode shapes (``whirl.modal``), one panel per mode",
)
rotor = _spec_drawer(
    "rotor",
    "The rotor's layout (``whirl.check``): shaft, nodes, disks and bearings",
)
hb_stability = _spec_drawer(
    "stability",
    "Harmonic balance: the largest real part of the Floquet exponents along the branch (above zero: unstable)",
    "hb_stability",
)
fit_forcing = _spec_drawer(
    "force_deflection",
    "The forcing-function fit (``whirl.fit_forcing``): the contact force over the deflection beyond the clearance, log-log, samples and fit per speed",
    "fit_forcing",
)
