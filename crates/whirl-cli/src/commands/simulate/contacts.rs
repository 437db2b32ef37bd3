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

use whirl::post::SpectralPeak;
use whirl::time::{FrequencyCheck, SimulationReport};

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
