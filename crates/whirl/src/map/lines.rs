//! Resonance lines: the speeds where non-synchronous vibration can appear on a stable
//! synchronous orbit, because an excitation the orbit does not hold meets one of the
//! orbit's natural frequencies (docs/theory.md section 7).
//!
//! The natural frequencies are those of the orbit's linearisation averaged over the period
//! ([`OrbitMode`]): the bearings' tangent stiffness along the orbit, which rises with the
//! orbit's load on the rollers, not the stiffness written in the model file. A line is a
//! crossing, between two successive points of the branch, of one of
//!
//! - a contact frequency (the varying compliance k N_b w_c, a waviness (N_w - 1) w_c) or its
//!   sideband k c w -+ w, meeting a natural frequency f_i: forced by the rollers passing,
//!   the response is at the contact frequency (`contact`);
//! - half the speed meeting f_i: the principal parametric resonance of the orbit's periodic
//!   stiffness, a response at w/2 (`half-speed`);
//! - a sum f_i + f_j = k w or a difference f_j - f_i = w of two natural frequencies: the
//!   combination resonances of the periodic stiffness, a response at f_i with its companion
//!   k w - f_i (`sum`, `difference`).
//!
//! Where such a resonance is strong enough to destabilise the orbit the sweep's Floquet
//! multipliers already show it as an unstable band; a line says where it can appear while
//! the orbit stays stable (a forced resonance, or one held down by damping).

use serde::{Deserialize, Serialize};

use crate::bearing::contact_frequencies;
use crate::hbm::{Branch, OrbitMode};
use crate::model::Model;
use crate::units::rad_s_to_hz as hz;

/// Modes damped more than this are left out: a resonance of a mode at 30 % of critical
/// damping has a quality factor below 2, no peak to speak of.
pub const MAX_DAMPING_RATIO: f64 = 0.3;

/// Multiples k of a contact frequency that draw lines (k c w and its sidebands).
const CONTACT_ORDERS: [f64; 2] = [1.0, 2.0];

/// Multiples k of the speed in the sum resonance f_i + f_j = k w.
const SUM_ORDERS: [f64; 2] = [1.0, 2.0];

/// What meets a natural frequency at a line.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Excitation {
    /// k times a contact frequency (`source`, c cage orders) plus `sideband` times the
    /// speed (-1, 0 or 1).
    Contact {
        /// The contact frequency's name (`varying compliance`, `waviness outer order 5`).
        source: String,
        /// Its multiple k.
        order: f64,
        /// The speed's multiple added to it.
        sideband: f64,
    },
    /// Half the speed.
    HalfSpeed,
    /// f_i + f_j = k w, with the other mode's frequency.
    Sum {
        /// k.
        order: f64,
        /// f_j at the crossing, Hz.
        other_hz: f64,
    },
    /// f_j - f_i = w, with the other (higher) mode's frequency.
    Difference {
        /// f_j at the crossing, Hz.
        other_hz: f64,
    },
}

impl Excitation {
    /// A short name for tables and plots: `1x varying compliance - 1X`, `0.5X`,
    /// `f_i + f_j = 1X`, `f_j - f_i = 1X`.
    pub fn name(&self) -> String {
        match self {
            Excitation::Contact {
                source,
                order,
                sideband,
            } => {
                let side = match *sideband {
                    s if s > 0.0 => " + 1X",
                    s if s < 0.0 => " - 1X",
                    _ => "",
                };
                format!("{order}x {source}{side}")
            }
            Excitation::HalfSpeed => "0.5X".into(),
            Excitation::Sum { order, .. } => format!("f_i + f_j = {order}X"),
            Excitation::Difference { .. } => "f_j - f_i = 1X".into(),
        }
    }
}

/// Where an excitation meets a natural frequency of the orbit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ResonanceLine {
    /// Running speed of the crossing, Hz (linear between the two branch points).
    pub speed_hz: f64,
    /// What meets the mode.
    pub excitation: Excitation,
    /// The frequency the vibration appears at, Hz: the excitation's, or f_i for a sum or a
    /// difference.
    pub response_hz: f64,
    /// The natural frequency met, Hz.
    pub mode_hz: f64,
    /// Its damping ratio.
    pub damping_ratio: f64,
    /// Whether the orbit is stable at both branch points around the crossing.
    pub on_stable_orbit: bool,
}

/// The lines of `branch` (a sweep of `model` with stability), in path order; none without
/// stability.
pub fn resonance_lines(branch: &Branch, model: &Model) -> Vec<ResonanceLine> {
    let contacts = contact_ratios(model);
    let points = &branch.points;
    let mut lines = Vec::new();
    for i in 0..points.len().saturating_sub(1) {
        if branch.jumped_after.contains(&i) {
            continue;
        }
        let (Some(a), Some(b)) = (&points[i].stability, &points[i + 1].stability) else {
            continue;
        };
        let ends = [
            End::new(hz(points[i].solution.frequency), &a.orbit_modes),
            End::new(hz(points[i + 1].solution.frequency), &b.orbit_modes),
        ];
        let stable = a.stable && b.stable;
        crossings(&ends, &contacts, stable, &mut lines);
    }
    lines
}

