//! Figures of a cascade: the waterfall (thesis figs. 5.1-5.9), the colour map seen from
//! above, the NSV amplitude over speed, and the full-spectrum map.
//!
//! Order lines (1X, 2X, 0.5X) and the first roller bearing's characteristic frequencies
//! (FTF, BPFO = N_b w_c, BPFI, BSF) are drawn on the waterfall and the maps, dashed. Amplitudes are drawn on a logarithmic scale over
//! [`DECADES`] decades below the largest: on a linear one the 1X near a critical speed
//! would flatten every non-synchronous peak into the baseline.

use whirl::nsv::{Cascade, CascadePoint, Component, NsvClass, StartComparison, WhirlDirection};
use whirl::time::Initial;
use whirl_plot::{Colour, Figure2d, HeatMap, LegendPosition, Marker, RefLine, Series, Style};

/// Decades of amplitude below the largest that the waterfall and the maps show.
const DECADES: f64 = 4.0;

/// Height of one waterfall trace's full scale, in steps between drawn traces: traces
/// overlap a little, as in a printed waterfall.
const TRACE_HEIGHT: f64 = 3.0;

/// At most this many traces in the waterfall (every k-th speed; the maps show them all):
/// more merge into a solid block.
const MAX_TRACES: usize = 60;

/// Orders of the running speed drawn as lines.
const ORDERS: [f64; 3] = [0.5, 1.0, 2.0];

/// `ux` or `uy`.
fn component(c: &Cascade) -> &'static str {
    match c.options.component {
        Component::Ux => "ux",
        Component::Uy => "uy",
    }
}

/// The completed points in ascending speed, each speed once.
fn ascending(c: &Cascade) -> Vec<&CascadePoint> {
    let mut points: Vec<&CascadePoint> = c.points.iter().filter(|p| p.diverged.is_none()).collect();
    points.sort_by(|a, b| a.speed_hz.total_cmp(&b.speed_hz));
    points.dedup_by(|a, b| a.speed_hz == b.speed_hz);
    points
}

/// The largest amplitude of the completed points, m.
fn largest(points: &[&CascadePoint]) -> f64 {
    points
        .iter()
        .flat_map(|p| p.amplitude.iter().copied())
        .fold(0.0, f64::max)
}

/// The lines f = k Omega (`sign` -1 draws them at negative frequency) and the first roller
/// bearing's characteristic frequencies (FTF, BPFO = N_b w_c, BPFI, BSF), as (speed, frequency) curves over `speeds`; `swap` puts frequency on x.
fn order_lines(c: &Cascade, speeds: &[f64], sign: f64, swap: bool) -> Vec<Series> {
    let curve = |f: Vec<f64>| {
        if swap {
            Series::new(f, speeds.to_vec())
        } else {
            Series::new(speeds.to_vec(), f)
        }
    };
    let mut lines: Vec<Series> = ORDERS
        .iter()
        .enumerate()
        .map(|(i, &k)| {
            curve(speeds.iter().map(|s| sign * k * s).collect())
                .label(format!("{k}X"))
                .style(Style::dashed(Colour::Palette(i + 1)).width(1))
        })
        .collect();
    // The first roller bearing's characteristic lines: the cage speed is proportional to
    // the spin speed, so each is an order line.
    let bearing = c.bearing_orders.first().map(|b| b.orders.lines());
    for (i, (name, order)) in bearing.into_iter().flatten().enumerate() {
        lines.push(
            curve(speeds.iter().map(|s| sign * order * s).collect())
                .label(name)
                .style(Style::dashed(Colour::Palette(4 + i)).width(1)),
        );
    }
    lines
}

/// Spectra stacked along speed: each trace at its speed, rising by log amplitude.
pub fn waterfall(c: &Cascade) -> Figure2d {
    let all = ascending(c);
    let top = largest(&all);
    let floor = top * 10f64.powf(-DECADES);
    let speeds: Vec<f64> = all.iter().map(|p| p.speed_hz).collect();
    let every = all.len().div_ceil(MAX_TRACES).max(1);
    let points: Vec<&CascadePoint> = all.iter().step_by(every).copied().collect();
    let span = speeds.last().copied().unwrap_or(1.0) - speeds.first().copied().unwrap_or(0.0);
    let height = TRACE_HEIGHT * span / (points.len().max(2) - 1) as f64;
    let mut fig = Figure2d::new(
        format!(
            "Waterfall of node {} {}: each trace spans {DECADES} decades of amplitude up to \
             {:.3e} m",
            c.options.node,
            component(c),
            top
        ),
        "Frequency [Hz]",
        "Speed [Hz] (trace: log amplitude)",
    );
    // From the back (highest speed) to the front, so nearer traces are drawn over.
    for p in points.iter().rev() {
        let y = p
            .amplitude
            .iter()
            .map(|&a| p.speed_hz + height * ((a.max(floor) / floor).log10() / DECADES))
            .collect();
        fig.series.push(
            Series::new(c.frequency_hz.clone(), y)
                .style(Style::solid(Colour::Rgb(40, 40, 90)).width(1)),
        );
    }
    fig.series.extend(order_lines(c, &speeds, 1.0, true));
    fig.x_range = Some((0.0, c.resolved.max_frequency_hz));
    fig.legend = LegendPosition::LowerRight;
    fig
}

