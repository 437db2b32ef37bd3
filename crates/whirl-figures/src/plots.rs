//! Results mapped onto whirl-plot figures, one function per figure. The CLI saves each as
//! PNG and SVG. Lengths are shown in mm (the rotor) or µm (responses); speeds in Hz.
//!
//! Conventions across figures: forward whirl is a solid line, backward dashed, mixed
//! dotted; a mode's forward and backward branches share a colour; excitation orders are
//! thin grey lines; the operating speed range is shown by two grey vertical lines.

use std::f64::consts::PI;

use whirl::bearing::characteristic_frequencies;
use whirl::fe::{dof, Direction};
use whirl::modal::{
    CampbellResult, ClearanceCurve, ComplexMode, ConvergenceResult, CriticalSpeed, UndampedModes,
    Whirl,
};
use whirl::model::Model;
use whirl::response::UnbalanceResult;
use whirl_plot::{
    Annotation, Colour, Figure2d, Grid, LegendPosition, Line, Marker, RefLine, Series, Style,
};

use crate::order_name;

mod cascade;
pub mod fit;
mod frf;
pub mod map;
mod reduce;
mod runup;
mod statics;
pub mod stiffness;
pub mod study;
mod time;

pub use cascade::{
    cascade_map, default_map_top_hz, full_map, nsv_amplitude, nsv_from_both_starts, waterfall,
};
pub use frf::{critical_speed_map, frf};
pub use reduce::{reduction_error, stable_steps};
pub use runup::{runup_amplitudes, runup_maps};
pub use statics::{roller_loads, static_response};
pub use time::{clearance_circles, orbits, spectrum, spectrum_markers, time_history};
pub use time::{contact_line, contact_zone, load_zone};

/// At most this many panels of modes (a grid of 4 x 3).
const MAX_PANELS: usize = 12;

/// Rows and columns for `n` panels: up to three per row.
fn grid_shape(n: usize) -> (usize, usize) {
    let cols = n.clamp(1, 3);
    (n.max(1).div_ceil(cols), cols)
}

/// Line style of a whirl direction in `colour`.
fn whirl_style(whirl: Whirl, colour: Colour) -> Style {
    let line = match whirl {
        Whirl::Forward => Line::Solid,
        Whirl::Backward => Line::Dashed,
        Whirl::Mixed => Line::Dotted,
    };
    Style {
        line,
        ..Style::solid(colour)
    }
}

/// The palette colour of a label's rank: `2F` and `2B` share colour 1.
fn rank_colour(label: &str) -> Colour {
    let rank: usize = label
        .trim_end_matches(char::is_alphabetic)
        .parse()
        .unwrap_or(1);
    Colour::Palette(rank.saturating_sub(1))
}

/// Grey vertical lines at the model's operating speed range, Hz.
fn operating_lines(operating_hz: Option<(f64, f64)>) -> Vec<RefLine> {
    match operating_hz {
        Some((lo, hi)) => vec![
            RefLine::new(lo).label(format!("min operating {lo:.0} Hz")),
            RefLine::new(hi).label(format!("max operating {hi:.0} Hz")),
        ],
        None => Vec::new(),
    }
}

/// Radius and width (m) of the solid disk with a disk's mass and inertias:
/// I_p = m r^2 / 2 and I_d = m (3 r^2 + b^2) / 12 (thesis eq. 2.14).
fn equivalent_disk(mass: f64, polar: f64, diametral: f64) -> (f64, f64) {
    if mass <= 0.0 {
        return (0.0, 0.0);
    }
    let r2 = 2.0 * polar / mass;
    let b2 = 12.0 * diametral / mass - 3.0 * r2;
    (r2.max(0.0).sqrt(), b2.max(0.0).sqrt())
}

