//! The NSV map's figure: the unstable bands of the synchronous orbit over speed (x) and the
//! parameter (y), each band a thick bar coloured by the bifurcation that opens it; the
//! resonance lines on a stable orbit as open symbols on the value's row, and where a
//! cascade checked the map, its speeds with NSV at the check's level as dots just above.

use whirl::hbm::BifurcationKind;
use whirl::map::{Edge, Excitation, MapEntry, MapReport};
use whirl_plot::{Colour, Figure2d, LegendPosition, Marker, Series, Style};

use crate::kind_label;

/// Bar thickness of a band, px: thick enough to read its colour, thin enough that a dozen
/// values stay apart on the default figure.
const BAND_WIDTH: u32 = 12;

/// The map as a figure.
pub fn map_plot(report: &MapReport) -> Figure2d {
    let axis = ParameterAxis::of(report);
    let mut figure = Figure2d::new(
        "Unstable synchronous orbit (harmonic balance, Floquet)",
        "Spin speed [Hz]",
        axis.label.clone(),
    );
    figure.legend = LegendPosition::UpperLeft;
    let (from, to) = (
        whirl::units::rad_s_to_hz(report.options.from),
        whirl::units::rad_s_to_hz(report.options.to),
    );
    figure.x_range = Some((from.min(0.0), to));
    let (lo, hi) = axis
        .y
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &y| {
            (a.min(y), b.max(y))
        });
    // Half a bar's room above and below the outer values, and room for one value alone;
    // above the highest value, room for the legend (about a third of the plot's height),
    // so that it covers no row (below the lowest, the axis would show negative values of
    // a parameter that has none).
    let pad = if hi > lo { 0.08 * (hi - lo) } else { 1.0 };
    let legend_room = if hi > lo { 0.6 * (hi - lo) } else { 3.0 };
    figure.y_range = Some((lo - pad, hi + pad + legend_room));
    for (j, entry) in report.entries.iter().enumerate() {
        let y = axis.y[j];
        // The range swept, thin, so that a value without bands still shows it was computed.
        figure.series.push(
            Series::new(vec![from, to], vec![y, y]).style(Style::solid(Colour::GREY).width(1)),
        );
        for band in &entry.run.bands {
            let colour = colour_of(&band.opens);
            figure.series.push(
                Series::new(vec![band.span_hz[0], band.span_hz[1]], vec![y, y])
                    .style(Style::solid(colour).width(BAND_WIDTH)),
            );
        }
        draw_lines(&mut figure, entry, y);
        if let Some(check) = report.checks.iter().find(|c| c.value == entry.value.text) {
            let above = y + 0.4 * pad;
            figure.series.push(
                Series::new(
                    check.nsv_speeds_hz.clone(),
                    vec![above; check.nsv_speeds_hz.len()],
                )
                .style(Style::markers(Colour::BLACK, Marker::Circle)),
            );
        }
        if let Some(b) = entry.first_loss() {
            figure.series.push(
                Series::new(vec![whirl::units::rad_s_to_hz(b.frequency)], vec![y])
                    .style(Style::markers(Colour::BLACK, Marker::Triangle)),
            );
        }
    }
    legend(&mut figure, report);
    if let Some(w) = report.clear_below {
        figure.vertical_lines =
            vec![whirl_plot::RefLine::new(whirl::units::rad_s_to_hz(w)).label("clear below")];
    }
    figure
}

/// Symbols of the resonance lines on a stable orbit: the contact frequencies' (roller
/// passing, waviness) and the orbit's own (half the speed, sums and differences).
const CONTACT_LINE: (Colour, Marker) = (Colour::Palette(4), Marker::OpenCircle);
const ORBIT_LINE: (Colour, Marker) = (Colour::Palette(5), Marker::Cross);

/// The resonance lines of `entry` on a stable orbit, on its row `y`.
fn draw_lines(figure: &mut Figure2d, entry: &MapEntry, y: f64) {
    for (contact, (colour, marker)) in [(true, CONTACT_LINE), (false, ORBIT_LINE)] {
        let speeds: Vec<f64> = entry
            .run
            .lines
            .iter()
            .filter(|l| l.on_stable_orbit)
            .filter(|l| matches!(l.excitation, Excitation::Contact { .. }) == contact)
            .map(|l| l.speed_hz)
            .collect();
        let ys = vec![y; speeds.len()];
        figure
            .series
            .push(Series::new(speeds, ys).style(Style::markers(colour, marker)));
    }
}

