//! Figures of frequency response functions and of the undamped critical-speed map.

use whirl::modal::CriticalSpeedMap;
use whirl::model::Model;
use whirl::response::{FrfKind, FrfResult};
use whirl_plot::{
    Annotation, Colour, Figure2d, Grid, LegendPosition, Marker, RefLine, Series, Style,
};

use super::{nearest, unwrap_deg};

/// One FRF kind of every output: magnitude (log) and phase above real and imaginary parts.
pub fn frf(model: &Model, result: &FrfResult, kind: FrfKind) -> Grid {
    let f = &result.frequencies_hz;
    let unit = kind.unit();
    let mut magnitude = Figure2d::new("Magnitude", "Frequency [Hz]", format!("|H| [{unit}]"));
    magnitude.log_y = true;
    let mut phase = Figure2d::new("Phase", "Frequency [Hz]", "Phase [deg]");
    let mut real = Figure2d::new("Real part", "Frequency [Hz]", format!("Re H [{unit}]"));
    let mut imag = Figure2d::new("Imaginary part", "Frequency [Hz]", format!("Im H [{unit}]"));
    for (o, out) in result.outputs.iter().enumerate() {
        let values: Vec<_> = (0..f.len()).map(|k| result.value(kind, o, k)).collect();
        let style = Style::solid(Colour::Palette(o));
        let series = |y: Vec<f64>| Series::new(f.clone(), y).style(style);
        magnitude
            .series
            .push(series(values.iter().map(|v| v.norm()).collect()).label(out.name.clone()));
        let deg: Vec<f64> = values.iter().map(|v| v.arg().to_degrees()).collect();
        phase.series.push(series(unwrap_deg(&deg)));
        real.series
            .push(series(values.iter().map(|v| v.re).collect()));
        imag.series
            .push(series(values.iter().map(|v| v.im).collect()));
        for p in &out.peaks {
            let k = nearest(f, p.speed_hz).unwrap_or(0);
            magnitude.annotations.push(
                Annotation::new(
                    p.speed_hz,
                    values[k].norm(),
                    format!("{:.1} Hz", p.speed_hz),
                )
                .marked(),
            );
        }
    }
    for fig in [&mut phase, &mut real, &mut imag] {
        fig.legend = LegendPosition::Hidden;
    }
    for fig in [&mut real, &mut imag] {
        fig.horizontal_lines.push(RefLine::new(0.0));
    }
    let speed_hz = result.speed / (2.0 * std::f64::consts::PI);
    let mut grid = Grid::new(
        format!(
            "{}: {} from {} at spin speed {:.2} Hz ({:.0} rpm)",
            model.name,
            kind.name(),
            result.input.1,
            speed_hz,
            60.0 * speed_hz
        ),
        2,
        2,
    );
    grid.size = (1400, 1000);
    grid.panels = vec![magnitude, phase, real, imag];
    grid
}

/// The critical-speed map: one curve per mode over the bearing stiffness (log-log), the
/// bearings' stiffnesses as vertical lines with their intersections marked, and the
/// operating speed range as horizontal lines.
pub fn critical_speed_map(model: &Model, map: &CriticalSpeedMap) -> Figure2d {
    let mut fig = Figure2d::new(
        format!(
            "{}: undamped critical-speed map ({})",
            model.name,
            if map.synchronous {
                "synchronous forward whirl, gyroscopic"
            } else {
                "at rest"
            }
        ),
        "Bearing stiffness [N/m] (every bearing)",
        "Critical speed [Hz]",
    );
    fig.log_x = true;
    fig.log_y = true;
    for (m, curve) in map.critical_speeds_hz.iter().enumerate() {
        fig.series.push(
            Series::new(map.stiffness.clone(), curve.clone())
                .label(format!("mode {}", m + 1))
                .style(Style::solid(Colour::Palette(m))),
        );
    }
    // Bearings of equal stiffness share one line.
    let mut drawn: Vec<f64> = Vec::new();
    for b in &map.bearings {
        if drawn.iter().any(|&k| (k - b.stiffness).abs() <= 1e-9 * k) {
            continue;
        }
        drawn.push(b.stiffness);
        let same: Vec<&str> = map
            .bearings
            .iter()
            .filter(|o| (o.stiffness - b.stiffness).abs() <= 1e-9 * b.stiffness)
            .map(|o| o.label.as_str())
            .collect();
        fig.vertical_lines
            .push(RefLine::new(b.stiffness).label(format!(
                "{} {:.2e} N/m",
                same.join(", "),
                b.stiffness
            )));
        let (x, y): (Vec<f64>, Vec<f64>) = b
            .critical_speeds_hz
            .iter()
            .flatten()
            .map(|&s| (b.stiffness, s))
            .unzip();
        for &s in &y {
            fig.annotations
                .push(Annotation::new(b.stiffness, s, format!("{s:.1} Hz")));
        }
        fig.series.push(
            Series::new(x, y)
                .style(Style::markers(Colour::BLACK, Marker::OpenCircle).marker_size(6)),
        );
    }
    if let Some((lo, hi)) = model.operating {
        for (w, name) in [(lo, "min"), (hi, "max")] {
            let f = w / (2.0 * std::f64::consts::PI);
            if f > 0.0 {
                fig.horizontal_lines
                    .push(RefLine::new(f).label(format!("{name} operating {f:.0} Hz")));
            }
        }
    }
    fig.legend = LegendPosition::UpperLeft;
    fig
}
