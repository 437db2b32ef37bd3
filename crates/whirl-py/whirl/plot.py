"""The command line's figures drawn with matplotlib from the result objects: each function
takes a result (and optionally the Axes to draw on) and returns the Axes.

    import whirl.plot
    whirl.plot.campbell(whirl.campbell("examples/reference_rotor.toml"))
"""

from __future__ import annotations

from typing import Any

import numpy as np


def _axes(ax: Any, **kwargs: Any) -> Any:
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    return plt.figure(**kwargs).add_subplot()


def campbell(diagram, ax=None):
    """Whirl frequencies over speed (forward solid, backward dashed), the excitation orders
    and the critical speeds."""
    ax = _axes(ax)
    for b in diagram.branches:
        style = "--" if b.whirl == "backward" else "-"
        ax.plot(diagram.speeds_hz, b.frequency_hz, style, label=b.label)
    for k in diagram.orders:
        ax.plot(diagram.speeds_hz, k * diagram.speeds_hz, ":", color="grey", label=f"{k:g}X")
    for c in diagram.critical_speeds:
        ax.plot(c.speed_hz, c.frequency_hz, "o", color="black")
    top = max(np.nanmax(b.frequency_hz) for b in diagram.branches) if diagram.branches else 1.0
    ax.set(xlabel="speed [Hz]", ylabel="frequency [Hz]", ylim=(0, 1.1 * top), title="Campbell diagram")
    ax.legend(fontsize="small", ncol=2)
    return ax


#: API 617's least logarithmic decrement of a mode.
_API_617_LOG_DECREMENT = 0.1


def log_decrement(diagram, ax=None):
    """The logarithmic decrement of each whirl branch of a Campbell diagram over speed
    (forward solid, backward dashed), with API 617's minimum of 0.1."""
    ax = _axes(ax)
    for b in diagram.branches:
        ax.plot(diagram.speeds_hz, b.log_decrement, "--" if b.whirl == "backward" else "-", label=b.label)
    ax.axhline(_API_617_LOG_DECREMENT, color="grey", lw=0.8, label="API 617 minimum")
    ax.set(xlabel="speed [Hz]", ylabel="log decrement [-]", title="logarithmic decrement of the whirl branches")
    ax.legend(fontsize="small", ncol=2)
    return ax


def bode(response, ax=None):
    """Unbalance response as the command line's Bode plot: the amplitude of ux (solid) and
    uy (dashed) at each reported node over speed, um on a log scale, above their phase,
    unwrapped, degrees. ``ax`` is the pair of Axes (amplitude, phase) to draw on, or one
    Axes for the amplitude alone; returns the amplitude's Axes."""
    if ax is None:
        import matplotlib.pyplot as plt

        _, (amplitude, phase) = plt.subplots(2, 1, sharex=True, figsize=(6.4, 6.4))
    elif isinstance(ax, (tuple, list)):
        amplitude, phase = ax
    else:
        amplitude, phase = ax, None
    for r in response.nodes:
        (line,) = amplitude.semilogy(response.speeds_hz, 1e6 * r.ux_amplitude, label=f"node {r.node} ux")
        amplitude.semilogy(response.speeds_hz, 1e6 * r.uy_amplitude, "--", color=line.get_color(),
                           label=f"node {r.node} uy")
        if phase is not None:
            for values, style in ((r.ux_phase_deg, "-"), (r.uy_phase_deg, "--")):
                unwrapped = np.degrees(np.unwrap(np.radians(values)))
                phase.plot(response.speeds_hz, unwrapped, style, color=line.get_color())
    amplitude.set(ylabel="amplitude [um]", title="unbalance response")
    amplitude.legend(fontsize="small")
    if phase is not None:
        phase.set(xlabel="speed [Hz]", ylabel="phase [deg]")
    else:
        amplitude.set(xlabel="speed [Hz]")
    return amplitude


def orbit_major(response, ax=None):
    """Unbalance response: the orbit's major semi-axis over speed at each reported node
    (um, log scale), each peak marked and labelled with its speed."""
    ax = _axes(ax)
    for r in response.nodes:
        ax.semilogy(response.speeds_hz, 1e6 * r.major, label=f"node {r.node}")
        for p in r.peaks:
            ax.plot(p.speed_hz, 1e6 * p.amplitude, "v", color="black")
            ax.annotate(f"{p.speed_hz:.1f} Hz", (p.speed_hz, 1e6 * p.amplitude), fontsize="small",
                        textcoords="offset points", xytext=(3, 3))
    ax.set(xlabel="speed [Hz]", ylabel="major semi-axis [um]", title="unbalance response: orbit size")
    ax.legend(fontsize="small")
    return ax