/// A contact frequency per unit speed: (name, cage orders times the cage ratio, i.e. the
/// frequency in Hz at 1 Hz of running speed). Bearings alike give it once.
fn contact_ratios(model: &Model) -> Vec<(String, f64)> {
    let mut out: Vec<(String, f64)> = Vec::new();
    for bearing in &model.roller_bearings {
        for c in contact_frequencies(bearing, std::f64::consts::TAU) {
            let known = out
                .iter()
                .any(|(s, r)| *s == c.source && (r - c.frequency_hz).abs() <= 1e-12 * r.abs());
            if !known {
                out.push((c.source, c.frequency_hz));
            }
        }
    }
    out
}

/// One end of a branch segment: its speed and lightly damped modes (Hz), ascending.
struct End {
    speed: f64,
    modes: Vec<OrbitMode>,
}

impl End {
    fn new(speed: f64, modes: &[OrbitMode]) -> End {
        End {
            speed,
            modes: modes
                .iter()
                .filter(|m| m.damping_ratio <= MAX_DAMPING_RATIO)
                .map(|m| OrbitMode {
                    frequency: hz(m.frequency),
                    damping_ratio: m.damping_ratio,
                })
                .collect(),
        }
    }
}

/// Where a gap that changes sign between the two ends of a segment is zero, as a fraction
/// of the segment from its first end.
fn zero_of([g0, g1]: [f64; 2]) -> Option<f64> {
    (g0 * g1 < 0.0 || (g0 == 0.0 && g1 != 0.0)).then(|| g0 / (g0 - g1))
}

/// A segment of the branch between two successive points.
struct Segment<'a> {
    ends: &'a [End; 2],
    stable: bool,
}

impl Segment<'_> {
    /// Mode `i`'s frequency at end `e`, Hz.
    fn mode(&self, e: usize, i: usize) -> f64 {
        self.ends[e].modes[i].frequency
    }

    /// `x` at both ends, at the fraction `t` of the segment.
    fn at(t: f64, [x0, x1]: [f64; 2]) -> f64 {
        x0 + t * (x1 - x0)
    }

    /// `value` at both ends.
    fn both(&self, value: impl Fn(usize) -> f64) -> [f64; 2] {
        [value(0), value(1)]
    }

    /// The line where `excitation` (at `response` Hz at both ends) meets mode `i`, when
    /// `gap` changes sign.
    fn line(
        &self,
        excitation: Excitation,
        gap: [f64; 2],
        response: [f64; 2],
        i: usize,
    ) -> Option<ResonanceLine> {
        let t = zero_of(gap)?;
        let ends = self.ends;
        Some(ResonanceLine {
            speed_hz: Self::at(t, self.both(|e| ends[e].speed)),
            excitation,
            response_hz: Self::at(t, response),
            mode_hz: Self::at(t, self.both(|e| self.mode(e, i))),
            damping_ratio: Self::at(t, self.both(|e| ends[e].modes[i].damping_ratio)),
            on_stable_orbit: self.stable,
        })
    }

    /// Modes present at both ends (matched by rank in frequency: between two close points
    /// of a branch a mode keeps its rank unless two modes cross, which moves a line by at
    /// most the segment).
    fn modes(&self) -> usize {
        self.ends[0].modes.len().min(self.ends[1].modes.len())
    }

    /// The contact and half-speed lines of mode `i`.
    fn single(&self, i: usize, contacts: &[(String, f64)], lines: &mut Vec<ResonanceLine>) {
        let speed = self.both(|e| self.ends[e].speed);
        let mode = self.both(|e| self.mode(e, i));
        let gap = |f: [f64; 2]| [f[0] - mode[0], f[1] - mode[1]];
        for (source, ratio) in contacts {
            for order in CONTACT_ORDERS {
                for sideband in [-1.0, 0.0, 1.0] {
                    let f = speed.map(|w| (order * ratio + sideband) * w);
                    let excitation = Excitation::Contact {
                        source: source.clone(),
                        order,
                        sideband,
                    };
                    lines.extend(self.line(excitation, gap(f), f, i));
                }
            }
        }
        let half = speed.map(|w| 0.5 * w);
        lines.extend(self.line(Excitation::HalfSpeed, gap(half), half, i));
    }

    /// The sum and difference lines of modes `i` < `j`, at f_i.
    fn pair(&self, i: usize, j: usize, lines: &mut Vec<ResonanceLine>) {
        let speed = self.both(|e| self.ends[e].speed);
        let (fi, fj) = (
            self.both(|e| self.mode(e, i)),
            self.both(|e| self.mode(e, j)),
        );
        for order in SUM_ORDERS {
            let gap = self.both(|e| fi[e] + fj[e] - order * speed[e]);
            if let Some(t) = zero_of(gap) {
                let other_hz = Self::at(t, fj);
                lines.extend(self.line(Excitation::Sum { order, other_hz }, gap, fi, i));
            }
        }
        let gap = self.both(|e| fj[e] - fi[e] - speed[e]);
        if let Some(t) = zero_of(gap) {
            let other_hz = Self::at(t, fj);
            lines.extend(self.line(Excitation::Difference { other_hz }, gap, fi, i));
        }
    }
}