/// The rotor seen from the side: shaft outline, nodes, disks (as the solid disk of the same
/// mass and inertias) and bearings, radii in mm.
pub fn rotor_layout(model: &Model) -> Figure2d {
    let mut fig = Figure2d::new(
        format!("{}: layout", model.name),
        "Axial position z [m]",
        "Radius [mm]",
    );
    let length = model.length();
    let (mut z, mut r_out, mut r_in) = (Vec::new(), Vec::new(), Vec::new());
    let mut start = 0.0;
    for s in &model.sections {
        for zz in [start, start + s.length] {
            z.push(zz);
            r_out.push(500.0 * s.outer_diameter);
            r_in.push(500.0 * s.inner_diameter);
        }
        start += s.length;
    }
    let shaft = Colour::Rgb(90, 90, 90);
    fig.series.push(
        Series::new(z.clone(), r_out.clone())
            .label("shaft")
            .style(Style::solid(shaft)),
    );
    fig.series.push(
        Series::new(z.clone(), r_out.iter().map(|r| -r).collect()).style(Style::solid(shaft)),
    );
    if r_in.iter().any(|&r| r > 0.0) {
        fig.series.push(
            Series::new(z.clone(), r_in.clone())
                .label("bore")
                .style(Style::dashed(shaft)),
        );
        fig.series
            .push(Series::new(z, r_in.iter().map(|r| -r).collect()).style(Style::dashed(shaft)));
    }
    let positions = model.node_positions();
    fig.series.push(
        Series::new(positions.clone(), vec![0.0; positions.len()])
            .label("nodes")
            .style(Style::markers(Colour::BLACK, Marker::Circle).marker_size(2)),
    );
    let mut rmax = r_out.iter().copied().fold(1.0, f64::max);
    for (k, d) in model.disks.iter().enumerate() {
        let (r, b) = equivalent_disk(d.mass, d.polar_inertia, d.diametral_inertia);
        let (r, half) = (1e3 * r, 0.5 * b.max(0.006 * length));
        rmax = rmax.max(r);
        let zc = d.station.z;
        let series = Series::new(
            vec![zc - half, zc + half, zc + half, zc - half, zc - half],
            vec![-r, -r, r, r, -r],
        )
        .style(Style::solid(Colour::Palette(0)).width(3));
        fig.series
            .push(if k == 0 { series.label("disk") } else { series });
        fig.annotations.push(Annotation::new(
            zc,
            r,
            format!("{} ({:.3} kg)", d.name, d.mass),
        ));
    }
    let supports: Vec<(f64, String, f64)> = model
        .bearings
        .iter()
        .map(|b| (b.station.z, b.name.clone(), b.station.node))
        .chain(
            model
                .roller_bearings
                .iter()
                .map(|b| (b.station.z, b.name.clone(), b.station.node)),
        )
        .map(|(z, name, node)| (z, name, shaft_radius_mm(model, node)))
        .collect();
    if !supports.is_empty() {
        let (zs, ys): (Vec<f64>, Vec<f64>) = supports.iter().map(|s| (s.0, -s.2)).unzip();
        fig.series.push(
            Series::new(zs, ys)
                .label("bearing")
                .style(Style::markers(Colour::Palette(1), Marker::Triangle).marker_size(9)),
        );
    }
    for (z, name, r) in supports {
        fig.annotations
            .push(Annotation::new(z, -r - 0.25 * rmax, name));
    }
    fig.y_range = Some((-1.5 * rmax, 1.5 * rmax));
    fig.x_range = Some((-0.05 * length, 1.05 * length));
    fig.legend = LegendPosition::LowerRight;
    fig
}

/// Outer radius of the shaft at a node, mm (the larger of the two sections at a joint).
fn shaft_radius_mm(model: &Model, node: usize) -> f64 {
    let mut first = 0;
    let mut r: f64 = 0.0;
    for s in &model.sections {
        let last = first + s.elements;
        if (first..=last).contains(&node) {
            r = r.max(500.0 * s.outer_diameter);
        }
        first = last;
    }
    r
}

