//! Figures of a time simulation: time histories, orbits and spectra, displacements in µm;
//! for roller bearings the contact line and contact zone (thesis figs. 4.7 and 4.9).

use std::f64::consts::PI;
use std::ops::Range;

use whirl::time::{RollerRecord, SimulationResult};
use whirl_plot::{
    Annotation, Colour, Figure2d, Grid, LegendPosition, Line, Marker, RefLine, Series, Style,
};

use super::{grid_shape, um};
use crate::order_name;
use whirl::model::Model;
use whirl::time::{BearingReport, SettledChannel};

/// A time history longer than this many pairs of points is drawn as its envelope: the
/// smallest and largest value of each of this many stretches, about one per pixel column.
/// It looks the same as every sample and keeps the SVG small.
const ENVELOPE_STRETCHES: usize = 1500;

/// At most this many points of an orbit are drawn (every k-th sample): a few hundred per
/// revolution over tens of revolutions.
const ORBIT_POINTS: usize = 6000;

/// The spectrum plot shows this many decades below its largest peak.
const SPECTRUM_DECADES: f64 = 6.0;

/// The spectrum plot reaches past peaks down to this fraction of their channel's largest.
const SHOWN_PEAK_RELATIVE: f64 = 0.1;

/// At most this many orders of the running speed are marked on the spectrum.
const MAX_ORDER_LINES: usize = 12;

/// The contact line draws at most this many stretches per roller, each marked in contact
/// when the roller touched anywhere in it: about one per pixel column.
const CONTACT_LINE_STRETCHES: usize = 2000;

/// At most this many points of the contact zone are drawn (every k-th sample).
const ZONE_POINTS: usize = 20_000;

/// Points of a clearance circle.
const CIRCLE_POINTS: usize = 181;

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

/// The orbit (uy against ux) of each node over the settled part, equal axes; at the nodes
/// of `circles` (node, radius in m) a dashed circle of that radius: a roller bearing's
/// clearance, inside which the shaft moves freely.
pub fn orbits(result: &SimulationResult, nodes: &[usize], circles: &[(usize, f64)]) -> Grid {
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
        panel.legend = LegendPosition::Hidden;
        for &(_, radius) in circles.iter().filter(|(n, _)| *n == node) {
            let (x, y): (Vec<f64>, Vec<f64>) = (0..CIRCLE_POINTS)
                .map(|k| {
                    let a = 2.0 * PI * k as f64 / (CIRCLE_POINTS - 1) as f64;
                    (1e6 * radius * a.cos(), 1e6 * radius * a.sin())
                })
                .unzip();
            panel.series.push(
                Series::new(x, y)
                    .label(format!("clearance {:.1} µm", 1e6 * radius))
                    .style(Style::dashed(Colour::GREY).width(1)),
            );
            panel.legend = LegendPosition::LowerRight;
        }
        panel.equal_aspect = true;
        grid.panels.push(panel);
    }
    grid
}

/// Amplitude spectra of the settled part (logarithmic), 1X and its multiples marked, and
/// `markers` (the roller bearings' contact frequencies).
pub fn spectrum(reports: &[SettledChannel], running_hz: f64, markers: &[RefLine]) -> Figure2d {
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
    // Peaks that matter: within a decade of their channel's largest.
    let highest_peak = reports
        .iter()
        .flat_map(|r| {
            let largest = r.peaks.first().map_or(0.0, |p| p.amplitude);
            r.peaks
                .iter()
                .filter(move |p| p.amplitude >= SHOWN_PEAK_RELATIVE * largest)
                .map(|p| p.frequency_hz)
        })
        .fold(0.0f64, f64::max);
    let highest_marker = markers.iter().map(|m| m.value).fold(0.0f64, f64::max);
    let top = (10.5 * running_hz)
        .max(1.2 * highest_peak)
        .max(1.1 * highest_marker);
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
        let orders = ((top / running_hz).floor() as usize).min(MAX_ORDER_LINES);
        fig.vertical_lines = (1..=orders)
            .map(|k| RefLine::new(k as f64 * running_hz).label(order_name(k as f64)))
            .collect();
    }
    fig.vertical_lines.extend(markers.iter().cloned());
    fig.x_range = Some((0.0, top));
    if largest > 0.0 {
        let largest = 1e6 * largest;
        fig.y_range = Some((largest * 10f64.powf(-SPECTRUM_DECADES), 3.0 * largest));
    }
    fig
}