/// Adds to `lines` every excitation that meets a mode between the two ends.
fn crossings(
    ends: &[End; 2],
    contacts: &[(String, f64)],
    stable: bool,
    lines: &mut Vec<ResonanceLine>,
) {
    let segment = Segment { ends, stable };
    let modes = segment.modes();
    for i in 0..modes {
        segment.single(i, contacts, lines);
        for j in i + 1..modes {
            segment.pair(i, j, lines);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn end(speed: f64, modes: &[f64]) -> End {
        End {
            speed,
            modes: modes
                .iter()
                .map(|&frequency| OrbitMode {
                    frequency,
                    damping_ratio: 0.02,
                })
                .collect(),
        }
    }

    fn lines_between(a: End, b: End, contacts: &[(String, f64)]) -> Vec<ResonanceLine> {
        let mut lines = Vec::new();
        crossings(&[a, b], contacts, true, &mut lines);
        lines
    }

    #[test]
    fn a_roller_passing_frequency_meets_a_mode_where_it_equals_it() {
        // N_b w_c = 3.2 w meets a 50 Hz mode at 15.625 Hz; between 10 and 20 Hz no other
        // excitation reaches 50 Hz (2 x 3.2 w - w = 54 Hz only above 9.26 Hz: it crosses
        // at 9.26, outside), and half the speed stays below it.
        let contacts = [("varying compliance".to_string(), 3.2)];
        let lines = lines_between(end(10.0, &[50.0]), end(20.0, &[50.0]), &contacts);
        let names: Vec<String> = lines.iter().map(|l| l.excitation.name()).collect();
        assert_eq!(
            names,
            ["1x varying compliance", "1x varying compliance + 1X"],
            "{lines:?}"
        );
        // Linear in speed and a constant mode: the crossing is exact to round-off.
        assert!((lines[0].speed_hz - 50.0 / 3.2).abs() < 1e-12);
        assert!((lines[0].response_hz - 50.0).abs() < 1e-12);
        assert!((lines[1].speed_hz - 50.0 / 4.2).abs() < 1e-12);
    }

    #[test]
    fn a_mode_that_moves_with_speed_is_met_where_the_two_lines_cross() {
        // f_1 stiffens from 40 to 60 Hz while the speed goes from 100 to 140 Hz; f_2 stays
        // at 160 Hz. The sum f_1 + f_2 = 200 -> 220 Hz equals 2 w = 200 -> 280 Hz at the
        // first end (a zero there counts once); the difference f_2 - f_1 = 120 -> 100 Hz
        // meets w where 120 - 20 t = 100 + 40 t, t = 1/3: w = 113.33 Hz, f_1 = 46.67 Hz.
        // Nothing else crosses: half the speed (50 -> 70) stays above f_1 and below f_2,
        // f_1 + f_2 stays above w, and there are no contact frequencies.
        let lines = lines_between(end(100.0, &[40.0, 160.0]), end(140.0, &[60.0, 160.0]), &[]);
        assert_eq!(lines.len(), 2, "{lines:?}");
        let (sum, difference) = (&lines[0], &lines[1]);
        assert_eq!(sum.excitation.name(), "f_i + f_j = 2X");
        assert_eq!((sum.speed_hz, sum.response_hz), (100.0, 40.0));
        assert_eq!(difference.excitation.name(), "f_j - f_i = 1X");
        // Linear interpolation of linear functions: round-off.
        assert!((difference.speed_hz - 340.0 / 3.0).abs() < 1e-12);
        assert!((difference.response_hz - 140.0 / 3.0).abs() < 1e-12);
        assert!(
            matches!(difference.excitation, Excitation::Difference { other_hz } if other_hz == 160.0)
        );
    }

    #[test]
    fn heavily_damped_modes_draw_no_line() {
        let damped = |speed| {
            End::new(
                speed,
                &[OrbitMode {
                    frequency: std::f64::consts::TAU * 50.0,
                    damping_ratio: 0.5,
                }],
            )
        };
        let contacts = [("varying compliance".to_string(), 3.2)];
        assert!(lines_between(damped(10.0), damped(20.0), &contacts).is_empty());
    }
}
