//! Every figure kind writes a PNG and an SVG; awkward data gives a plot or an error, never a
//! panic.

use std::path::{Path, PathBuf};

use whirl_plot::{
    Annotation, Colour, Figure2d, Grid, HeatMap, HeatMapGrid, LegendPosition, Line, Marker,
    PlotError, RefLine, Series, Style,
};

const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];

/// Asserts that `written` is `[stem.png, stem.svg]`, both well formed, the SVG naming `title`.
fn assert_written(written: &[PathBuf], stem: &Path, title: &str) {
    assert_eq!(written.len(), 2);
    assert_eq!(
        written[0],
        stem.with_file_name(format!("{}.png", name(stem)))
    );
    assert_eq!(
        written[1],
        stem.with_file_name(format!("{}.svg", name(stem)))
    );
    let png = std::fs::read(&written[0]).expect("png written");
    assert!(png.len() > PNG_SIGNATURE.len(), "png is empty");
    assert_eq!(png[..8], PNG_SIGNATURE, "not a PNG");
    let svg = std::fs::read_to_string(&written[1]).expect("svg written");
    assert!(svg.contains("<svg"), "not an SVG");
    assert!(svg.contains(title), "SVG lacks the title {title:?}");
}

fn name(stem: &Path) -> String {
    stem.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}

fn linspace(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| a + (b - a) * i as f64 / (n.max(2) - 1) as f64)
        .collect()
}

fn every_style() -> Figure2d {
    let x = linspace(0.0, 10.0, 41);
    let mut fig = Figure2d::new("Every style", "Speed [rpm]", "Amplitude [m]");
    let lines = [Line::Solid, Line::Dashed, Line::Dotted, Line::None];
    let markers = [
        Marker::None,
        Marker::Circle,
        Marker::OpenCircle,
        Marker::Triangle,
        Marker::Square,
        Marker::Cross,
    ];
    for (k, (line, marker)) in lines.iter().cycle().zip(markers).enumerate() {
        let y = x.iter().map(|x| (k as f64 + 1.0) * (1.0 + x * x)).collect();
        let style = Style {
            line: *line,
            marker,
            ..Style::default()
        };
        fig.series.push(
            Series::new(x.clone(), y)
                .label(format!("series {k}"))
                .style(style),
        );
    }
    fig.series.push(
        Series::new(x.clone(), x.iter().map(|x| 50.0 * x).collect())
            .style(Style::solid(Colour::Rgb(10, 200, 30)).width(4)),
    );
    fig.vertical_lines.push(RefLine::new(3.0).label("critical"));
    fig.vertical_lines
        .push(RefLine::new(9.5).label("near the right edge"));
    fig.horizontal_lines
        .push(RefLine::new(100.0).label("limit"));
    fig.annotations
        .push(Annotation::new(5.0, 30.0, "note").marked());
    fig.annotations.push(Annotation::new(9.9, 30.0, "right"));
    fig.log_y = true;
    fig
}

#[test]
fn figure2d_writes_png_and_svg() {
    let dir = tempfile::tempdir().unwrap();
    let stem = dir.path().join("styles");
    let written = every_style().save(&stem).unwrap();
    assert_written(&written, &stem, "Every style");
}

#[test]
fn legend_positions_and_log_x_do_not_fail() {
    let dir = tempfile::tempdir().unwrap();
    let positions = [
        LegendPosition::UpperLeft,
        LegendPosition::LowerLeft,
        LegendPosition::LowerRight,
        LegendPosition::UpperMiddle,
        LegendPosition::LowerMiddle,
        LegendPosition::MiddleRight,
        LegendPosition::MiddleLeft,
        LegendPosition::Hidden,
    ];
    for (k, legend) in positions.into_iter().enumerate() {
        let mut fig = every_style();
        fig.legend = legend;
        fig.log_x = k % 2 == 0;
        let stem = dir.path().join(format!("legend{k}"));
        assert_written(&fig.save(&stem).unwrap(), &stem, "Every style");
    }
}

#[test]
fn grid_writes_png_and_svg() {
    let dir = tempfile::tempdir().unwrap();
    let mut grid = Grid::new("Mode shapes", 2, 3);
    for m in 1..=5 {
        let z = linspace(0.0, 1.0, 30);
        let w = z
            .iter()
            .map(|z| (m as f64 * std::f64::consts::PI * z).sin())
            .collect();
        grid.panels.push(
            Figure2d::new(format!("Mode {m}"), "z [m]", "w [-]").with_series(
                Series::new(z, w)
                    .label("bending")
                    .style(Style::line_markers(Colour::Palette(m), Marker::Circle)),
            ),
        );
    }
    let stem = dir.path().join("modes");
    assert_written(&grid.save(&stem).unwrap(), &stem, "Mode shapes");
}