/// Scale factor that makes the largest translation of a real shape 1.
fn translation_scale(values: impl Iterator<Item = f64>) -> f64 {
    let largest = values.fold(0.0f64, |a, v| a.max(v.abs()));
    if largest > 0.0 {
        1.0 / largest
    } else {
        1.0
    }
}

/// Deflected shapes of the undamped modes: ux and uy along the shaft, one panel per mode.
pub fn mode_shapes(model: &Model, modes: &UndampedModes) -> Grid {
    let n = modes.frequencies_hz.len().min(MAX_PANELS);
    let (rows, cols) = grid_shape(n);
    let mut grid = Grid::new(
        format!(
            "{}: undamped mode shapes (largest translation 1)",
            model.name
        ),
        rows,
        cols,
    );
    let z = model.node_positions();
    let bearings: Vec<f64> = model.bearing_nodes().iter().map(|&b| z[b]).collect();
    for j in 0..n {
        let ux: Vec<f64> = (0..z.len())
            .map(|k| modes.shapes[(dof(k, Direction::Ux), j)])
            .collect();
        let uy: Vec<f64> = (0..z.len())
            .map(|k| modes.shapes[(dof(k, Direction::Uy), j)])
            .collect();
        let s = translation_scale(ux.iter().chain(&uy).copied());
        let mut panel = Figure2d::new(
            format!("mode {}: {:.2} Hz", j + 1, modes.frequencies_hz[j]),
            "z [m]",
            "Deflection [-]",
        );
        panel.series.push(
            Series::new(z.clone(), ux.iter().map(|v| v * s).collect())
                .label("ux")
                .style(Style::line_markers(Colour::Palette(0), Marker::Circle).marker_size(2)),
        );
        panel.series.push(
            Series::new(z.clone(), uy.iter().map(|v| v * s).collect())
                .label("uy")
                .style(Style::dashed(Colour::Palette(1))),
        );
        panel.y_range = Some((-1.15, 1.15));
        panel.vertical_lines = bearings.iter().map(|&b| RefLine::new(b)).collect();
        panel.horizontal_lines.push(RefLine::new(0.0));
        panel.legend = LegendPosition::LowerRight;
        grid.panels.push(panel);
    }
    grid
}

/// The most orbits drawn along the shaft in [`damped_orbits`].
const MAX_ORBITS: usize = 60;

