//! Figures of `whirl study`: the cascades of a sweep side by side (thesis figs. 5.1-5.9) and
//! the largest NSV versus the swept parameter with its fit (fig. 5.10).

use whirl::study::results::{CascadeMap, Metric, SweepResult};
use whirl::units::{parse_quantity, Dimension};
use whirl_plot::{
    Annotation, Colour, Figure2d, HeatMap, HeatMapGrid, LegendPosition, Marker, Series, Style,
};

/// Decades of amplitude below the sweep's largest that the colour scale spans: enough to
/// show an NSV a thousand times below the synchronous peak.
const COLOUR_DECADES: f64 = 3.0;

/// Most panels in a row of a sweep's cascades.
const MAX_COLUMNS: usize = 4;

/// The cascades of one sweep in rows of up to `MAX_COLUMNS`, one colour scale
/// (logarithmic) for all, the 1X and 0.5X lines drawn over them. A failed point (`None`)
/// gets empty axes titled as failed.
pub fn cascade_grid(sweep: &SweepResult, maps: &[Option<&CascadeMap>]) -> HeatMapGrid {
    let top = maps
        .iter()
        .flatten()
        .flat_map(|m| m.amplitude.iter().flatten().flatten())
        .fold(0.0f64, |a, &b| a.max(f64::from(b)));
    let range = (top > 0.0).then(|| (top * 10f64.powf(-COLOUR_DECADES), top));
    // Rows of at most four panels, so that a long sweep stays readable.
    let cols = maps.len().clamp(1, MAX_COLUMNS);
    let rows = maps.len().div_ceil(cols).max(1);
    let mut grid = HeatMapGrid::new(
        format!("{}: cascades (amplitude of the response, m)", sweep.name),
        rows,
        cols,
    );
    for (value, map) in sweep.values.iter().zip(maps) {
        let Some(map) = map else {
            // Empty axes that say so, rather than a gap that could be a drawing fault.
            let title = format!("{value}: cascade failed (see points.csv)");
            let empty = HeatMap::new(title, "Speed [Hz]", "Frequency [Hz]", "Amplitude [m]");
            grid.panels.push(Some(empty));
            continue;
        };
        let mut panel = HeatMap::new(value, "Speed [Hz]", "Frequency [Hz]", "Amplitude [m]")
            .with_data(
                map.speeds_hz.clone(),
                map.frequencies_hz.clone(),
                map.amplitude
                    .iter()
                    .map(|row| row.iter().map(|a| a.map_or(f64::NAN, f64::from)).collect())
                    .collect(),
            );
        panel.log_colour = true;
        panel.z_range = range;
        for (order, label) in [(1.0, "1X"), (0.5, "0.5X")] {
            let y = map.speeds_hz.iter().map(|s| order * s).collect();
            panel.overlays.push(
                Series::new(map.speeds_hz.clone(), y)
                    .label(label)
                    .style(Style::dashed(Colour::Rgb(255, 255, 255))),
            );
        }
        grid.panels.push(Some(panel));
    }
    grid
}

/// A swept model path in words for an axis, with the SI unit of its plain numbers (empty for
/// counts and words): `roller_bearing[*].clearance` is "Radial clearance, every roller
/// bearing", m.
fn parameter_words(path: &str) -> (String, &'static str) {
    let (owner, field) = path.rsplit_once('.').unwrap_or(("", path));
    let (what, unit) = match field {
        "clearance" => ("Radial clearance".to_string(), "m"),
        "rollers" => ("Number of rollers".to_string(), ""),
        "eccentricity" => ("Unbalance eccentricity".to_string(), "m"),
        "mass_radius" => ("Unbalance (mass x radius)".to_string(), "kg m"),
        "contact" => ("Contact law".to_string(), ""),
        "contact_stiffness" => ("Contact stiffness".to_string(), "N/m^(10/9)"),
        "density" => ("Density".to_string(), "kg/m^3"),
        "young_modulus" => ("Young's modulus".to_string(), "Pa"),
        other => (capitalised(&other.replace('_', " ")), "SI"),
    };
    let whose = match owner.split_once('[') {
        Some((kind, "*]")) => format!(", every {}", kind.replace('_', " ")),
        Some((kind, index)) => format!(
            ", {} {}",
            kind.replace('_', " "),
            index.trim_end_matches(']')
        ),
        None if owner == "cascade" => ", cascade".to_string(),
        None => String::new(),
    };
    (format!("{what}{whose}"), unit)
}

