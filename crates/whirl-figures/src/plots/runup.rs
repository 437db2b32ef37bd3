//! Figures of a run-up: the time-frequency cascade of each sweep beside the steady cascade,
//! and 1X and NSV over speed for both directions and the steady states, with the hysteresis
//! bands and the speeds of coexisting steady motions marked.

use whirl::runup::{Quantity, Runup, SweepResult};
use whirl_plot::{
    Colour, Figure2d, HeatMap, HeatMapGrid, LegendPosition, Marker, RefLine, Series, Style,
};

use super::cascade::cascade_map;

/// Decades of amplitude below the largest that the maps show (as the cascade's).
const DECADES: f64 = 4.0;

/// Orders of the running speed drawn on the maps.
const ORDERS: [f64; 3] = [0.5, 1.0, 2.0];

/// One sweep's short-time spectra: frequency up to `top_hz` over speed (ascending),
/// colour = log amplitude over [`DECADES`] below `top_m`; the order lines drawn.
fn sweep_map(r: &Runup, s: &SweepResult, top_hz: f64, top_m: f64) -> HeatMap {
    let mut windows: Vec<_> = s
        .windows
        .iter()
        .filter(|w| !w.amplitude.is_empty())
        .collect();
    windows.sort_by(|a, b| a.speed_hz.total_cmp(&b.speed_hz));
    let speeds: Vec<f64> = windows.iter().map(|w| w.speed_hz).collect();
    let rows: Vec<usize> = (0..r.frequency_hz.len())
        .filter(|&j| r.frequency_hz[j] <= top_hz)
        .collect();
    let z = rows
        .iter()
        .map(|&j| {
            windows
                .iter()
                .map(|w| w.amplitude.get(j).copied().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    let title = match s.sweep {
        whirl::runup::Sweep::Up => "Run-up",
        whirl::runup::Sweep::Down => "Coast-down",
    };
    let mut m = HeatMap::new(
        format!(
            "{title} at {:.3} Hz/s, {:.3} s windows",
            r.options.rate_hz_per_s(),
            r.resolved.window_s
        ),
        "Speed [Hz]",
        "Frequency [Hz]",
        "Amplitude [m]",
    )
    .with_data(
        speeds.clone(),
        rows.iter().map(|&j| r.frequency_hz[j]).collect(),
        z,
    );
    m.log_colour = true;
    if top_m > 0.0 {
        m.z_range = Some((top_m * 10f64.powf(-DECADES), top_m));
    }
    m.overlays = ORDERS
        .iter()
        .enumerate()
        .map(|(i, &k)| {
            Series::new(speeds.clone(), speeds.iter().map(|s| k * s).collect())
                .label(format!("{k}X"))
                .style(Style::dashed(Colour::Palette(i + 1)).width(1))
        })
        .collect();
    m.legend = LegendPosition::UpperLeft;
    m
}

/// The sweeps' time-frequency cascades beside the steady cascade, one colour scale, up to
/// `top_hz`.
pub fn runup_maps(r: &Runup, top_hz: f64) -> HeatMapGrid {
    let top_m = r
        .sweeps
        .iter()
        .flat_map(|s| s.windows.iter().flat_map(|w| w.amplitude.iter().copied()))
        .fold(0.0, f64::max);
    let mut panels: Vec<Option<HeatMap>> = r
        .sweeps
        .iter()
        .map(|s| Some(sweep_map(r, s, top_hz, top_m)))
        .collect();
    if let Some(c) = &r.steady {
        let mut m = cascade_map(c, r.options.threshold_m, top_hz);
        m.title = "Steady cascade".into();
        m.z_range = Some((top_m * 10f64.powf(-DECADES), top_m));
        panels.push(Some(m));
    }
    let mut grid = HeatMapGrid::new(
        format!(
            "Time-frequency cascade of node {} beside the steady cascade (colour: log amplitude)",
            r.options.cascade.node
        ),
        1,
        panels.len(),
    );
    grid.panels = panels;
    grid
}

/// 1X and NSV over speed: each sweep (lines), the steady cascade (markers), the hysteresis
/// bands (vertical lines at their edges) and the steady speeds with coexisting motions
/// (rings).
pub fn runup_amplitudes(r: &Runup) -> Figure2d {
    let mut fig = Figure2d::new(
        format!(
            "1X and NSV of node {} in run-up and coast-down at {:.3} Hz/s, and steady",
            r.options.cascade.node,
            r.options.rate_hz_per_s()
        ),
        "Speed [Hz]",
        "Amplitude [µm]",
    );
    for (i, s) in r.sweeps.iter().enumerate() {
        let x: Vec<f64> = s.windows.iter().map(|w| w.speed_hz).collect();
        let name = s.sweep.name();
        fig.series.push(
            Series::new(
                x.clone(),
                s.windows.iter().map(|w| 1e6 * w.one_x_m).collect(),
            )
            .label(format!("1X {name}"))
            .style(Style::solid(Colour::Palette(2 * i))),
        );
        fig.series.push(
            Series::new(x, s.windows.iter().map(|w| 1e6 * w.nsv_m()).collect())
                .label(format!("NSV {name}"))
                .style(Style::dashed(Colour::Palette(2 * i + 1))),
        );
    }
    if let Some(c) = &r.steady {
        let points: Vec<_> = c.points.iter().filter(|p| p.diverged.is_none()).collect();
        let x: Vec<f64> = points.iter().map(|p| p.speed_hz).collect();
        fig.series.push(
            Series::new(x.clone(), points.iter().map(|p| 1e6 * p.one_x_m).collect())
                .label("1X steady")
                .style(Style::markers(Colour::BLACK, Marker::Circle).marker_size(3)),
        );
        fig.series.push(
            Series::new(
                x,
                points
                    .iter()
                    .map(|p| 1e6 * p.peak.map_or(0.0, |n| n.amplitude_m))
                    .collect(),
            )
            .label("NSV steady")
            .style(Style::markers(Colour::GREY, Marker::Circle).marker_size(3)),
        );
    }
    if let Some(h) = r.hysteresis() {
        for b in h.bands.iter().filter(|b| b.quantity == Quantity::Nsv) {
            fig.vertical_lines
                .push(RefLine::new(b.low_hz).label(format!("NSV band {:.0}", b.low_hz)));
            fig.vertical_lines.push(RefLine::new(b.high_hz));
        }
        let (x, y): (Vec<f64>, Vec<f64>) = h
            .flagged
            .iter()
            .map(|f| (f.speed_hz, 1e6 * f.steady_first_m.max(f.steady_other_m)))
            .unzip();
        if !x.is_empty() {
            fig.series.push(
                Series::new(x, y)
                    .label("steady: two motions")
                    .style(Style::markers(Colour::BLACK, Marker::OpenCircle).marker_size(7)),
            );
        }
    }
    fig.log_y = true;
    fig.horizontal_lines
        .push(RefLine::new(1e6 * r.options.threshold_m).label("threshold"));
    fig.legend = LegendPosition::LowerRight;
    fig
}
