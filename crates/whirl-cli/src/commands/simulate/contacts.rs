//! The roller-bearing outputs of `whirl simulate`: per bearing, what the rollers did
//! (docs/theory.md
//! section 6, thesis figs. 4.7 and 4.9) and whether the spectrum shows the frequencies they
//! excite, N_b w_c and (N_w - 1) w_c (eqs. 4.4-4.5).
//!
//! - `contacts_<bearing>.csv`: `time_s`, `in_contact` (rollers carrying load), then each
//!   roller's force `roller_<j>_force_n` (N) and approach `roller_<j>_approach_m` (m,
//!   positive = penetration), rollers numbered from 0 as the model's `cage_angle` counts
//!   them. The forcing-function law has no per-roller forces: those cells are empty.
//! - `contact_line_<bearing>` (png, svg): roller index versus time, a thick bar where the
//!   roller is in contact, over the first [`CONTACT_LINE_CAGE_TURNS`] cage revolutions of
//!   the settled part.
//! - `contact_zone_<bearing>`: roller force versus roller angle over the settled part.
//! - `load_zone_<bearing>`: the same as a polar load zone around the bearing, with the
//!   largest load of each 5-degree sector as its outline.
//! - summary.json `bearings`: rollers in contact (most, fewest, mean), largest penetration
//!   and roller force over the settled part and over the whole run, and each predicted
//!   frequency with the largest spectral peak of the bearing node's channels within
//!   [`MATCH_BINS`] bins of it.
//!
//! `<bearing>` is the bearing's name in lower case with every run of other characters than
//! letters and digits made one `_` (`bearing A` -> `bearing_a`), numbered when two names
//! would collide.

use std::f64::consts::PI;
use std::fmt::Write;
use std::ops::Range;

use serde_json::{json, Value};
use whirl::bearing::{contact_frequencies, ContactFrequency};
use whirl::model::Model;
use whirl::post::SpectralPeak;
use whirl::time::{peak_near, ContactSummary, RollerRecord, SimulationResult};
use whirl_plot::{Colour, RefLine};

use crate::output::{num, Output};
use crate::plots;
use whirl::time::SettledChannel;

/// A predicted frequency is matched with the largest spectral peak within this many bins.
/// The flat-top window's main lobe spans +-5 bins, so a component shows as a local maximum
/// within one bin of its frequency; 3 leaves room to see (in `offset_bins`) how far off a
/// peak is without reaching a neighbouring component's lobe.
pub const MATCH_BINS: f64 = 3.0;

/// The contact line spans this many cage revolutions: each roller passes the loaded zone
/// this often.
pub const CONTACT_LINE_CAGE_TURNS: f64 = 3.0;

/// A predicted contact frequency and the peaks measured near it.
pub struct FrequencyCheck {
    /// What excites it and where it should be.
    pub predicted: ContactFrequency,
    /// Per channel of the bearing's node: the channel and the peak found, if any.
    pub measured: Vec<(String, Option<SpectralPeak>)>,
}

/// What one roller bearing did.
pub struct BearingReport<'a> {
    /// Its record.
    pub record: &'a RollerRecord,
    /// File-name stem, `bearing_a`.
    pub stem: String,
    /// Clearance at the final speed, m.
    pub clearance: f64,
    /// Statistics over the settled part.
    pub settled: ContactSummary,
    /// Statistics over the whole run.
    pub whole: ContactSummary,
    /// Cage speed at the final speed, Hz.
    pub cage_hz: f64,
    /// Spectrum bin width, Hz.
    pub resolution_hz: f64,
    /// Contact frequencies and the peaks that show them.
    pub frequencies: Vec<FrequencyCheck>,
    /// Samples of the contact line.
    pub line_window: Range<usize>,
    /// Samples of the contact zone (the settled part).
    pub settled_range: Range<usize>,
}

/// The longest slug, in characters: a name of any length must still make a file name
/// (`contacts_<slug>_zone.png`) within the 255 bytes most file systems allow.
const MAX_SLUG: usize = 64;

