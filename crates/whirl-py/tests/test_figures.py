"""The command line's figures from Python: the same files from the same specification, and
matplotlib drawing that specification's series."""

from __future__ import annotations

import pickle

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

import whirl  # noqa: E402
import whirl.plot  # noqa: E402
from conftest import EXAMPLES, REFERENCE  # noqa: E402

#: Each analysis as the command line runs it and as Python does, with the same options.
#: Small runs (seconds): the figures, not the physics, are under test.
RUNS = {
    "check": (["check"], lambda: whirl.check(REFERENCE)),
    "campbell": (
        ["campbell", "--speeds", "0:800Hz:41", "--orders", "1,2"],
        lambda: whirl.campbell(REFERENCE, "0:800Hz:41", orders=[1, 2]),
    ),
    "modal": (["modal", "--speed", "300Hz", "--modes", "6"], lambda: whirl.modal(REFERENCE, "300Hz", modes=6)),
    "unbalance": (
        ["unbalance", "--speeds", "1:100Hz:40", "--nodes", "10"],
        lambda: whirl.unbalance(REFERENCE, "1:100Hz:40", nodes=[10]),
    ),
    "cascade": (
        ["cascade", "--speeds", "100Hz:300Hz:4", "--no-refine", "--max-records", "1", "--compare-starts"],
        lambda: whirl.cascade(
            REFERENCE, "100Hz:300Hz:4", no_refine=True, max_records=1, compare_starts=True, progress=False
        ),
    ),
    "hbm": (["hbm", "--speeds", "1:60Hz", "--harmonics", "2"], lambda: whirl.hbm(REFERENCE, "1:60Hz", harmonics=2, progress=False)),
    "simulate": (
        ["simulate", "--speed", "50Hz", "--duration", "0.3s", "--reduce", "12", "--nodes", "10"],
        lambda: whirl.simulate(REFERENCE, "50Hz", duration="0.3s", reduce=12, nodes=[10], progress=False),
    ),
    "fit-forcing": (
        ["fit-forcing", "--speeds", "200Hz:300Hz:2", "--duration", "0.2s", "--settle", "0.1s"],
        lambda: whirl.fit_forcing(REFERENCE, "200Hz:300Hz:2", duration="0.2s", settle="0.1s"),
    ),
    "runup": (
        ["runup", "--speeds", "100:140Hz", "--rate", "40Hz/s", "--steady", "none"],
        lambda: whirl.runup(REFERENCE, speeds="100:140Hz", rate="40Hz/s", steady="none"),
    ),
    "map": (
        ["map", "--values", "20um,60um", "--speeds", "1:30Hz", "--harmonics", "2", "--reduce", "12"],
        lambda: whirl.map(REFERENCE, ["20um", "60um"], "1:30Hz", harmonics=2, reduce=12, progress=False),
    ),
    "convergence": (
        ["convergence", "--counts", "2,5,10,20", "--modes", "4"],
        lambda: whirl.convergence(REFERENCE, [2, 5, 10, 20], modes=4),
    ),
    "static": (["static"], lambda: whirl.static(REFERENCE)),
    "reduce": (["reduce", "--modes", "8", "--nodes", "10"], lambda: whirl.reduce(REFERENCE, modes=8, nodes=[10])),
    "ucs": (["ucs", "--modes", "3"], lambda: whirl.ucs(REFERENCE, modes=3)),
    "frf": (["frf", "--input", "10:ux"], lambda: whirl.frf(REFERENCE, (10, "ux"))),
    "stiffness": (
        ["stiffness", "--cage-steps", "4", "--grid", "5"],
        lambda: whirl.stiffness(REFERENCE, cage_steps=4, grid=5),
    ),
}


@pytest.fixture(autouse=True)
def close_figures():
    yield
    import matplotlib.pyplot as plt

    plt.close("all")


def svgs(folder) -> dict[str, bytes]:
    return {p.stem: p.read_bytes() for p in sorted(folder.glob("*.svg"))}


@pytest.mark.parametrize("command", RUNS)
def test_python_writes_the_command_lines_figures(command, run_cli, tmp_path):
    """The same figures, file for file: each SVG (the data of every series, mark and label
    as text) byte for byte the command line's, drawn from the same specification."""
    args, run = RUNS[command]
    cli = run_cli(args[0], str(REFERENCE), *args[1:])
    result = run()
    written = result.save_figures(tmp_path / "py")
    names = [spec["name"] for spec in result.figure_specs()]
    assert sorted(written) == sorted(str(tmp_path / "py" / f"{n}.{ext}") for n in names for ext in ("png", "svg"))
    expected = svgs(cli.out)
    assert list(expected) == sorted(names), "Python and the command line write different figures"
    for name, svg in svgs(tmp_path / "py").items():
        assert svg == expected[name], f"{command}: {name}.svg differs from the command line's"