/// Orbits of the damped modes along the shaft, one panel per mode (thesis figs. 2.9-2.10).
///
/// A three-dimensional view in oblique projection: the shaft axis runs left to right, y is
/// up and x points into the page, drawn up and to the right. Each node's orbit is a thin
/// ellipse around its place on the axis; the thick line joins the nodes at t = 0 (the
/// deflected shape), the dashed one 1/8 period later, which shows the whirl direction.
/// Shapes are scaled so that the largest translation is 1.
pub fn damped_orbits(
    model: &Model,
    modes: &[ComplexMode],
    labels: &[String],
    speed_hz: f64,
) -> Grid {
    let n = modes.len().min(MAX_PANELS);
    let (rows, cols) = grid_shape(n);
    let mut grid = Grid::new(
        format!(
            "{}: damped modes at {speed_hz:.1} Hz; orbits with x into the page, \
             shape at t = 0 (solid) and 1/8 period later (dashed)",
            model.name
        ),
        rows,
        cols,
    );
    let z = model.node_positions();
    let length = model.length();
    // Oblique projection of x: along z by `ax` (m per unit) and up by `ay` (units per unit).
    let (ax, ay) = (0.06 * length, 0.35);
    let project = |zn: f64, x: f64, y: f64| (zn + ax * x, y + ay * x);
    // At most MAX_ORBITS evenly spaced nodes and the last: more orbits than that overlap
    // into a grey band, and a fine mesh's thousands of them took most of `modal`'s time.
    let stride = z.len().div_ceil(MAX_ORBITS);
    let drawn = |node: usize| node.is_multiple_of(stride) || node + 1 == z.len();
    let steps = 72;
    for (m, label) in modes.iter().zip(labels).take(n) {
        let colour = rank_colour(label);
        let mut panel = Figure2d::new(
            format!(
                "{label} {:.2} Hz, {} whirl",
                m.damped_frequency_hz,
                m.whirl.name()
            ),
            "z [m]",
            "y [-]",
        );
        panel.series.push(
            Series::new(vec![0.0, length], vec![0.0, 0.0])
                .style(Style::solid(Colour::GREY).width(1)),
        );
        let mut shape = (Vec::new(), Vec::new());
        let mut later = (Vec::new(), Vec::new());
        for (node, &zn) in z.iter().enumerate().filter(|(node, _)| drawn(*node)) {
            let a = m.shape[dof(node, Direction::Ux)];
            let b = m.shape[dof(node, Direction::Uy)];
            let (x, y): (Vec<f64>, Vec<f64>) = (0..=steps)
                .map(|k| {
                    let t = 2.0 * PI * k as f64 / steps as f64;
                    let e = faer::c64::new(t.cos(), t.sin());
                    project(zn, (a * e).re, (b * e).re)
                })
                .unzip();
            shape.0.push(x[0]);
            shape.1.push(y[0]);
            later.0.push(x[steps / 8]);
            later.1.push(y[steps / 8]);
            panel
                .series
                .push(Series::new(x, y).style(Style::solid(Colour::Rgb(150, 150, 150)).width(1)));
        }
        panel.series.push(
            Series::new(shape.0, shape.1).style(
                Style::line_markers(colour, Marker::Circle)
                    .width(3)
                    .marker_size(3),
            ),
        );
        panel
            .series
            .push(Series::new(later.0, later.1).style(Style::dashed(colour).width(2)));
        panel.x_range = Some((-0.1 * length, 1.1 * length + ax));
        panel.y_range = Some((-1.2 - ay, 1.2 + ay));
        panel.legend = LegendPosition::Hidden;
        grid.panels.push(panel);
    }
    grid
}

