//! Figures of `whirl hbm`: the harmonics of a node along the harmonic-balance branch, its
//! stability, and the first harmonic for several harmonic counts. Amplitudes in µm.

use whirl::fe::{dof, Direction};
use whirl::hbm::{SettledResponse, Sweep};
use whirl_plot::{Colour, Figure2d, LegendPosition, Marker, RefLine, Series, Style};

use crate::kind_label;
use whirl::units::rad_s_to_hz as hz;

/// Runs of consecutive points with the same stability, as (stable, indices).
fn stability_runs(result: &Sweep) -> Vec<(bool, Vec<usize>)> {
    let mut runs: Vec<(bool, Vec<usize>)> = Vec::new();
    for (i, p) in result.branch.points.iter().enumerate() {
        let stable = p.stability.as_ref().is_none_or(|s| s.stable);
        match runs.last_mut() {
            Some((s, idx)) if *s == stable => idx.push(i),
            _ => {
                // Start the new run at the last point so the curve stays connected.
                let mut idx = runs
                    .last()
                    .map_or(Vec::new(), |(_, v)| vec![v[v.len() - 1]]);
                idx.push(i);
                runs.push((stable, idx));
            }
        }
    }
    runs
}

/// The harmonics of `node` along the branch; `from` (rad/s), the start of the range asked
/// for, is marked where the branch went below it.
pub fn harmonics_plot(
    result: &Sweep,
    node: usize,
    comparisons: &[SettledResponse],
    from: f64,
) -> Figure2d {
    let uy = dof(node, Direction::Uy);
    let mut figure = Figure2d::new(
        format!(
            "Harmonics of uy at node {node} ({})",
            short_bearings(result)
        ),
        "Spin speed [Hz]",
        "Amplitude [µm]",
    );
    figure.log_y = true;
    figure.legend = LegendPosition::UpperRight;
    let speeds: Vec<f64> = result
        .branch
        .points
        .iter()
        .map(|p| hz(p.solution.frequency))
        .collect();
    for r in 1..=result.harmonics() {
        let colour = Colour::Palette(r - 1);
        for (k, (stable, idx)) in stability_runs(result).into_iter().enumerate() {
            let x = idx.iter().map(|&i| speeds[i]).collect();
            let y = idx
                .iter()
                .map(|&i| 1e6 * result.amplitude(i, uy, r))
                .collect();
            let style = if stable {
                Style::solid(colour)
            } else {
                Style::dashed(colour)
            };
            let mut series = Series::new(x, y).style(style);
            if k == 0 {
                series = series.label(format!("{r}X"));
            }
            figure.series.push(series);
        }
    }
    // Harmonics far below the largest (the response at the lowest speeds) would squeeze
    // the decades that matter.
    let top = figure
        .series
        .iter()
        .flat_map(|s| s.y.iter().copied())
        .fold(0.0f64, f64::max);
    if top > 0.0 {
        figure.y_range = Some((1e-4 * top, 3.0 * top));
    }
    // The line style, not the colour, tells stability: say so in the legend, in grey,
    // when stability was computed.
    if result.branch.points.iter().any(|p| p.stability.is_some()) {
        let grey = Colour::Rgb(90, 90, 90);
        for (label, style) in [
            ("stable", Style::solid(grey)),
            ("unstable (dashed)", Style::dashed(grey)),
        ] {
            figure.series.push(
                Series::new(Vec::new(), Vec::new())
                    .label(label)
                    .style(style),
            );
        }
    }
    if !comparisons.is_empty() {
        figure.series.push(
            Series::new(
                comparisons.iter().map(|c| hz(c.speed)).collect(),
                comparisons.iter().map(|c| 1e6 * c.uy[0]).collect(),
            )
            .label("1X time marching")
            .style(Style::markers(Colour::Palette(0), Marker::Circle)),
        );
    }
    figure.vertical_lines = result
        .branch
        .bifurcations
        .iter()
        .filter(|b| b.loses_stability)
        .map(|b| RefLine::new(hz(b.frequency)).label(kind_label(b.kind)))
        .collect();
    if result.branch.speed_span().0 < from {
        figure
            .vertical_lines
            .push(RefLine::new(hz(from)).label("start of range"));
    }
    figure
}

/// The bearing model in a title's few words.
fn short_bearings(result: &Sweep) -> &'static str {
    if result
        .bearings
        .starts_with("Hertz contacts, roller passage averaged")
    {
        "passage-averaged rollers"
    } else if result.bearings.starts_with("Hertz contacts, cage frozen") {
        "frozen cage"
    } else {
        "forcing function"
    }
}

/// The largest real part of the Floquet exponents over speed.
pub fn stability_plot(result: &Sweep) -> Figure2d {
    let mut figure = Figure2d::new(
        "Largest real part of the Floquet exponents (> 0: unstable)",
        "Spin speed [Hz]",
        "Re(lambda) [1/s]",
    );
    let (x, y) = result
        .branch
        .points
        .iter()
        .filter_map(|p| {
            p.stability
                .as_ref()
                .map(|s| (hz(p.solution.frequency), s.max_real))
        })
        .unzip();
    figure
        .series
        .push(Series::new(x, y).style(Style::solid(Colour::Palette(0))));
    figure.horizontal_lines = vec![RefLine::new(0.0)];
    figure.legend = LegendPosition::Hidden;
    figure
}

/// The first harmonic of `node` over speed for each harmonic count of the study.
pub fn study_plot(study: &[(usize, Sweep)], node: usize) -> Figure2d {
    let uy = dof(node, Direction::Uy);
    let mut figure = Figure2d::new(
        format!("1X of uy at node {node} for several harmonic counts"),
        "Spin speed [Hz]",
        "Amplitude [µm]",
    );
    figure.log_y = true;
    for (k, (h, r)) in study.iter().enumerate() {
        let (x, y) = r
            .branch
            .points
            .iter()
            .enumerate()
            .map(|(i, p)| (hz(p.solution.frequency), 1e6 * r.amplitude(i, uy, 1)))
            .unzip();
        figure.series.push(
            Series::new(x, y)
                .label(format!("H = {h}"))
                .style(Style::solid(Colour::Palette(k))),
        );
    }
    figure
}