#[test]
fn orbit_with_equal_aspect_writes() {
    let dir = tempfile::tempdir().unwrap();
    let t = linspace(0.0, std::f64::consts::TAU, 200);
    let mut fig = Figure2d::new("Orbit", "x [m]", "y [m]").with_series(Series::new(
        t.iter().map(|t| 3e-5 * t.cos()).collect(),
        t.iter().map(|t| 1e-5 * t.sin()).collect(),
    ));
    fig.equal_aspect = true;
    let stem = dir.path().join("orbit");
    assert_written(&fig.save(&stem).unwrap(), &stem, "Orbit");
}

fn cascade() -> HeatMap {
    let x = linspace(100.0, 1000.0, 10);
    let y = vec![0.0, 1.0, 3.0, 7.0]; // uneven
    let z = y
        .iter()
        .map(|f| x.iter().map(|s| 1e-6 * (s / 100.0 + f)).collect())
        .collect();
    let mut map = HeatMap::new("Cascade", "Speed [rpm]", "Frequency [Hz]", "Amplitude [m]")
        .with_data(x.clone(), y, z);
    map.overlays
        .push(Series::new(x.clone(), x.iter().map(|s| s / 200.0).collect()).label("1X"));
    map
}

#[test]
fn heat_map_writes_png_and_svg_with_embedded_bitmap() {
    let dir = tempfile::tempdir().unwrap();
    for log_colour in [false, true] {
        let mut map = cascade();
        map.log_colour = log_colour;
        let stem = dir.path().join(format!("cascade_{log_colour}"));
        let written = map.save(&stem).unwrap();
        assert_written(&written, &stem, "Cascade");
        let svg = std::fs::read_to_string(&written[1]).unwrap();
        assert!(
            svg.contains("data:image/png;base64,"),
            "cells are one embedded image"
        );
    }
}

#[test]
fn heat_map_grid_writes_with_blank_cells_and_refuses_too_many_panels() {
    let dir = tempfile::tempdir().unwrap();
    let mut grid = HeatMapGrid::new("Cascades", 2, 2);
    grid.panels = vec![Some(cascade()), None, Some(cascade())];
    let stem = dir.path().join("cascades");
    assert_written(&grid.save(&stem).unwrap(), &stem, "Cascades");
    grid.panels = vec![Some(cascade()); 5];
    assert!(matches!(
        grid.save(&stem),
        Err(PlotError::GridShape { panels: 5, .. })
    ));
}

#[test]
fn stem_keeps_its_dots_and_parents_are_created() {
    let dir = tempfile::tempdir().unwrap();
    let stem = dir.path().join("a").join("b").join("run.v2");
    let fig =
        Figure2d::new("Dots", "x", "y").with_series(Series::new(vec![0.0, 1.0], vec![1.0, 2.0]));
    assert_written(&fig.save(&stem).unwrap(), &stem, "Dots");
}