/// Campbell diagram: branches (forward solid, backward dashed), order lines, the first roller
/// bearing's characteristic frequencies, critical speeds.
pub fn campbell(model: &Model, result: &CampbellResult, labels: &[String]) -> Figure2d {
    let mut fig = Figure2d::new(
        format!("{}: Campbell diagram", model.name),
        "Spin speed [Hz]",
        "Whirl frequency [Hz]",
    );
    let speeds = &result.speeds_hz;
    let mut top = 0.0f64;
    for (b, label) in result.branches.iter().zip(labels) {
        top = b
            .frequency_hz
            .iter()
            .copied()
            .filter(|f| f.is_finite())
            .fold(top, f64::max);
        let f0 = b
            .frequency_hz
            .iter()
            .copied()
            .find(|f| f.is_finite())
            .unwrap_or(f64::NAN);
        fig.series.push(
            Series::new(speeds.clone(), b.frequency_hz.clone())
                .label(format!("{label} {f0:.1} Hz"))
                .style(whirl_style(b.whirl, rank_colour(label))),
        );
    }
    let top = if top > 0.0 { 1.08 * top } else { 1.0 };
    let (x_lo, x_hi) = match (speeds.first(), speeds.last()) {
        (Some(&a), Some(&b)) => (a, b),
        _ => (0.0, 0.0),
    };
    for (k, &order) in result.orders.iter().enumerate() {
        fig.series.push(
            Series::new(speeds.clone(), speeds.iter().map(|s| order * s).collect())
                .label(order_name(order))
                .style(order_style(k)),
        );
        // The name where the line leaves the plot, so it is read off the line itself.
        let end = x_hi.min(0.97 * top / order);
        if end > x_lo {
            fig.annotations
                .push(Annotation::new(end, order * end, order_name(order)));
        }
    }
    fig.series.extend(bearing_lines(
        model,
        speeds,
        x_lo..x_hi,
        top,
        &mut fig.annotations,
    ));
    for (whirl, marker, label) in [
        (
            Whirl::Forward,
            Marker::OpenCircle,
            "critical speed, forward",
        ),
        (Whirl::Backward, Marker::Square, "critical speed, backward"),
        (Whirl::Mixed, Marker::Cross, "critical speed, mixed whirl"),
    ] {
        let (x, y): (Vec<f64>, Vec<f64>) = result
            .critical_speeds
            .iter()
            .filter(|c| c.whirl == whirl)
            .map(|c| (c.speed_hz, c.frequency_hz))
            .unzip();
        if !x.is_empty() {
            fig.series.push(
                Series::new(x, y)
                    .label(label)
                    .style(Style::markers(Colour::BLACK, marker).marker_size(6)),
            );
        }
    }
    for cluster in crossing_clusters(&result.critical_speeds, x_hi - x_lo, top) {
        // One entry per printed speed, its whirl letters joined: "24.9 Hz B/F".
        let mut texts: Vec<(String, String)> = Vec::new();
        for c in &cluster {
            let (speed, letter) = (format!("{:.1}", c.speed_hz), whirl_letter(c.whirl));
            match texts.iter_mut().find(|(s, _)| *s == speed) {
                Some((_, letters)) if !letters.contains(letter) => {
                    letters.push('/');
                    letters.push_str(letter);
                }
                Some(_) => {}
                None => texts.push((speed, letter.to_string())),
            }
        }
        // Each speed with its unit, so that --rpm can write it in rpm.
        let texts: Vec<String> = texts.iter().map(|(s, l)| format!("{s} Hz {l}")).collect();
        let last = cluster[cluster.len() - 1];
        let y = cluster.iter().map(|c| c.frequency_hz).fold(0.0, f64::max);
        fig.annotations
            .push(Annotation::new(last.speed_hz, y, texts.join(" / ")));
    }
    if let Some((_, hi)) = model.operating {
        let hi = hi / (2.0 * PI);
        fig.vertical_lines
            .push(RefLine::new(hi).label(format!("max operating {hi:.0} Hz")));
    }
    fig.y_range = Some((0.0, top));
    if let (Some(&a), Some(&b)) = (speeds.first(), speeds.last()) {
        if b > a {
            fig.x_range = Some((a, b));
        }
    }
    fig.legend = LegendPosition::UpperLeft;
    fig
}

/// The first order line (1X) solid and dark; higher orders dotted and lighter, so 1X and
/// 2X differ in more than a shade of grey.
/// The first roller bearing's characteristic frequencies (FTF, BPFO = N_b w_c, BPFI, BSF)
/// as lines over `speeds`, each named where it leaves the plot (at frequency `top`).
fn bearing_lines(
    model: &Model,
    speeds: &[f64],
    span: std::ops::Range<f64>,
    top: f64,
    annotations: &mut Vec<Annotation>,
) -> Vec<Series> {
    let Some(bearing) = model.roller_bearings.first() else {
        return Vec::new();
    };
    characteristic_frequencies(bearing, 1.0)
        .lines()
        .into_iter()
        .enumerate()
        .map(|(i, (name, order))| {
            let end = span.end.min(0.97 * top / order);
            if end > span.start {
                annotations.push(Annotation::new(end, order * end, name));
            }
            Series::new(speeds.to_vec(), speeds.iter().map(|s| order * s).collect())
                .label(name)
                .style(Style::dashed(Colour::Palette(4 + i)).width(1))
        })
        .collect()
}

fn order_style(k: usize) -> Style {
    if k == 0 {
        Style::solid(Colour::Rgb(30, 30, 30))
    } else {
        let grey = 70 + 30 * (k as u8 % 4);
        Style {
            line: Line::Dotted,
            ..Style::solid(Colour::Rgb(grey, grey, grey))
        }
    }
}