def test_a_study_writes_the_command_lines_figures(run_cli, tmp_path):
    study = tmp_path / "study.toml"
    text = (EXAMPLES / "quick_study.toml").read_text()
    study.write_text(text.replace('model = "reference_rotor.toml"', f"model = {str(REFERENCE)!r}"))
    cli = run_cli("study", str(study), "--checkpoint", str(tmp_path / "cli.points"))
    result = whirl.study(study, checkpoint=tmp_path / "py.points", progress=False)
    assert result.figures == ("cascades_0", "nsv_0")
    result.save_figures(tmp_path / "py")
    assert svgs(tmp_path / "py") == svgs(cli.out)


def test_speeds_in_rpm_as_the_command_line_writes_them(run_cli, tmp_path):
    cli = run_cli("campbell", str(REFERENCE), "--speeds", "0:800Hz:41", "--rpm")
    result = whirl.campbell(REFERENCE, "0:800Hz:41")
    result.save_figures(tmp_path / "py", rpm=True)
    assert svgs(tmp_path / "py") == svgs(cli.out)
    assert b"[rpm]" in svgs(cli.out)["campbell"]


def lines_of(spec: dict) -> list[tuple[list, list]]:
    """The (x, y) of every series of a plot or grid specification, panel by panel."""
    figure = spec["figure"]
    panels = figure["panels"] if figure["kind"] == "grid" else [figure]
    return [(s["x"], s["y"]) for panel in panels for s in panel["series"]]


@pytest.mark.parametrize("name", ["campbell", "log_decrement"])
def test_matplotlib_draws_the_specifications_series(name):
    """`.plot()` draws the command line's figure: one line per series of the
    specification, in order, with its data and label; the axes' labels and scales too."""
    result = whirl.campbell(REFERENCE, "0:800Hz:41", orders=[1, 2])
    spec = result.figure_spec(name)
    ax = result.plot(name)
    figure = spec["figure"]
    drawn = ax.lines[: len(figure["series"])]
    assert len(drawn) == len(figure["series"]) > 0
    for line, series in zip(drawn, figure["series"]):
        np.testing.assert_array_equal(line.get_xdata(), series["x"])
        np.testing.assert_array_equal(line.get_ydata(), series["y"])
        assert line.get_label() == (series["label"] if series["label"] is not None else "_nolegend_")
    assert (ax.get_xlabel(), ax.get_ylabel(), ax.get_title()) == (figure["x_label"], figure["y_label"], figure["title"])
    assert ax.get_ylim() == pytest.approx(figure["y_range"])
    # Forward branches solid, backward dashed, as the command line draws them.
    styles = {s["label"].split()[0][-1]: s["style"]["line"] for s in figure["series"][:4]}
    assert styles == {"F": "solid", "B": "dashed"}, styles


def test_panels_and_heat_maps_draw_from_their_specification():
    response = whirl.unbalance(REFERENCE, "1:100Hz:40", nodes=[10])
    ax = whirl.plot.bode(response)
    amplitude, phase = ax.figure.axes
    spec = response.figure_spec("bode")
    panels = spec["figure"]["panels"]
    # Each panel's series first, then its reference lines (the operating speed range).
    drawn = [(line.get_xdata(), line.get_ydata()) for a, p in zip((amplitude, phase), panels)
             for line in a.lines[: len(p["series"])]]
    assert len(drawn) == len(lines_of(spec)) == 4
    assert len(amplitude.lines) == 2 + len(panels[0]["vertical_lines"])
    for (x, y), (sx, sy) in zip(drawn, lines_of(spec)):
        np.testing.assert_array_equal(x, sx)
        np.testing.assert_array_equal(y, sy)
    assert amplitude.get_yscale() == "log" and phase.get_ylabel() == "Phase [deg]"
    with pytest.raises(ValueError, match="2 panels: give as many Axes, not 1"):
        whirl.plot.bode(response, ax=amplitude)
    cascade = RUNS["cascade"][1]()
    ax = cascade.plot("cascade_map")
    figure = cascade.figure_spec("cascade_map")["figure"]
    assert figure["kind"] == "heat_map"
    mesh = ax.collections[0].get_array()
    assert mesh.size == len(figure["x"]) * len(figure["y"])
    labels = [line.get_label() for line in ax.lines]
    assert labels == [s["label"] or "_nolegend_" for s in figure["overlays"]]
    assert any(label.startswith("BPFO") for label in labels), labels


def test_figures_survive_pickling(tmp_path):
    result = whirl.modal(REFERENCE, "300Hz", modes=6)
    back = pickle.loads(pickle.dumps(result))
    assert back.figures == result.figures == ("mode_shapes", "damped_orbits")
    # The specifications hold NaN (!= NaN): the files drawn from them are compared.
    back.save_figures(tmp_path / "a")
    result.save_figures(tmp_path / "b")
    assert svgs(tmp_path / "a") == svgs(tmp_path / "b")


def test_a_bad_specification_is_an_input_error(tmp_path):
    spec = whirl.check(REFERENCE).figure_spec("rotor")
    spec["figure"]["series"][0]["style"]["colour"] = "grey"
    with pytest.raises(whirl.InputError, match="figure specification 0: .*#rrggbb"):
        whirl._whirl.save_figures([spec], tmp_path, False)