/// Top of the maps' frequency axis as a multiple of the highest speed: the band the
/// cascade searches reaches to the contact frequencies (3.4 kHz on the reference rotor),
/// where a 50 Hz whip is a sliver at the bottom edge; twice the speed keeps 1X, 2X and
/// everything below them.
const MAP_TOP_ORDER: f64 = 2.0;

/// The default top of the maps' frequency axis, Hz: `MAP_TOP_ORDER` times the highest
/// speed, within the band computed.
pub fn default_map_top_hz(c: &Cascade) -> f64 {
    let fastest = c.points.iter().map(|p| p.speed_hz).fold(0.0, f64::max);
    (MAP_TOP_ORDER * fastest).min(c.resolved.max_frequency_hz)
}

/// A heat map of `column(point)` over the completed speeds, log colour over [`DECADES`],
/// for the frequencies within `top_hz` of zero.
fn map(
    c: &Cascade,
    frequency_hz: &[f64],
    top_hz: f64,
    column: impl Fn(&CascadePoint) -> &[f64],
) -> HeatMap {
    let points = ascending(c);
    let speeds: Vec<f64> = points.iter().map(|p| p.speed_hz).collect();
    let rows: Vec<usize> = (0..frequency_hz.len())
        .filter(|&j| frequency_hz[j].abs() <= top_hz)
        .collect();
    let z: Vec<Vec<f64>> = rows
        .iter()
        .map(|&j| {
            points
                .iter()
                .map(|p| column(p).get(j).copied().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    let top = points
        .iter()
        .flat_map(|p| column(p).iter().copied())
        .fold(0.0, f64::max);
    let mut m = HeatMap::new(
        format!(
            "Cascade of node {} {} (colour: log amplitude)",
            c.options.node,
            component(c)
        ),
        "Speed [Hz]",
        "Frequency [Hz]",
        "Amplitude [m]",
    )
    .with_data(speeds, rows.iter().map(|&j| frequency_hz[j]).collect(), z);
    m.log_colour = true;
    if top > 0.0 {
        m.z_range = Some((top * 10f64.powf(-DECADES), top));
    }
    m.legend = LegendPosition::UpperLeft;
    m
}

/// Frequency up to `top_hz` over speed, colour = log amplitude; order lines; the NSV peaks
/// at or above `threshold` (m) marked.
pub fn cascade_map(c: &Cascade, threshold: f64, top_hz: f64) -> HeatMap {
    let mut m = map(c, &c.frequency_hz, top_hz, |p| &p.amplitude);
    m.overlays = order_lines(c, &m.x, 1.0, false);
    let (x, y): (Vec<f64>, Vec<f64>) = c
        .nsv
        .iter()
        .flatten()
        .filter(|n| n.peak.amplitude_m >= threshold && n.class.is_steady())
        .map(|n| (n.speed_hz, n.peak.frequency_hz))
        .unzip();
    m.overlays.push(
        Series::new(x, y)
            .label("NSV >= threshold")
            .style(Style::markers(Colour::Rgb(255, 255, 255), Marker::OpenCircle).marker_size(5)),
    );
    m
}

/// The full spectrum of x + i y over speed, frequencies within `top_hz` of zero: forward
/// whirl above zero, backward below.
pub fn full_map(c: &Cascade, top_hz: f64) -> HeatMap {
    let mut m = map(c, &c.full_frequency_hz, top_hz, |p| &p.full_amplitude);
    m.title = format!(
        "Full spectrum of node {}: forward whirl above 0 Hz, backward below",
        c.options.node
    );
    m.overlays = order_lines(c, &m.x, 1.0, false);
    m.overlays.extend(
        order_lines(c, &m.x, -1.0, false)
            .into_iter()
            .map(|s| Series { label: None, ..s }),
    );
    m
}

/// 1X and the NSV amplitude over speed, NSV by class; the threshold as a line.
/// The NSV over speed from both starts, the speeds where they differ (coexisting motions)
/// ringed.
pub fn nsv_from_both_starts(c: &Cascade, starts: &StartComparison, threshold: f64) -> Figure2d {
    let mut fig = Figure2d::new(
        format!(
            "Largest non-synchronous vibration from two starts, node {} {}",
            c.options.node,
            component(c)
        ),
        "Speed [Hz]",
        "Amplitude [µm]",
    );
    let comparable = || starts.pairs.iter().filter(|p| p.comparable);
    let line = |f: fn(&whirl::nsv::StartPair) -> f64| -> (Vec<f64>, Vec<f64>) {
        comparable().map(|p| (p.speed_hz, 1e6 * f(p))).unzip()
    };
    let (x, y) = line(|p| p.first_m);
    fig.series.push(
        Series::new(x, y)
            .label(format!("from {}", start_label(c.options.initial)))
            .style(Style::solid(Colour::Palette(0))),
    );
    let (x, y) = line(|p| p.other_m);
    fig.series.push(
        Series::new(x, y)
            .label(format!("from {}", start_label(starts.other)))
            .style(Style::dashed(Colour::Palette(1))),
    );
    let (x, y): (Vec<f64>, Vec<f64>) = starts
        .pairs
        .iter()
        .filter(|p| p.differs)
        .map(|p| (p.speed_hz, 1e6 * p.first_m.max(p.other_m)))
        .unzip();
    rings_on_a_log_scale(fig, x, y, "differ beyond 3 standard errors", threshold)
}

/// Rings the speeds `x` at NSV `y` (um) with `label`, and finishes an NSV-over-speed figure:
/// logarithmic amplitude, the threshold drawn, the legend below right.
fn rings_on_a_log_scale(
    mut fig: Figure2d,
    x: Vec<f64>,
    y: Vec<f64>,
    label: &str,
    threshold: f64,
) -> Figure2d {
    if !x.is_empty() {
        fig.series.push(
            Series::new(x, y)
                .label(label)
                .style(Style::markers(Colour::BLACK, Marker::OpenCircle).marker_size(6)),
        );
    }
    fig.log_y = true;
    fig.horizontal_lines
        .push(RefLine::new(1e6 * threshold).label("threshold"));
    fig.legend = LegendPosition::LowerRight;
    fig
}

fn start_label(start: Initial) -> &'static str {
    match start {
        Initial::StaticEquilibrium => "static equilibrium",
        Initial::Rest => "rest",
    }
}

/// The largest non-synchronous amplitude over speed, with the threshold that calls it NSV.
pub fn nsv_amplitude(c: &Cascade, threshold: f64) -> Figure2d {
    let mut fig = Figure2d::new(
        format!(
            "Largest non-synchronous vibration at node {} {}",
            c.options.node,
            component(c)
        ),
        "Speed [Hz]",
        "Amplitude [µm]",
    );
    let points = ascending(c);
    fig.series.push(
        Series::new(
            points.iter().map(|p| p.speed_hz).collect(),
            points.iter().map(|p| 1e6 * p.one_x_m).collect(),
        )
        .label("1X")
        .style(Style::solid(Colour::GREY)),
    );
    for class in NsvClass::ALL.iter() {
        let (x, y): (Vec<f64>, Vec<f64>) = c
            .nsv
            .iter()
            .flatten()
            .filter(|n| n.class == *class)
            .map(|n| (n.speed_hz, 1e6 * n.peak.amplitude_m))
            .unzip();
        if !x.is_empty() {
            fig.series.push(
                Series::new(x, y)
                    .label(class.name())
                    .style(class_style(*class)),
            );
        }
    }
    let (x, y): (Vec<f64>, Vec<f64>) = c
        .points
        .iter()
        .zip(&c.nsv)
        .filter(|(p, _)| p.added)
        .filter_map(|(p, n)| n.as_ref().map(|n| (p.speed_hz, 1e6 * n.peak.amplitude_m)))
        .unzip();
    rings_on_a_log_scale(fig, x, y, "added by refinement", threshold)
}

/// A class's markers: the colour names the mechanism (seven, one palette entry each), the
/// symbol the whirl (circle forward or undirected, triangle backward, square planar), so
/// no two of the thirteen classes look alike.
fn class_style(class: NsvClass) -> Style {
    let (mechanism, direction) = match class {
        NsvClass::Subharmonic(d) => (0, Some(d)),
        NsvClass::VaryingCompliance => (1, None),
        NsvClass::Whip(d) => (2, Some(d)),
        NsvClass::CombinationResonance(d) => (3, Some(d)),
        NsvClass::SuperHarmonic => (4, None),
        NsvClass::Other => (5, None),
        NsvClass::Unsettled => (6, None),
    };
    let marker = match direction {
        Some(WhirlDirection::Backward) => Marker::Triangle,
        Some(WhirlDirection::Planar) => Marker::Square,
        _ => Marker::Circle,
    };
    Style::markers(Colour::Palette(mechanism), marker).marker_size(4)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_two_classes_are_drawn_alike() {
        let styles: Vec<Style> = NsvClass::ALL.iter().map(|&c| class_style(c)).collect();
        for (i, a) in styles.iter().enumerate() {
            for (j, b) in styles.iter().enumerate().skip(i + 1) {
                assert_ne!(
                    a,
                    b,
                    "{} and {}",
                    NsvClass::ALL[i].name(),
                    NsvClass::ALL[j].name()
                );
            }
        }
    }
}