/// Legend entries for the kinds that open a band here, and the first-loss marker.
fn legend(figure: &mut Figure2d, report: &MapReport) {
    let mut kinds: Vec<Edge> = Vec::new();
    for band in report.entries.iter().flat_map(|e| &e.run.bands) {
        if !kinds.iter().any(|k| k.name() == band.opens.name()) {
            kinds.push(band.opens);
        }
    }
    for kind in kinds {
        let label = match kind {
            Edge::Bifurcation { bifurcation, .. } => {
                format!("{} ({})", kind.name(), kind_label(bifurcation))
            }
            _ => format!("unstable from {}", kind.name()),
        };
        figure.series.push(
            Series::new(Vec::new(), Vec::new())
                .label(label)
                .style(Style::solid(colour_of(&kind)).width(BAND_WIDTH)),
        );
    }
    figure.series.push(
        Series::new(Vec::new(), Vec::new())
            .label("first loss of stability")
            .style(Style::markers(Colour::BLACK, Marker::Triangle)),
    );
    let lines = report.entries.iter().flat_map(|e| &e.run.lines);
    let (contact, orbit) = lines
        .filter(|l| l.on_stable_orbit)
        .fold((false, false), |(c, o), l| match l.excitation {
            Excitation::Contact { .. } => (true, o),
            _ => (c, true),
        });
    let entries = [
        (contact, "roller-passing or waviness line", CONTACT_LINE),
        (orbit, "0.5X, sum or difference line", ORBIT_LINE),
        (
            !report.checks.is_empty(),
            "cascade NSV at the check level",
            (Colour::BLACK, Marker::Circle),
        ),
    ];
    for (label, (colour, marker)) in entries.into_iter().filter(|e| e.0).map(|e| (e.1, e.2)) {
        figure.series.push(
            Series::new(Vec::new(), Vec::new())
                .label(label)
                .style(Style::markers(colour, marker)),
        );
    }
}

/// A band's colour, by what opens it.
fn colour_of(edge: &Edge) -> Colour {
    match edge {
        Edge::Bifurcation { bifurcation, .. } => match bifurcation {
            BifurcationKind::NeimarkSacker => Colour::Palette(3),
            BifurcationKind::PeriodDoubling => Colour::Palette(1),
            BifurcationKind::Fold => Colour::Palette(0),
            BifurcationKind::SymmetryBreaking => Colour::Palette(2),
        },
        Edge::BranchStart | Edge::BranchEnd | Edge::Jump => Colour::GREY,
    }
}

/// Where each value goes on the y axis: the number as written when every value shares one
/// unit (`20 um` at 20, labelled `[um]`), the SI number when they are numbers of mixed
/// units, or the value's position for words.
struct ParameterAxis {
    label: String,
    y: Vec<f64>,
}

impl ParameterAxis {
    fn of(report: &MapReport) -> ParameterAxis {
        let values: Vec<&whirl::map::MapValue> = report.entries.iter().map(|e| &e.value).collect();
        let split = |t: &str| {
            let t = t.trim();
            let end = t
                .find(|c: char| c.is_ascii_alphabetic() && c != 'e' && c != 'E')
                .unwrap_or(t.len());
            let (number, unit) = t.split_at(end);
            Some((number.trim().parse::<f64>().ok()?, unit.trim().to_string()))
        };
        let written: Option<Vec<(f64, String)>> = values.iter().map(|v| split(&v.text)).collect();
        if let Some(w) = written.filter(|w| w.iter().all(|(_, u)| *u == w[0].1)) {
            let unit = &w[0].1;
            let label = if unit.is_empty() {
                report.parameter.clone()
            } else {
                format!("{} [{unit}]", report.parameter)
            };
            return ParameterAxis {
                label,
                y: w.iter().map(|(x, _)| *x).collect(),
            };
        }
        if let Some(si) = values.iter().map(|v| v.si).collect::<Option<Vec<f64>>>() {
            return ParameterAxis {
                label: format!("{} [SI]", report.parameter),
                y: si,
            };
        }
        ParameterAxis {
            label: format!("{} (value number)", report.parameter),
            y: (0..values.len()).map(|j| j as f64).collect(),
        }
    }
}