/// `bearing A` -> `bearing_a`, cut to [`MAX_SLUG`] characters.
fn slug(name: &str) -> String {
    let mut s = String::new();
    for c in name.chars().take(MAX_SLUG) {
        if c.is_ascii_alphanumeric() {
            s.push(c.to_ascii_lowercase());
        } else if !s.ends_with('_') {
            s.push('_');
        }
    }
    let s = s.trim_matches('_').to_string();
    if s.is_empty() {
        "bearing".into()
    } else {
        s
    }
}

/// File stems of `names`, numbered (`_2`, `_3`) where two would collide.
fn stems(names: &[&str]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for name in names {
        let base = slug(name);
        let mut stem = base.clone();
        let mut k = 2;
        while out.contains(&stem) {
            stem = format!("{base}_{k}");
            k += 1;
        }
        out.push(stem);
    }
    out
}

/// One report per roller bearing recorded; `speed` is the final spin speed, rad/s.
pub fn bearing_reports<'a>(
    model: &Model,
    result: &'a SimulationResult,
    reports: &[SettledChannel],
    speed: f64,
    running_hz: f64,
) -> Vec<BearingReport<'a>> {
    let names: Vec<&str> = result.rollers.iter().map(|r| r.name.as_str()).collect();
    let start = result.settled_start();
    let end = result.time.len();
    let resolution_hz = reports
        .first()
        .map_or(f64::NAN, |r| r.spectrum.resolution_hz);
    result
        .rollers
        .iter()
        .zip(stems(&names))
        .zip(&model.roller_bearings)
        .map(|((record, stem), bearing)| {
            let frequencies = contact_frequencies(bearing, speed)
                .into_iter()
                .map(|predicted| FrequencyCheck {
                    measured: reports
                        .iter()
                        .filter(|r| r.node == record.node)
                        .map(|r| {
                            let peak = peak_near(
                                &r.spectrum,
                                predicted.frequency_hz,
                                MATCH_BINS,
                                running_hz,
                            );
                            (r.name.clone(), peak)
                        })
                        .collect(),
                    predicted,
                })
                .collect();
            let cage_hz = record.cage_ratio * speed / (2.0 * PI);
            let line_end = if cage_hz > 0.0 {
                let span = CONTACT_LINE_CAGE_TURNS / cage_hz;
                start + result.time[start..].partition_point(|&t| t < result.time[start] + span)
            } else {
                end
            };
            BearingReport {
                record,
                stem,
                clearance: bearing.clearance.at_speed(speed),
                settled: record.summary(start..end),
                whole: record.summary(0..end),
                cage_hz,
                resolution_hz,
                frequencies,
                line_window: start..line_end.min(end),
                settled_range: start..end,
            }
        })
        .collect()
}

fn statistics(s: &ContactSummary) -> Value {
    json!({
        "samples": s.samples,
        "max_in_contact": s.max_in_contact,
        "min_in_contact": s.min_in_contact,
        "mean_in_contact": s.mean_in_contact,
        "largest_penetration_m": s.largest_penetration,
        "largest_force_n": s.largest_force,
    })
}

/// The `bearings` entry of summary.json.
pub fn summary(bearings: &[BearingReport]) -> Value {
    bearings
        .iter()
        .map(|b| {
            let frequencies: Vec<Value> = b
                .frequencies
                .iter()
                .map(|f| {
                    json!({
                        "source": f.predicted.source,
                        "cage_orders": f.predicted.cage_orders,
                        "predicted_hz": f.predicted.frequency_hz,
                        "measured": f.measured.iter().map(|(channel, peak)| json!({
                            "channel": channel,
                            "frequency_hz": peak.map(|p| p.frequency_hz),
                            "amplitude_m": peak.map(|p| p.amplitude),
                            "offset_bins": peak.map(|p| {
                                (p.frequency_hz - f.predicted.frequency_hz) / b.resolution_hz
                            }),
                        })).collect::<Vec<_>>(),
                    })
                })
                .collect();
            let waviness: Vec<f64> = b
                .frequencies
                .iter()
                .skip(1)
                .map(|f| f.predicted.frequency_hz)
                .collect();
            json!({
                "name": b.record.name,
                "node": b.record.node,
                "file_stem": b.stem,
                "rollers": b.record.rollers,
                "clearance_m": b.clearance,
                "cage_speed_hz": b.cage_hz,
                "varying_compliance_hz": b.frequencies.first().map(|f| f.predicted.frequency_hz),
                "waviness_hz": waviness,
                "spectrum_resolution_hz": b.resolution_hz,
                "settled": statistics(&b.settled),
                "whole_run": statistics(&b.whole),
                "frequencies": frequencies,
            })
        })
        .collect::<Vec<_>>()
        .into()
}