fn whirl_letter(whirl: Whirl) -> &'static str {
    match whirl {
        Whirl::Forward => "F",
        Whirl::Backward => "B",
        Whirl::Mixed => "M",
    }
}

/// Critical speeds below `top` (Hz) grouped for one label each: crossings within 4 % of the
/// speed span and 4 % of the frequency axis of the previous one (a forward and a backward
/// branch crossing 1X a few Hz apart), sorted by speed. Crossings near in speed but far
/// apart in frequency (2X at 470 Hz, 1X at 250 Hz) get labels of their own.
fn crossing_clusters(critical: &[CriticalSpeed], span: f64, top: f64) -> Vec<Vec<&CriticalSpeed>> {
    let mut visible: Vec<&CriticalSpeed> =
        critical.iter().filter(|c| c.frequency_hz <= top).collect();
    visible.sort_by(|a, b| a.speed_hz.total_cmp(&b.speed_hz));
    let mut clusters: Vec<Vec<&CriticalSpeed>> = Vec::new();
    for c in visible {
        let near = |d: &&CriticalSpeed| {
            (c.speed_hz - d.speed_hz).abs() < 0.04 * span
                && (c.frequency_hz - d.frequency_hz).abs() < 0.04 * top
        };
        match clusters.iter_mut().find(|cl| cl.iter().any(near)) {
            Some(cluster) => cluster.push(c),
            None => clusters.push(vec![c]),
        }
    }
    clusters
}

/// Logarithmic decrement of each branch over speed.
pub fn log_decrement(result: &CampbellResult, labels: &[String]) -> Figure2d {
    let mut fig = Figure2d::new(
        "Logarithmic decrement of the whirl branches",
        "Spin speed [Hz]",
        "Log decrement [-]",
    );
    for (b, label) in result.branches.iter().zip(labels) {
        fig.series.push(
            Series::new(result.speeds_hz.clone(), b.log_decrement.clone())
                .label(label.clone())
                .style(whirl_style(b.whirl, rank_colour(label))),
        );
    }
    fig.horizontal_lines
        .push(RefLine::new(0.1).label("log dec 0.1 (API 617 minimum)"));
    // From zero (or below, if a branch is unstable), with room for the legend at the top.
    let finite = || {
        result
            .branches
            .iter()
            .flat_map(|b| b.log_decrement.iter().copied())
            .filter(|d| d.is_finite())
    };
    let lo = finite().fold(0.0f64, f64::min);
    let hi = finite().fold(0.15f64, f64::max);
    fig.y_range = Some((1.1 * lo, 1.45 * hi));
    fig.legend = LegendPosition::UpperRight;
    fig
}

/// Frequency versus element count, one panel per mode (thesis fig. 2.8).
pub fn convergence(result: &ConvergenceResult) -> Grid {
    let modes = result
        .frequencies_hz
        .first()
        .map_or(0, |f| f.len())
        .min(MAX_PANELS);
    let (rows, cols) = grid_shape(modes);
    let mut grid = Grid::new("Mesh convergence of the natural frequencies", rows, cols);
    let x: Vec<f64> = result.element_counts.iter().map(|&n| n as f64).collect();
    for j in 0..modes {
        let y: Vec<f64> = result.frequencies_hz.iter().map(|f| f[j]).collect();
        let last = y.last().copied().unwrap_or(f64::NAN);
        let mut panel = Figure2d::new(
            format!("mode {}: {last:.3} Hz", j + 1),
            "Elements",
            "Frequency [Hz]",
        );
        panel.series.push(
            Series::new(x.clone(), y)
                .style(Style::line_markers(Colour::Palette(j), Marker::Circle)),
        );
        panel.legend = LegendPosition::Hidden;
        grid.panels.push(panel);
    }
    grid
}

