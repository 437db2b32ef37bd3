//! Figures of a time simulation: time histories, orbits and spectra, displacements in µm.

use whirl::time::SimulationResult;
use whirl_plot::{Colour, Figure2d, Grid, LegendPosition, RefLine, Series, Style};

use super::{grid_shape, um};
use crate::commands::campbell::order_name;
use crate::commands::simulate::ChannelReport;

/// A time history longer than this many pairs of points is drawn as its envelope: the
/// smallest and largest value of each of this many stretches, about one per pixel column.
/// It looks the same as every sample and keeps the SVG small.
const ENVELOPE_STRETCHES: usize = 1500;

/// At most this many points of an orbit are drawn (every k-th sample): a few hundred per
/// revolution over tens of revolutions.
const ORBIT_POINTS: usize = 6000;

/// The spectrum plot shows this many decades below its largest peak.
const SPECTRUM_DECADES: f64 = 6.0;

/// The smallest and the largest sample of each stretch, in time order.
fn envelope(t: &[f64], x: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let per = t.len().div_ceil(ENVELOPE_STRETCHES);
    if per <= 2 {
        return (t.to_vec(), x.to_vec());
    }
    let (mut te, mut xe) = (Vec::new(), Vec::new());
    for (tc, xc) in t.chunks(per).zip(x.chunks(per)) {
        let pick = |better: fn(f64, f64) -> bool| {
            (0..xc.len()).fold(0, |b, i| if better(xc[i], xc[b]) { i } else { b })
        };
        let (lo, hi) = (pick(|a, b| a < b), pick(|a, b| a > b));
        for i in [lo.min(hi), lo.max(hi)] {
            te.push(tc[i]);
            xe.push(xc[i]);
        }
    }
    (te, xe)
}

/// The recorded channels of `node`: (direction name, values).
fn node_channels(result: &SimulationResult, node: usize) -> impl Iterator<Item = (&str, &[f64])> {
    result
        .channels
        .iter()
        .filter(move |c| c.node == node)
        .map(|c| {
            let direction = c.name.rsplit('.').next().unwrap_or(&c.name);
            (direction, c.values.as_slice())
        })
}

/// ux and uy over time, one panel per node, the start of the settled part marked.
pub fn time_history(result: &SimulationResult, nodes: &[usize]) -> Grid {
    let mut grid = Grid::new(
        format!(
            "Time history ({}, step {:.3e} s)",
            result.method, result.step
        ),
        nodes.len().max(1),
        1,
    );
    grid.size = (1000, (300 * nodes.len() as u32).max(700));
    for &node in nodes {
        let mut panel = Figure2d::new(format!("node {node}"), "Time [s]", "Displacement [µm]");
        for (k, (direction, values)) in node_channels(result, node).enumerate() {
            let (t, x) = envelope(&result.time, values);
            panel.series.push(
                Series::new(t, um(&x))
                    .label(direction)
                    .style(Style::solid(Colour::Palette(k)).width(1)),
            );
        }
        if result.settle > 0.0 {
            panel
                .vertical_lines
                .push(RefLine::new(result.settle).label("settled from here"));
        }
        panel.legend = LegendPosition::LowerRight;
        grid.panels.push(panel);
    }
    grid
}

/// The orbit (uy against ux) of each node over the settled part, equal axes.
pub fn orbits(result: &SimulationResult, nodes: &[usize]) -> Grid {
    let (rows, cols) = grid_shape(nodes.len());
    let mut grid = Grid::new(
        format!("Orbits after {} s (x horizontal, y up)", result.settle),
        rows,
        cols,
    );
    let start = result.settled_start();
    for &node in nodes {
        let mut panel = Figure2d::new(format!("node {node}"), "ux [µm]", "uy [µm]");
        let channels: Vec<(&str, &[f64])> = node_channels(result, node).collect();
        if let [(_, ux), (_, uy)] = channels[..] {
            let stride = (ux.len() - start).div_ceil(ORBIT_POINTS).max(1);
            let pick = |v: &[f64]| -> Vec<f64> {
                v[start..].iter().step_by(stride).map(|x| 1e6 * x).collect()
            };
            panel.series.push(
                Series::new(pick(ux), pick(uy)).style(Style::solid(Colour::Palette(0)).width(1)),
            );
        }
        panel.equal_aspect = true;
        panel.legend = LegendPosition::Hidden;
        grid.panels.push(panel);
    }
    grid
}

/// Amplitude spectra of the settled part (logarithmic), 1X and its multiples marked.
pub fn spectrum(reports: &[ChannelReport], running_hz: f64) -> Figure2d {
    let mut fig = Figure2d::new(
        "Amplitude spectrum of the settled part (flat-top window)",
        "Frequency [Hz]",
        "Amplitude, zero-to-peak [µm]",
    );
    fig.log_y = true;
    let nyquist = reports
        .first()
        .and_then(|r| r.spectrum.frequency_hz.last().copied())
        .unwrap_or(1.0);
    // Ten orders, or past the highest listed peak when that lies further out.
    let highest_peak = reports
        .iter()
        .flat_map(|r| r.peaks.iter().map(|p| p.frequency_hz))
        .fold(0.0f64, f64::max);
    let top = (10.5 * running_hz).max(1.2 * highest_peak);
    let top = if top > 0.0 { top.min(nyquist) } else { nyquist };
    let mut largest = 0.0f64;
    let mut nodes: Vec<usize> = reports.iter().map(|r| r.node).collect();
    nodes.dedup();
    for r in reports {
        // One colour per node, as in the Bode plot; uy dashed.
        let colour = Colour::Palette(nodes.iter().position(|&n| n == r.node).unwrap_or(0));
        let style = if r.name.ends_with(".uy") {
            Style::dashed(colour)
        } else {
            Style::solid(colour)
        };
        let shown = r.spectrum.frequency_hz.partition_point(|&f| f <= top);
        largest = r.spectrum.amplitude[..shown]
            .iter()
            .copied()
            .fold(largest, f64::max);
        fig.series.push(
            Series::new(
                r.spectrum.frequency_hz[..shown].to_vec(),
                um(&r.spectrum.amplitude[..shown]),
            )
            .label(r.name.clone())
            .style(style.width(1)),
        );
    }
    if running_hz > 0.0 {
        let orders = (top / running_hz).floor() as usize;
        fig.vertical_lines = (1..=orders)
            .map(|k| RefLine::new(k as f64 * running_hz).label(order_name(k as f64)))
            .collect();
    }
    fig.x_range = Some((0.0, top));
    if largest > 0.0 {
        let largest = 1e6 * largest;
        fig.y_range = Some((largest * 10f64.powf(-SPECTRUM_DECADES), 3.0 * largest));
    }
    fig
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn envelope_keeps_extremes_in_time_order() {
        let t: Vec<f64> = (0..30_000).map(|i| i as f64).collect();
        let x: Vec<f64> = t.iter().map(|v| (v * 0.37).sin() * v).collect();
        let (te, xe) = envelope(&t, &x);
        assert!(te.len() <= 2 * ENVELOPE_STRETCHES);
        assert!(te.windows(2).all(|w| w[0] <= w[1]));
        let max = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(max(&xe), max(&x));
        // Short records are drawn as they are.
        assert_eq!(envelope(&t[..100], &x[..100]).0.len(), 100);
    }
}