def polar(response, node=None, ax=None):
    """Unbalance response of ux at a node (default the first) in the complex plane."""
    import matplotlib.pyplot as plt

    r = response.nodes[0] if node is None else response.node(node)
    if ax is None:
        ax = plt.figure().add_subplot(projection="polar")
    ax.plot(np.radians(r.ux_phase_deg), r.ux_amplitude)
    ax.set_title(f"polar plot, node {r.node} ux")
    return ax


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


#: The roller bearings' characteristic frequencies, as the summary's ``bearing_orders``
#: name them, and as the figures label them.
_BEARING_LINES = (("ftf", "FTF"), ("bpfo", "BPFO = N_b w_c"), ("bpfi", "BPFI"), ("bsf", "BSF"))


def _order_lines(cascade) -> list[tuple[str, float]]:
    """The orders drawn over a cascade, as the command line draws them: 0.5X, 1X and 2X, and
    the first roller bearing's characteristic frequencies."""
    lines = [(f"{k:g}X", k) for k in (0.5, 1.0, 2.0)]
    for bearing in cascade.to_dict()["bearing_orders"][:1]:
        lines += [(f"{name}, {bearing['bearing']}", bearing["orders"][key]) for key, name in _BEARING_LINES]
    return lines


def waterfall(cascade, ax=None):
    """Every speed's spectrum, offset by its speed and rising by its log amplitude over the
    four decades below the largest (the cascade's waterfall), with the order lines and the
    first roller bearing's characteristic frequencies dashed."""
    ax = _axes(ax)
    speeds = cascade.speeds_hz
    floor = (np.nanmax(cascade.amplitude) or 1.0) * 1e-4
    step = np.median(np.diff(speeds)) if len(speeds) > 1 else 1.0
    for speed, a in zip(speeds, cascade.amplitude):
        rise = np.log10(np.maximum(a, floor) / floor) / 4
        ax.plot(cascade.frequency_hz, speed + 3 * step * rise, color="black", lw=0.5)
    for name, order in _order_lines(cascade):
        ax.plot(order * speeds, speeds, "--", lw=0.8, label=name)
    ax.set(xlabel="frequency [Hz]", ylabel="speed [Hz] (trace: log amplitude)", title="cascade",
           xlim=(0, cascade.frequency_hz[-1]))
    ax.legend(fontsize="small", loc="lower right")
    return ax


def cascade_map(cascade, ax=None, max_frequency_hz=None):
    """Frequency over speed, colour the log amplitude over four decades, as the command
    line's map: the 0.5X, 1X and 2X lines and the first roller bearing's characteristic
    frequencies (FTF, BPFO = N_b w_c, BPFI, BSF) dashed, and the steady NSV peaks at or
    above the threshold circled."""
    ax = _axes(ax)
    speeds = cascade.speeds_hz
    top = max_frequency_hz or 2 * speeds.max()
    keep = cascade.frequency_hz <= top
    level = np.log10(np.maximum(cascade.amplitude[:, keep].T, 1e-300))
    # Four decades below the largest amplitude, as the command line's map.
    ax.pcolormesh(speeds, cascade.frequency_hz[keep], level, shading="nearest",
                  vmin=level.max() - 4, vmax=level.max())
    for name, order in _order_lines(cascade):
        ax.plot(speeds, order * speeds, "--", lw=0.8, label=name)
    threshold = cascade.to_dict()["nsv"]["threshold_m"]
    peaks = [
        (n["speed_hz"], n["peak"]["frequency_hz"])
        for n in cascade.nsv
        if n is not None and n["class"] != "unsettled" and n["peak"]["amplitude_m"] >= threshold
    ]
    if peaks:
        ax.plot(*zip(*peaks), "o", mfc="none", mec="white", ms=5, label="NSV >= threshold")
    ax.set(xlabel="speed [Hz]", ylabel="frequency [Hz]", ylim=(0, top), title="cascade map (log amplitude)")
    ax.legend(fontsize="small", loc="upper left")
    return ax