/// Roller index versus time over the samples `window`: a thick bar where the roller is in
/// contact (thesis fig. 4.7).
pub fn contact_line(record: &RollerRecord, time: &[f64], window: Range<usize>) -> Figure2d {
    let mut fig = Figure2d::new(
        format!(
            "Contact line of {}: bars where a roller touches",
            record.name
        ),
        "Time [s]",
        "Roller",
    );
    let per = window.len().div_ceil(CONTACT_LINE_STRETCHES).max(1);
    let starts: Vec<usize> = window.clone().step_by(per).collect();
    for j in 0..record.rollers {
        let (mut x, mut y) = (Vec::new(), Vec::new());
        for &a in &starts {
            let b = (a + per).min(window.end);
            let touches = (a..b).any(|i| record.in_contact(i, j));
            // Each stretch spans from its first sample to the next stretch's, so
            // consecutive stretches in contact join into one bar.
            x.push(time[a]);
            y.push(if touches { j as f64 } else { f64::NAN });
            x.push(time[b.min(time.len() - 1)]);
            y.push(if touches { j as f64 } else { f64::NAN });
        }
        fig.series.push(
            Series::new(x, y)
                .label(format!("roller {j}"))
                .style(Style::solid(Colour::Palette(j)).width(6)),
        );
    }
    fig.y_range = Some((-0.5, record.rollers as f64 - 0.5));
    fig.legend = LegendPosition::Hidden;
    fig
}

/// Roller force versus roller angle (0 deg along +x, 90 deg up, 270 deg straight down)
/// over the samples `range`, points where a roller touches (thesis fig. 4.9). A law
/// without per-roller forces shows the penetration instead, against the clearance.
pub fn contact_zone(record: &RollerRecord, range: Range<usize>, clearance: f64) -> Figure2d {
    let forces = record.has_forces();
    let mut fig = Figure2d::new(
        format!("Contact zone of {}", record.name),
        "Roller angle [deg] (270 = bottom)",
        if forces {
            "Roller force [N]"
        } else {
            "Roller penetration [µm]"
        },
    );
    if !forces {
        fig.title = format!(
            "Contact zone of {} (no per-roller forces: penetration, clearance {:.1} µm)",
            record.name,
            1e6 * clearance
        );
    }
    let (x, y) = zone_samples(record, range);
    fig.series.push(Series::new(x, y).style(Style {
        line: Line::None,
        ..Style::markers(Colour::Palette(0), Marker::Circle).marker_size(2)
    }));
    fig.vertical_lines
        .push(RefLine::new(270.0).label("bottom (gravity)"));
    fig.x_range = Some((0.0, 360.0));
    fig.legend = LegendPosition::Hidden;
    fig
}

/// Angles (degrees in 0-360) and loads (roller force, N, or without per-roller forces the
/// penetration, µm) of the rollers in contact over `range`, at most about [`ZONE_POINTS`].
fn zone_samples(record: &RollerRecord, range: Range<usize>) -> (Vec<f64>, Vec<f64>) {
    let forces = record.has_forces();
    let stride = (range.len() * record.rollers).div_ceil(ZONE_POINTS).max(1);
    let (mut angle, mut load) = (Vec::new(), Vec::new());
    for i in range.step_by(stride) {
        for j in 0..record.rollers {
            if !record.in_contact(i, j) {
                continue;
            }
            let k = i * record.rollers + j;
            angle.push(record.angle[k].to_degrees().rem_euclid(360.0));
            load.push(if forces {
                record.force[k]
            } else {
                1e6 * record.approach[k]
            });
        }
    }
    (angle, load)
}

/// Width of the sectors whose largest load draws the load zone's outline, degrees.
const ZONE_SECTOR_DEG: f64 = 5.0;