/// Relative change of each frequency from the previous mesh, logarithmic.
pub fn convergence_change(result: &ConvergenceResult) -> Figure2d {
    let mut fig = Figure2d::new(
        "Change of each frequency from the previous mesh",
        "Elements",
        "Relative change [-]",
    );
    fig.log_y = true;
    let x: Vec<f64> = result.element_counts.iter().map(|&n| n as f64).collect();
    let modes = result.relative_change.first().map_or(0, |c| c.len());
    for j in 0..modes {
        let y: Vec<f64> = result.relative_change.iter().map(|c| c[j]).collect();
        fig.series.push(
            Series::new(x.clone(), y)
                .label(format!("mode {}", j + 1))
                .style(Style::line_markers(Colour::Palette(j), Marker::Circle)),
        );
    }
    fig
}

/// Each roller bearing's clearance over speed (thesis fig. 3.3).
pub fn clearance_over_speed(curve: &ClearanceCurve) -> Figure2d {
    let mut fig = Figure2d::new("Internal radial clearance", "Speed [Hz]", "Clearance [um]");
    for (j, (name, values)) in curve.bearings.iter().enumerate() {
        fig.series.push(
            Series::new(curve.speeds_hz.clone(), um(values))
                .label(name.clone())
                .style(Style::solid(Colour::Palette(j))),
        );
    }
    fig
}

/// µm from m.
fn um(v: &[f64]) -> Vec<f64> {
    v.iter().map(|x| x * 1e6).collect()
}

/// Phase in degrees made continuous: each step is taken modulo 360 into (-180, 180].
fn unwrap_deg(phase: &[f64]) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::with_capacity(phase.len());
    for &p in phase {
        let next = match out.last() {
            Some(&prev) if p.is_finite() && prev.is_finite() => {
                prev + (p - prev + 180.0).rem_euclid(360.0) - 180.0
            }
            _ => p,
        };
        out.push(next);
    }
    out
}

/// Bode plot: amplitude (log) above phase (unwrapped), ux solid and uy dashed, one colour per node.
pub fn bode(result: &UnbalanceResult) -> Grid {
    let mut amp = Figure2d::new("Amplitude", "Spin speed [Hz]", "Amplitude [µm]");
    let mut phase = Figure2d::new("Phase", "Spin speed [Hz]", "Phase [deg]");
    amp.log_y = true;
    for (c, r) in result.nodes.iter().enumerate() {
        let colour = Colour::Palette(c);
        let s = &result.speeds_hz;
        amp.series.push(
            Series::new(s.clone(), um(&r.ux_amplitude))
                .label(format!("node {} ux", r.node))
                .style(Style::solid(colour)),
        );
        amp.series.push(
            Series::new(s.clone(), um(&r.uy_amplitude))
                .label(format!("node {} uy", r.node))
                .style(Style::dashed(colour)),
        );
        phase
            .series
            .push(Series::new(s.clone(), unwrap_deg(&r.ux_phase_deg)).style(Style::solid(colour)));
        phase
            .series
            .push(Series::new(s.clone(), unwrap_deg(&r.uy_phase_deg)).style(Style::dashed(colour)));
    }
    amp.vertical_lines = operating_lines(result.operating_hz);
    phase.vertical_lines = operating_lines(result.operating_hz);
    phase.legend = LegendPosition::Hidden;
    amp.legend = LegendPosition::LowerRight;
    let mut grid = Grid::new("Unbalance response", 2, 1);
    grid.size = (1000, 900);
    grid.panels = vec![amp, phase];
    grid
}

/// Polar (Nyquist) plot of ux at each node, µm; peaks labelled with their speed.
pub fn polar(result: &UnbalanceResult) -> Figure2d {
    let mut fig = Figure2d::new(
        "Unbalance response, polar plot of ux",
        "Re ux [µm]",
        "Im ux [µm]",
    );
    for (c, r) in result.nodes.iter().enumerate() {
        let (x, y): (Vec<f64>, Vec<f64>) = r
            .ux_amplitude
            .iter()
            .zip(&r.ux_phase_deg)
            .map(|(a, p)| {
                let p = p.to_radians();
                (1e6 * a * p.cos(), 1e6 * a * p.sin())
            })
            .unzip();
        for p in &r.peaks {
            if let Some(k) = nearest(&result.speeds_hz, p.speed_hz) {
                fig.annotations
                    .push(Annotation::new(x[k], y[k], format!("{:.1} Hz", p.speed_hz)).marked());
            }
        }
        fig.series.push(
            Series::new(x, y)
                .label(format!("node {}", r.node))
                .style(Style::solid(Colour::Palette(c))),
        );
    }
    fig.equal_aspect = true;
    fig
}