fn capitalised(text: &str) -> String {
    let mut chars = text.chars();
    chars
        .next()
        .map_or_else(String::new, |c| c.to_uppercase().chain(chars).collect())
}

/// The study's NSV metric versus the swept parameter, with the fitted polynomial, and the
/// largest NSV beside it. Lengths are drawn in µm; other numbers in SI; words (contact
/// laws) at positions 1, 2, ... with their names.
pub fn nsv_versus_parameter(sweep: &SweepResult, metric: Metric) -> Figure2d {
    // Quantities written with a length unit; a bare number could be anything.
    let lengths = sweep
        .values
        .iter()
        .all(|v| parse_quantity(v, Dimension::Length).is_ok() && v.parse::<f64>().is_err());
    let numeric = sweep.values_si.iter().all(Option::is_some);
    let (words, si_unit) = parameter_words(&sweep.parameter);
    let (scale, x_label) = if lengths {
        (1e6, format!("{words} [µm]"))
    } else if numeric && !si_unit.is_empty() {
        (1.0, format!("{words} [{si_unit}]"))
    } else {
        (1.0, words)
    };
    let x: Vec<f64> = if numeric {
        sweep
            .values_si
            .iter()
            .map(|v| v.unwrap_or(f64::NAN) * scale)
            .collect()
    } else {
        (1..=sweep.values.len()).map(|k| k as f64).collect()
    };
    let micrometres = |values: &[Option<f64>]| -> Vec<f64> {
        values
            .iter()
            .map(|a| a.map_or(f64::NAN, |a| a * 1e6))
            .collect()
    };
    let y = micrometres(&sweep.metric_nsv);
    let mut fig = Figure2d::new(
        format!("{}: {}", sweep.name, metric.describe()),
        x_label,
        "NSV [µm]",
    );
    // The largest NSV grows with most parameters: the lower right corner is the free one.
    fig.legend = LegendPosition::LowerRight;
    fig.series.push(
        Series::new(x.clone(), y.clone())
            .label(metric.name())
            .style(Style::markers(Colour::Palette(0), Marker::Circle)),
    );
    if metric != Metric::Largest {
        fig.series.push(
            Series::new(x.clone(), micrometres(&sweep.largest_nsv))
                .label("largest")
                .style(Style::markers(Colour::Palette(1), Marker::OpenCircle)),
        );
    }
    if let Some(fit) = &sweep.fit {
        let (lo, hi) = x
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        let xs: Vec<f64> = (0..=100)
            .map(|i| lo + (hi - lo) * i as f64 / 100.0)
            .collect();
        let ys = xs.iter().map(|&v| fit.at(v / scale) * 1e6).collect();
        fig.series.push(
            Series::new(xs, ys)
                .label(format!("least-squares fit, R² = {:.4}", fit.r_squared))
                .style(Style::solid(Colour::Palette(1))),
        );
    }
    if !numeric {
        for ((xi, yi), v) in x.iter().zip(&y).zip(&sweep.values) {
            fig.annotations.push(Annotation::new(*xi, *yi, v.clone()));
        }
    }
    fig
}

#[cfg(test)]
mod tests {
    use super::parameter_words;

    #[test]
    fn swept_paths_read_as_words() {
        assert_eq!(
            parameter_words("roller_bearing[*].clearance"),
            ("Radial clearance, every roller bearing".to_string(), "m")
        );
        assert_eq!(
            parameter_words("unbalance[0].eccentricity"),
            ("Unbalance eccentricity, unbalance 0".to_string(), "m")
        );
        assert_eq!(
            parameter_words("roller_bearing[1].rollers"),
            ("Number of rollers, roller bearing 1".to_string(), "")
        );
        assert_eq!(
            parameter_words("cascade.settle_max"),
            ("Settle max, cascade".to_string(), "SI")
        );
    }
}