/// Figures whose data cannot all be drawn: each must save without panicking.
#[test]
fn degenerate_figures_still_draw() {
    let nan = f64::NAN;
    let inf = f64::INFINITY;
    /// Title, x, y, log x, log y.
    type Case = (&'static str, Vec<f64>, Vec<f64>, bool, bool);
    let cases: Vec<Case> = vec![
        ("empty", vec![], vec![], false, false),
        ("all nan", vec![nan, nan], vec![nan, nan], false, false),
        ("one point", vec![1.0], vec![2.0], false, false),
        (
            "flat",
            vec![0.0, 1.0, 2.0],
            vec![5.0, 5.0, 5.0],
            false,
            false,
        ),
        ("zero flat", vec![0.0, 1.0], vec![0.0, 0.0], false, false),
        (
            "infinite",
            vec![0.0, 1.0, 2.0, 3.0],
            vec![1.0, inf, -inf, 2.0],
            false,
            false,
        ),
        (
            "log of negatives",
            vec![1.0, 2.0],
            vec![-1.0, 0.0],
            true,
            true,
        ),
        ("huge", vec![0.0, 1.0], vec![-1e300, 1e300], false, false),
        (
            "tiny span",
            vec![0.0, 1.0],
            vec![1.0, 1.0 + 1e-15],
            false,
            false,
        ),
        (
            "subnormal",
            vec![0.0, 1.0],
            vec![5e-324, 1e-320],
            false,
            false,
        ),
        (
            "orbit of a point",
            vec![2.0, 2.0],
            vec![2.0, 2.0],
            false,
            false,
        ),
    ];
    let dir = tempfile::tempdir().unwrap();
    for (k, (title, x, y, log_x, log_y)) in cases.into_iter().enumerate() {
        let mut fig = Figure2d::new(title, "x", "y").with_series(
            Series::new(x, y)
                .label("data")
                .style(Style::line_markers(Colour::Palette(k), Marker::Square)),
        );
        fig.log_x = log_x;
        fig.log_y = log_y;
        fig.equal_aspect = title.starts_with("orbit");
        let stem = dir.path().join(format!("degenerate{k}"));
        match fig.save(&stem) {
            Ok(written) => assert_written(&written, &stem, title),
            Err(e) => panic!("{title}: {e}"),
        }
    }
}

#[test]
fn silly_styles_and_explicit_ranges_draw() {
    let dir = tempfile::tempdir().unwrap();
    let mut fig = Figure2d::new("Silly", "x", "y").with_series(
        Series::new(vec![0.0, 1.0, 2.0], vec![0.0, 10.0, 0.0]).style(
            Style::line_markers(Colour::Palette(usize::MAX), Marker::Triangle)
                .width(u32::MAX)
                .marker_size(u32::MAX),
        ),
    );
    fig.x_range = Some((0.5, 0.5)); // zero width: padded
    fig.y_range = Some((2.0, 3.0)); // data crosses it: clipped
    fig.annotations.push(Annotation::new(f64::NAN, 1.0, "lost"));
    fig.vertical_lines
        .push(RefLine::new(f64::INFINITY).label("lost"));
    let stem = dir.path().join("silly");
    assert_written(&fig.save(&stem).unwrap(), &stem, "Silly");
}

#[test]
fn degenerate_heat_maps_still_draw() {
    let dir = tempfile::tempdir().unwrap();
    let nan = f64::NAN;
    /// Title, x, y, z, log colour.
    type Case = (&'static str, Vec<f64>, Vec<f64>, Vec<Vec<f64>>, bool);
    let cases: Vec<Case> = vec![
        ("no data", vec![], vec![], vec![], false),
        ("one cell", vec![3.0], vec![0.0], vec![vec![1.0]], false),
        (
            "all nan",
            vec![1.0, 2.0],
            vec![1.0, 2.0],
            vec![vec![nan; 2]; 2],
            false,
        ),
        (
            "all equal",
            vec![1.0, 2.0],
            vec![1.0, 2.0],
            vec![vec![4.0; 2]; 2],
            false,
        ),
        (
            "log of zeros",
            vec![1.0, 2.0],
            vec![1.0, 2.0],
            vec![vec![0.0, -1.0]; 2],
            true,
        ),
        ("no rows", vec![1.0, 2.0], vec![], vec![], false),
    ];
    for (k, (title, x, y, z, log_colour)) in cases.into_iter().enumerate() {
        let mut map = HeatMap::new(title, "x", "y", "z").with_data(x, y, z);
        map.log_colour = log_colour;
        map.overlays
            .push(Series::new(vec![nan, 1.0], vec![1.0, inf()]).label("overlay"));
        let stem = dir.path().join(format!("heat{k}"));
        match map.save(&stem) {
            Ok(written) => assert_written(&written, &stem, title),
            Err(e) => panic!("{title}: {e}"),
        }
    }
}

fn inf() -> f64 {
    f64::INFINITY
}

#[test]
fn inconsistent_input_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let stem = dir.path().join("bad");
    let mismatch =
        Figure2d::default().with_series(Series::new(vec![1.0, 2.0], vec![1.0]).label("short"));
    assert!(matches!(
        mismatch.save(&stem),
        Err(PlotError::LengthMismatch { .. })
    ));

    let reversed = Figure2d {
        x_range: Some((2.0, 1.0)),
        ..Figure2d::default()
    };
    assert!(matches!(
        reversed.save(&stem),
        Err(PlotError::InvalidRange { axis: "x", .. })
    ));

    let log_from_zero = Figure2d {
        log_y: true,
        y_range: Some((0.0, 1.0)),
        ..Figure2d::default()
    };
    assert!(matches!(
        log_from_zero.save(&stem),
        Err(PlotError::InvalidRange { axis: "y", .. })
    ));

    let overflow =
        Figure2d::default().with_series(Series::new(vec![0.0, 1.0], vec![-f64::MAX, f64::MAX]));
    assert!(matches!(
        overflow.save(&stem),
        Err(PlotError::InvalidRange { .. })
    ));

    let tiny = Figure2d {
        size: (10, 10),
        ..Figure2d::default()
    };
    assert!(matches!(tiny.save(&stem), Err(PlotError::TooSmall(10, 10))));

    let ragged = HeatMap::new("", "", "", "").with_data(vec![1.0, 2.0], vec![1.0], vec![vec![1.0]]);
    assert!(matches!(ragged.save(&stem), Err(PlotError::Shape(_))));
    let unsorted =
        HeatMap::new("", "", "", "").with_data(vec![2.0, 1.0], vec![1.0], vec![vec![1.0, 1.0]]);
    assert!(matches!(unsorted.save(&stem), Err(PlotError::Shape(_))));

    let no_cells = Grid::new("", 0, 3);
    assert!(matches!(
        no_cells.save(&stem),
        Err(PlotError::GridShape { .. })
    ));
    let crowded = Grid::new("", 1, 1)
        .with_panel(Figure2d::default())
        .with_panel(Figure2d::default());
    assert!(matches!(
        crowded.save(&stem),
        Err(PlotError::GridShape { .. })
    ));
    let mut cramped = Grid::new("", 10, 10);
    cramped.size = (1000, 700);
    assert!(matches!(cramped.save(&stem), Err(PlotError::TooSmall(..))));

    assert!(
        !stem.with_extension("png").exists(),
        "no file is written for bad input"
    );
}