/// Index of the sample nearest to `x`.
fn nearest(xs: &[f64], x: f64) -> Option<usize> {
    xs.iter()
        .enumerate()
        .min_by(|a, b| (a.1 - x).abs().total_cmp(&(b.1 - x).abs()))
        .map(|(i, _)| i)
}

/// Orbit major semi-axis over speed, each peak labelled with speed and amplification factor.
pub fn orbit_major(result: &UnbalanceResult) -> Figure2d {
    let mut fig = Figure2d::new(
        "Unbalance response, orbit size",
        "Spin speed [Hz]",
        "Major semi-axis [µm]",
    );
    for (c, r) in result.nodes.iter().enumerate() {
        fig.series.push(
            Series::new(result.speeds_hz.clone(), um(&r.major))
                .label(format!("node {} (z {:.3} m)", r.node, r.z))
                .style(Style::solid(Colour::Palette(c))),
        );
        for p in &r.peaks {
            let af = p
                .amplification_factor
                .map_or(String::new(), |a| format!(", AF {a:.1}"));
            fig.annotations.push(
                Annotation::new(
                    p.speed_hz,
                    1e6 * p.amplitude,
                    format!("{:.1} Hz{af}", p.speed_hz),
                )
                .marked(),
            );
        }
    }
    fig.vertical_lines = operating_lines(result.operating_hz);
    // Headroom above the highest peak for its label and the operating-range labels.
    let top = result
        .nodes
        .iter()
        .flat_map(|r| r.major.iter().copied())
        .filter(|v| v.is_finite())
        .fold(0.0f64, f64::max);
    if top > 0.0 {
        fig.y_range = Some((0.0, 1.2e6 * top));
    }
    fig.legend = LegendPosition::MiddleRight;
    fig
}

#[cfg(test)]
mod tests {
    use super::*;

    fn crossing(speed_hz: f64, frequency_hz: f64, whirl: Whirl) -> CriticalSpeed {
        CriticalSpeed {
            speed_hz,
            speed_rpm: 60.0 * speed_hz,
            frequency_hz,
            order: frequency_hz / speed_hz,
            branch: 0,
            whirl,
            damping_ratio: 0.02,
        }
    }

    #[test]
    fn crossings_share_a_label_only_when_near_on_both_axes() {
        // The reference rotor's Campbell diagram over 0-800 Hz up to 1000 Hz: 3B and 3F
        // cross 2X at 233 and 235 Hz (470 Hz whirl); 2B and 2F cross 1X at 242 and 266 Hz
        // (250 Hz whirl), 2 % and 3 % of the span further: near in speed, far in frequency.
        let critical = [
            crossing(233.3, 466.7, Whirl::Backward),
            crossing(234.6, 469.1, Whirl::Forward),
            crossing(242.5, 242.5, Whirl::Backward),
            crossing(266.5, 266.5, Whirl::Forward),
            crossing(727.8, 727.8, Whirl::Backward),
            crossing(900.0, 1100.0, Whirl::Forward),
        ];
        let clusters = crossing_clusters(&critical, 800.0, 1000.0);
        let speeds: Vec<Vec<f64>> = clusters
            .iter()
            .map(|c| c.iter().map(|x| x.speed_hz).collect())
            .collect();
        assert_eq!(
            speeds,
            vec![vec![233.3, 234.6], vec![242.5, 266.5], vec![727.8]]
        );
    }
}