def nsv(cascade, ax=None):
    """1X and the NSV amplitude over speed, the NSV by class, added speeds circled."""
    ax = _axes(ax)
    one_x = [p["one_x_m"] for p in cascade.points]
    ax.semilogy(cascade.speeds_hz, one_x, color="grey", label="1X")
    classes: dict[str, list[tuple[float, float]]] = {}
    for p, n in zip(cascade.points, cascade.nsv):
        if n is not None:
            classes.setdefault(n["class"], []).append((p["speed_hz"], n["peak"]["amplitude_m"]))
    for name, points in sorted(classes.items()):
        s, a = zip(*points)
        ax.semilogy(s, a, "o", ms=3, label=name)
    added = [(p["speed_hz"], n["peak"]["amplitude_m"]) for p, n in zip(cascade.points, cascade.nsv) if p["added"] and n]
    if added:
        s, a = zip(*added)
        ax.plot(s, a, "o", mfc="none", mec="black", ms=7, label="added speed")
    ax.set(xlabel="speed [Hz]", ylabel="amplitude [m]", title="NSV by class")
    ax.legend(fontsize="small")
    return ax


def starts(cascade, ax=None):
    """The NSV from both starts over speed (``compare_starts=True``), the speeds where they
    differ (coexisting motions) circled."""
    compared = cascade.to_dict().get("starts")
    if compared is None:
        raise ValueError("the cascade has no second start: run it with compare_starts=True")
    ax = _axes(ax)
    t = cascade.to_pandas("starts")
    other = compared["other_start"]
    ax.semilogy(t["speed_hz"], t["nsv_m"], "o-", ms=3, label="first start")
    ax.semilogy(t["speed_hz"], t["other_start_nsv_m"], "s--", ms=3, label=f"from {other}")
    differ = t[t["differs"] == 1]
    ax.plot(differ["speed_hz"], differ["nsv_m"], "o", mfc="none", mec="red", ms=9, label="differ")
    ax.set(xlabel="speed [Hz]", ylabel="NSV amplitude [m]", title="NSV from both starts")
    ax.legend(fontsize="small")
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


def hb_stability(result, ax=None):
    """Harmonic balance: the largest real part of the Floquet exponents along the branch
    (above zero: unstable)."""
    ax = _axes(ax)
    branch = result.columns("branch")
    ax.plot(branch["speed_hz"], branch["max_real_exponent_per_s"])
    ax.axhline(0.0, color="grey", lw=0.8)
    ax.set(xlabel="speed [Hz]", ylabel="largest real part [1/s]", title="Floquet stability")
    return ax


def reduction_error(result, modes=4, ax=None):
    """Craig-Bampton (``whirl.reduce``): the relative error of the first ``modes`` natural
    frequencies over the number of fixed-interface modes kept (log scale)."""
    ax = _axes(ax)
    study = result.columns("study")
    kept = study["fixed_interface_modes"]
    for j in range(1, modes + 1):
        name = f"mode{j}_relative_error"
        if name in study:
            ax.semilogy(kept, np.abs(study[name]), "o-", ms=3, label=f"mode {j}")
    ax.set(xlabel="fixed-interface modes", ylabel="relative frequency error",
           title="Craig-Bampton reduction error")
    ax.legend(fontsize="small")
    return ax


def static_response(result, ax=None):
    """The static response (``whirl.static``): the deflection along the shaft, the
    bearings marked."""
    ax = _axes(ax)
    stations = result.to_pandas("stations")
    ax.plot(stations["z_m"], stations["uy_m"], label="uy")
    ax.plot(stations["z_m"], stations["ux_m"], "--", label="ux")
    reactions = result.to_pandas("reactions")
    ax.plot(reactions["z_m"], reactions["uy_m"], "^", color="black", label="bearings")
    ax.set(xlabel="z [m]", ylabel="deflection [m]", title="static deflection under gravity")
    ax.legend(fontsize="small")
    return ax


def ucs(result, ax=None):
    """The undamped critical-speed map (``whirl.ucs``): each critical speed over the bearing
    stiffness (log-log), where the bearings' own stiffness cuts the curves marked."""
    ax = _axes(ax)
    table = result.columns("ucs")
    for name, speeds in table.items():
        if name != "stiffness_n_per_m":
            ax.loglog(table["stiffness_n_per_m"], speeds, label=name.removesuffix("_hz"))
    for b in result.bearings:
        ax.axvline(b["stiffness_n_per_m"], color="grey", ls=":", lw=0.8)
        cuts = [c for c in b["critical_speeds_hz"] if c is not None]
        ax.plot([b["stiffness_n_per_m"]] * len(cuts), cuts, "o", color="black")
    ax.set(xlabel="bearing stiffness [N/m]", ylabel="critical speed [Hz]",
           title="undamped critical-speed map")
    ax.legend(fontsize="small")
    return ax