/// The load zone as bearing engineers draw it: around the bearing (x horizontal, y up, so
/// 270 degrees is the bottom) each roller contact at the distance of its load from the
/// centre, the largest load of each 5-degree sector joined into an outline, circles of
/// equal load and the four quadrant directions.
pub fn load_zone(record: &RollerRecord, range: Range<usize>) -> Figure2d {
    let forces = record.has_forces();
    let unit = if forces { "N" } else { "µm" };
    let (angle, load) = zone_samples(record, range);
    let mut fig = Figure2d::new(
        format!(
            "Load zone of {}: roller {} by angle (x horizontal, y up)",
            record.name,
            if forces { "force" } else { "penetration" }
        ),
        format!("Horizontal [{unit}]"),
        format!("Vertical [{unit}]"),
    );
    fig.equal_aspect = true;
    let polar = |deg: f64, r: f64| {
        let t = deg.to_radians();
        (r * t.cos(), r * t.sin())
    };
    let sectors = (360.0 / ZONE_SECTOR_DEG).round() as usize;
    let mut largest = vec![0.0f64; sectors];
    for (&a, &l) in angle.iter().zip(&load) {
        let k = ((a / ZONE_SECTOR_DEG) as usize).min(sectors - 1);
        largest[k] = largest[k].max(l);
    }
    let top = largest.iter().copied().fold(0.0, f64::max);
    let step = round_step(top);
    let grey = Colour::Rgb(150, 150, 150);
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    for level in (1..)
        .map(|k| k as f64 * step)
        .take_while(|&l| l <= top * 1.0001)
    {
        let (x, y) = (0..=72).map(|k| polar(5.0 * k as f64, level)).unzip();
        fig.series
            .push(Series::new(x, y).style(Style::solid(grey).width(1)));
        fig.annotations.push(Annotation::new(
            0.0,
            level,
            format!("{level:.decimals$} {unit}"),
        ));
    }
    let reach = top.max(step) * 1.1;
    for (deg, name) in [
        (0.0, "0°"),
        (90.0, "90°"),
        (180.0, "180°"),
        (270.0, "270° bottom"),
    ] {
        let (x, y) = polar(deg, reach);
        fig.series
            .push(Series::new(vec![0.0, x], vec![0.0, y]).style(Style::dashed(grey).width(1)));
        fig.annotations.push(Annotation::new(x, y, name));
    }
    let (x, y) = angle.iter().zip(&load).map(|(&a, &l)| polar(a, l)).unzip();
    fig.series.push(
        Series::new(x, y)
            .label("each roller contact")
            .style(Style::markers(Colour::Palette(0), Marker::Circle).marker_size(2)),
    );
    let (x, y) = (0..=sectors)
        .map(|k| {
            polar(
                (k % sectors) as f64 * ZONE_SECTOR_DEG + 0.5 * ZONE_SECTOR_DEG,
                largest[k % sectors],
            )
        })
        .unzip();
    fig.series.push(
        Series::new(x, y)
            .label(format!("largest in each {ZONE_SECTOR_DEG}° sector"))
            .style(Style::solid(Colour::Palette(1))),
    );
    fig.x_range = Some((-reach * 1.15, reach * 1.15));
    fig.y_range = Some((-reach * 1.15, reach * 1.15));
    fig.legend = LegendPosition::UpperRight;
    fig
}

/// A round spacing (1, 2 or 5 times a power of ten) that puts two to five circles up to
/// `top`.
fn round_step(top: f64) -> f64 {
    if !(top > 0.0 && top.is_finite()) {
        return 1.0;
    }
    let decade = 10f64.powf((top / 2.0).log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&s| top / s >= 2.0)
        .unwrap_or(decade)
}

/// (node, clearance in m at `speed`) of every roller bearing, for the orbit plot.
pub fn clearance_circles(model: &Model, speed: f64) -> Vec<(usize, f64)> {
    model
        .roller_bearings
        .iter()
        .map(|b| (b.station.node, b.clearance.at_speed(speed)))
        .collect()
}

/// Vertical lines at the characteristic frequencies (FTF, BPFO = N_b w_c, BPFI, BSF) and the
/// waviness frequencies, one per distinct frequency.
pub fn spectrum_markers(bearings: &[BearingReport]) -> Vec<RefLine> {
    let mut lines: Vec<RefLine> = Vec::new();
    for b in bearings {
        let characteristic = b
            .characteristic
            .lines()
            .map(|(name, f)| (name.to_string(), f));
        // The waviness lines; N_b w_c is BPFO, already among the characteristic lines.
        let waviness = b
            .frequencies
            .iter()
            .filter(|f| f.predicted.source != "varying compliance")
            .map(|f| {
                let orders = f.predicted.cage_orders;
                let label = if f.predicted.source.starts_with("ring-fixed") {
                    format!("{orders:.4} w_c")
                } else {
                    format!("({}-1) w_c", orders + 1.0)
                };
                (label, f.predicted.frequency_hz)
            });
        for (label, value) in characteristic.into_iter().chain(waviness) {
            let duplicate = lines
                .iter()
                .any(|l| (l.value - value).abs() <= 1e-9 * l.value.abs());
            if duplicate || value.is_nan() || value <= 0.0 {
                continue;
            }
            // Short labels: the lines sit among the order lines; the values are in
            // summary.json.
            lines.push(RefLine {
                colour: Colour::Palette(1),
                ..RefLine::new(value).label(label)
            });
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn load_circles_are_round_and_two_to_five() {
        for (top, step) in [
            (1.0, 0.5),
            (171.0, 50.0),
            (9.0, 2.0),
            (2.0, 1.0),
            (4.5, 2.0),
        ] {
            assert_eq!(round_step(top), step, "{top}");
            let circles = (top / step).floor();
            assert!((2.0..=5.0).contains(&circles), "{top}: {circles}");
        }
    }

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
