//! The roller-bearing outputs of `whirl simulate`: per bearing, what the rollers did
//! (docs/theory.md
//! section 6, thesis figs. 4.7 and 4.9) and whether the spectrum shows the frequencies they
//! excite, N_b w_c and (N_w - 1) w_c (eqs. 4.4-4.5).
//!
//! - `contacts_<bearing>.csv` (a table of the library's report): `time_s`, `in_contact` (rollers carrying load), then each
//!   roller's force `roller_<j>_force_n` (N) and approach `roller_<j>_approach_m` (m,
//!   positive = penetration), rollers numbered from 0 as the model's `cage_angle` counts
//!   them. The forcing-function law has no per-roller forces: those cells are empty.
//! - `contact_line_<bearing>` (png, svg): roller index versus time, a thick bar where the
//!   roller is in contact, over the first [`whirl::time::CONTACT_LINE_CAGE_TURNS`] cage revolutions of
//!   the settled part.
//! - `contact_zone_<bearing>`: roller force versus roller angle over the settled part.
//! - `load_zone_<bearing>`: the same as a polar load zone around the bearing, with the
//!   largest load of each 5-degree sector as its outline.
//! - summary.json `bearings`: rollers in contact (most, fewest, mean), largest penetration
//!   and roller force over the settled part and over the whole run, and each predicted
//!   frequency with the largest spectral peak of the bearing node's channels within
//!   [`whirl::time::MATCH_BINS`] bins of it.
//!
//! `<bearing>` is the bearing's name in lower case with every run of other characters than
//! letters and digits made one `_` (`bearing A` -> `bearing_a`), numbered when two names
//! would collide.

use std::fmt::Write;

use whirl::model::Model;
use whirl::post::SpectralPeak;
use whirl::time::{BearingReport, FrequencyCheck, SimulationReport};
use whirl_plot::{Colour, RefLine};

use crate::output::Output;
use whirl_figures::plots;

/// The peak of a check with the largest amplitude over the node's channels.
fn best(check: &FrequencyCheck) -> Option<(&str, SpectralPeak)> {
    check
        .measured
        .iter()
        .filter_map(|(c, p)| p.map(|p| (c.as_str(), p)))
        .max_by(|a, b| a.1.amplitude.total_cmp(&b.1.amplitude))
}

/// Lines of the text summary.
pub fn text(t: &mut String, report: &SimulationReport) {
    for b in &report.bearings {
        let record = report.record(b);
        let s = &b.settled;
        let force = if record.has_forces() {
            format!("largest roller force {:.1} N", s.largest_force)
        } else {
            "no per-roller forces (forcing-function law)".into()
        };
        // Micrometres for Hertz contacts; round-off (Lagrange) in metres.
        let penetration = if s.largest_penetration.abs() >= 1e-9 {
            format!("{:.3} um", 1e6 * s.largest_penetration)
        } else {
            format!("{:.1e} m", s.largest_penetration)
        };
        let _ = writeln!(
            t,
            "  {} (n{}): {}-{} of {} rollers in contact (mean {:.2}), largest penetration \
             {penetration}, {force}",
            record.name,
            record.node,
            s.min_in_contact,
            s.max_in_contact,
            record.rollers,
            s.mean_in_contact,
        );
        for f in &b.frequencies {
            let measured = best(f).map_or("no peak within 3 bins".into(), |(c, p)| {
                format!(
                    "peak at {:.3} Hz in {c} ({:+.2} bins of {:.3} Hz), {:.3e} m",
                    p.frequency_hz,
                    (p.frequency_hz - f.predicted.frequency_hz) / b.resolution_hz,
                    b.resolution_hz,
                    p.amplitude
                )
            });
            let _ = writeln!(
                t,
                "    {} {:.3} Hz: {measured}",
                f.predicted.source, f.predicted.frequency_hz
            );
        }
    }
}

/// The contact line and zone plots of each bearing (its `contacts_<bearing>.csv` is a table
/// of the report).
pub fn plot(out: &mut Output, report: &SimulationReport) -> miette::Result<()> {
    let result = &report.result;
    for b in &report.bearings {
        let r = report.record(b);
        out.plot(&format!("contact_line_{}", b.stem), |stem| {
            plots::contact_line(r, &result.time, b.line_window.clone()).save(stem)
        })?;
        out.plot(&format!("contact_zone_{}", b.stem), |stem| {
            plots::contact_zone(r, b.settled_range.clone(), b.clearance).save(stem)
        })?;
        out.plot(&format!("load_zone_{}", b.stem), |stem| {
            plots::load_zone(r, b.settled_range.clone()).save(stem)
        })?;
    }
    Ok(())
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