def frf(result, kind="receptance", ax=None):
    """Frequency response functions (``whirl.frf``): the magnitude of ``kind``
    (receptance, mobility or accelerance) of each output over frequency, peaks marked."""
    ax = _axes(ax)
    table = result.columns("frf")
    for name in table:
        if name.endswith(f"_{kind}_magnitude"):
            ax.semilogy(table["frequency_hz"], table[name], label=name.removesuffix(f"_{kind}_magnitude"))
    if kind == "receptance":
        peaks = result.to_pandas("peaks")
        ax.plot(peaks["frequency_hz"], peaks["receptance_magnitude"], "v", color="black")
    ax.set(xlabel="frequency [Hz]", ylabel=f"{kind} magnitude", title=f"{kind} from {result.input}")
    ax.legend(fontsize="small")
    return ax


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
    """A force-deflection surface (``whirl.stiffness``): ``component`` (fx, fy or fr, N) over
    the journal displacement at ``clearance`` (a table's label such as ``"20um"``; default
    the first surface), filled contours."""
    ax = _axes(ax)
    names = [n for n in result.tables if n.startswith("surfaces_")]
    name = names[0] if clearance is None else f"surfaces_{clearance}"
    t = result.columns(name)
    n = int(round(np.sqrt(len(t["ux_um"]))))
    grid = lambda key: np.asarray(t[key]).reshape(n, n)  # noqa: E731  (rows of uy)
    drawn = ax.contourf(grid("ux_um"), grid("uy_um"), grid(f"{component}_n"), levels=20)
    ax.figure.colorbar(drawn, ax=ax, label=f"{component} [N]")
    ax.set(xlabel="ux [um]", ylabel="uy [um]", aspect="equal",
           title=f"{component} at clearance {name.removeprefix('surfaces_')}")
    return ax


def rotor(result, ax=None):
    """The rotor's layout (``whirl.check``): the nodes along the shaft, disks and bearings
    marked with their node numbers."""
    model = result.model
    ax = _axes(ax)
    z = model.node_positions()
    ax.plot(z, np.zeros_like(z), "k.-", label="shaft nodes")
    bearings = model.bearing_nodes()
    ax.plot(z[bearings], np.zeros(len(bearings)), "^", markersize=12, label="bearings")
    for node in bearings:
        ax.annotate(str(node), (z[node], 0.0), textcoords="offset points", xytext=(0, -18), ha="center")
    ax.set(xlabel="z (m)", yticks=[], title=f"{model.name}: {model.node_count} nodes")
    ax.legend()
    return ax


def convergence(result, ax=None):
    """Each natural frequency over the number of elements (``whirl.convergence``)."""
    ax = _axes(ax)
    for j in range(result.frequencies_hz.shape[1]):
        ax.plot(result.element_counts, result.frequencies_hz[:, j], "o-", label=f"mode {j + 1}")
    ax.set(xlabel="elements", ylabel="natural frequency (Hz)", yscale="log", title="mesh convergence")
    ax.legend()
    return ax


def mode_shapes(result, ax=None):
    """The undamped mode shapes (``whirl.modal``): the larger of ux and uy of each mode along
    the shaft, scaled to 1, with its frequency."""
    ax = _axes(ax)
    z = result.model.node_positions()
    for j, f in enumerate(result.undamped_frequencies_hz):
        shape = result.undamped_shapes[:, j].reshape(len(z), 4)
        lateral = shape[:, 0] if np.abs(shape[:, 0]).max() >= np.abs(shape[:, 1]).max() else shape[:, 1]
        ax.plot(z, lateral / lateral[np.abs(lateral).argmax()], label=f"{f:.1f} Hz")
    ax.axhline(0.0, color="k", linewidth=0.5)
    ax.set(xlabel="z (m)", ylabel="displacement (scaled)", title="undamped mode shapes")
    ax.legend()
    return ax


def fit_forcing(result, ax=None):
    """The forcing-function fit (``whirl.fit_forcing``): the bearing's force over its
    deflection, sampled and fitted, log-log, per speed."""
    ax = _axes(ax)
    fit = result.columns("fit")
    for speed in np.unique(fit["speed_hz"]):
        at = fit["speed_hz"] == speed
        order = np.argsort(fit["deflection_m"][at])
        (drawn,) = ax.loglog(fit["deflection_m"][at], fit["force_n"][at], ".", alpha=0.4)
        ax.loglog(fit["deflection_m"][at][order], fit["fitted_force_n"][at][order], "-",
                  color=drawn.get_color(), label=f"{speed:g} Hz")
    ax.set(xlabel="deflection (m)", ylabel="force (N)", title="forcing function: samples and fit")
    ax.legend()
    return ax