/// The peak of a check with the largest amplitude over the node's channels.
fn best(check: &FrequencyCheck) -> Option<(&str, SpectralPeak)> {
    check
        .measured
        .iter()
        .filter_map(|(c, p)| p.map(|p| (c.as_str(), p)))
        .max_by(|a, b| a.1.amplitude.total_cmp(&b.1.amplitude))
}

/// Lines of the text summary.
pub fn text(t: &mut String, bearings: &[BearingReport]) {
    for b in bearings {
        let s = &b.settled;
        let force = if b.record.has_forces() {
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
            b.record.name,
            b.record.node,
            s.min_in_contact,
            s.max_in_contact,
            b.record.rollers,
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

/// `contacts_<bearing>.csv` and the contact line and zone plots of each bearing.
pub fn write(
    out: &mut Output,
    result: &SimulationResult,
    bearings: &[BearingReport],
) -> miette::Result<()> {
    for b in bearings {
        let r = b.record;
        let mut header = vec!["time_s".to_string(), "in_contact".to_string()];
        header.extend((0..r.rollers).map(|j| format!("roller_{j}_force_n")));
        header.extend((0..r.rollers).map(|j| format!("roller_{j}_approach_m")));
        let rows = result.time.iter().enumerate().map(|(i, t)| {
            let force = r
                .forces_at(i)
                .iter()
                .map(|&f| if f.is_nan() { String::new() } else { num(f) });
            std::iter::once(num(*t))
                .chain(std::iter::once(r.contacts_at(i).to_string()))
                .chain(force)
                .chain(r.approaches_at(i).iter().map(|&a| num(a)))
                .collect::<Vec<_>>()
        });
        out.csv(&format!("contacts_{}.csv", b.stem), &header, rows)?;
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

/// Vertical lines at the contact frequencies, one per distinct frequency.
pub fn spectrum_markers(bearings: &[BearingReport]) -> Vec<RefLine> {
    let mut lines: Vec<RefLine> = Vec::new();
    for b in bearings {
        for f in &b.frequencies {
            let duplicate = lines
                .iter()
                .any(|l| (l.value - f.predicted.frequency_hz).abs() <= 1e-9 * l.value.abs());
            if duplicate || f.predicted.frequency_hz.is_nan() || f.predicted.frequency_hz <= 0.0 {
                continue;
            }
            // Short labels: the lines sit among the order lines; the values are in
            // summary.json.
            let label = if f.predicted.source == "varying compliance" {
                "N_b w_c".to_string()
            } else {
                format!("({}-1) w_c", f.predicted.cage_orders + 1.0)
            };
            lines.push(RefLine {
                colour: Colour::Palette(1),
                ..RefLine::new(f.predicted.frequency_hz).label(label)
            });
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stems_are_file_safe_and_distinct() {
        assert_eq!(
            stems(&["bearing A", "Bearing-A", "", "x/y"]),
            ["bearing_a", "bearing_a_2", "bearing", "x_y"]
        );
        // A 300-character name (issue 16: "File name too long" after the computation).
        let long = "b".repeat(300);
        assert_eq!(
            stems(&[&long, &long]),
            [long[..64].to_string(), format!("{}_2", &long[..64])]
        );
    }
}
