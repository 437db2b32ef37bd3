//! What the largest non-synchronous peak at each speed is (docs/theory.md section 8; thesis 5.1).
//!
//! The classes name the physics and, for the sub-synchronous ones, the whirl direction
//! (from the full spectrum of x + i y: forward when the component at +f is the larger):
//! whip is forward precession locked at a natural frequency, and a backward whirl locked
//! the same way is `backward-whip`, never plain whip.
//!
//! A point whose run did not settle (see [`crate::nsv`]: its largest non-synchronous peak was
//! still dying away at the longest settling time) is **unsettled**, whatever its frequency;
//! it is never an NSV of any other class. Otherwise the checks run in this order, the first
//! that holds names the peak (`tol` is the cascade's tolerance, `tolerance_bins` times the
//! bin spacing):
//!
//! 1. **sub-synchronous whirl** (`forward-` or `backward-sub-synchronous-whirl`): within
//!    `tol` of 0.5X (the thesis' whirl "at twice the first critical speed").
//! 2. **whip** (`forward-whip`, `backward-whip`), frequency-locked: sub-synchronous, and
//!    another settled speed within [`lock_window`] of this one has its NSV within
//!    [`lock_tolerance`] of it, although a vibration proportional to speed would have moved
//!    by more than twice that (the thesis' "frequency-locked phenomenon": the whip's
//!    frequency does not follow the speed). The window is in hertz of speed, not in
//!    neighbours, so a refined grid finds the same locks as a coarse one, and wide enough
//!    for a low order to have moved by that much.
//! 3. **varying compliance** `m N_b w_c` (`m` = 1..3, eq. 4.4; waviness frequencies
//!    `(N_w - 1) w_c` likewise), and **combination** tones `|m f_c +- n Omega|` (`n` = 1..3),
//!    within `tol`. Combinations are named only where the running speed exceeds 4 `tol`:
//!    below that they pack so densely that any frequency would match one.
//! 4. **whip**, near a natural frequency: sub-synchronous and within [`NATURAL_TOLERANCE`]
//!    of a natural frequency of the rotor on linearised bearings at that speed (Campbell):
//!    the contact stiffness of a bearing with clearance is not its linear stiffness, so the
//!    match is loose.
//! 5. **super-harmonic**: above 1X and not explained above (a peak above 1X within
//!    [`NATURAL_TOLERANCE`] of a natural frequency is a mode ringing, named **other**).
//! 6. **other**.

use serde::{Deserialize, Serialize, Serializer};

use super::point::{CascadePoint, NsvPeak};

/// A sub-synchronous peak within this fraction of a linearised natural frequency is whip.
pub const NATURAL_TOLERANCE: f64 = 0.1;

/// Combination tones are named only when the running speed exceeds this many tolerances.
const COMBINATION_SPACING: f64 = 4.0;

/// Multiples m of a contact frequency and n of the running speed tried.
const MAX_CONTACT_MULTIPLE: usize = 3;
const MAX_SPEED_MULTIPLE: usize = 3;

/// The lock window's fraction of the running speed ...
const LOCK_WINDOW_FRACTION: f64 = 0.1;
/// ... and its least width, Hz: about two steps of the default 150-speed grid over
/// 1-750 Hz, where whip locks were first seen.
const LOCK_WINDOW_MIN_HZ: f64 = 12.0;

/// Whirl direction of a peak, from the full spectrum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum WhirlDirection {
    /// With the spin (its +frequency component is the larger).
    Forward,
    /// Against the spin.
    Backward,
}

impl WhirlDirection {
    /// `forward` or `backward`.
    pub fn name(self) -> &'static str {
        match self {
            WhirlDirection::Forward => "forward",
            WhirlDirection::Backward => "backward",
        }
    }
}

/// What kind of non-synchronous vibration a peak is (rules in the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum NsvClass {
    /// Near half the running speed, whirling this way.
    SubSynchronousWhirl(WhirlDirection),
    /// Locked near a natural frequency while the speed changes, whirling this way.
    Whip(WhirlDirection),
    /// A multiple of a bearing's varying-compliance (or waviness) frequency.
    VaryingCompliance,
    /// A combination `|m f_c +- n Omega|` of a contact frequency and the running speed.
    Combination,
    /// Above 1X, at no multiple of it, not otherwise explained.
    SuperHarmonic,
    /// None of the above.
    Other,
    /// The start had not died away at the longest settling time: no NSV.
    Unsettled,
}

impl NsvClass {
    /// Every class, in the order of the module documentation's list.
    pub const ALL: [NsvClass; 9] = [
        NsvClass::SubSynchronousWhirl(WhirlDirection::Forward),
        NsvClass::SubSynchronousWhirl(WhirlDirection::Backward),
        NsvClass::Whip(WhirlDirection::Forward),
        NsvClass::Whip(WhirlDirection::Backward),
        NsvClass::VaryingCompliance,
        NsvClass::Combination,
        NsvClass::SuperHarmonic,
        NsvClass::Other,
        NsvClass::Unsettled,
    ];

    /// Name as in tables: `forward-whip`, `backward-sub-synchronous-whirl`, ...
    pub fn name(self) -> &'static str {
        use WhirlDirection::{Backward, Forward};
        match self {
            NsvClass::SubSynchronousWhirl(Forward) => "forward-sub-synchronous-whirl",
            NsvClass::SubSynchronousWhirl(Backward) => "backward-sub-synchronous-whirl",
            NsvClass::Whip(Forward) => "forward-whip",
            NsvClass::Whip(Backward) => "backward-whip",
            NsvClass::VaryingCompliance => "varying-compliance",
            NsvClass::Combination => "combination",
            NsvClass::SuperHarmonic => "super-harmonic",
            NsvClass::Other => "other",
            NsvClass::Unsettled => "unsettled",
        }
    }

    /// Whether this is a steady NSV (every class but unsettled).
    pub fn is_steady(self) -> bool {
        self != NsvClass::Unsettled
    }
}

impl Serialize for NsvClass {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

/// A frequency named for the classification: a contact frequency (`N_b w_c of bearing A`)
/// or a natural frequency (`mode 1F`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NamedFrequency {
    /// What it is.
    pub name: String,
    /// Hz.
    pub frequency_hz: f64,
}

/// The classified NSV at one speed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Nsv {
    /// Spin speed, Hz.
    pub speed_hz: f64,
    /// The peak.
    pub peak: NsvPeak,
    /// What it is.
    pub class: NsvClass,
    /// Why: `0.5X`, `N_b w_c - 1X (bearing A)`, `locked near 45.1 Hz`, ...
    pub explanation: String,
    /// Forward or backward whirl.
    pub direction: WhirlDirection,
}

/// What the classification of one speed knows besides its peak.
pub(super) struct Context<'a> {
    /// Contact frequencies at this speed.
    pub contact: &'a [NamedFrequency],
    /// Natural frequencies of the linearised rotor at this speed.
    pub natural: &'a [NamedFrequency],
    /// Tolerance, Hz.
    pub tolerance_hz: f64,
}

/// How close two speeds' NSV frequencies must be to count as locked, Hz: the tolerance, or
/// 2 % of the frequency (a whip drifts a little as the contact stiffness changes with
/// speed), whichever is larger.
pub fn lock_tolerance(frequency_hz: f64, tolerance_hz: f64) -> f64 {
    tolerance_hz.max(0.02 * frequency_hz)
}

/// How far in speed (Hz) from `speed_hz` a lock partner of a peak of `order` is looked
/// for: a tenth of the speed, at least `LOCK_WINDOW_MIN_HZ`, and at least 1.5 times the
/// speed change over which a vibration of that order would move by twice the lock
/// tolerance `lock_hz` (else a low order could never show its lock).
pub fn lock_window(speed_hz: f64, order: f64, lock_hz: f64) -> f64 {
    let reach = if order > 0.0 {
        1.5 * 2.0 * lock_hz / order
    } else {
        0.0
    };
    (LOCK_WINDOW_FRACTION * speed_hz)
        .max(LOCK_WINDOW_MIN_HZ)
        .max(reach)
}

/// Classifies every point's peak.
pub(super) fn classify(points: &[CascadePoint], contexts: &[Context<'_>]) -> Vec<Option<Nsv>> {
    points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let peak = p.peak?;
            let direction = if peak.forward_m >= peak.backward_m {
                WhirlDirection::Forward
            } else {
                WhirlDirection::Backward
            };
            let (class, explanation) = if p.settled {
                let locked = lock_partner(points, i, &contexts[i]);
                name(p.speed_hz, &peak, direction, locked, &contexts[i])
            } else {
                let why = format!(
                    "still dying away after {:.2} s: {:.2} of its amplitude per half record",
                    p.settle_s, peak.decay_ratio
                );
                (NsvClass::Unsettled, why)
            };
            Some(Nsv {
                speed_hz: p.speed_hz,
                peak,
                class,
                explanation,
                direction,
            })
        })
        .collect()
}

/// The nearest settled speed in the lock window whose peak is locked with point `i`'s.
fn lock_partner(points: &[CascadePoint], i: usize, c: &Context<'_>) -> Option<(f64, NsvPeak)> {
    let p = &points[i];
    let peak = p.peak?;
    let lock_hz = lock_tolerance(peak.frequency_hz, c.tolerance_hz);
    let window = lock_window(p.speed_hz, peak.order, lock_hz);
    points
        .iter()
        .enumerate()
        .filter(|&(j, q)| j != i && q.settled && (q.speed_hz - p.speed_hz).abs() <= window)
        .filter_map(|(_, q)| q.peak.map(|other| (q.speed_hz, other)))
        .filter(|(speed_hz, other)| locked_with(p.speed_hz, &peak, *speed_hz, other, c))
        .min_by(|a, b| {
            (a.0 - p.speed_hz)
                .abs()
                .total_cmp(&(b.0 - p.speed_hz).abs())
        })
}

/// Whether `peak` at `speed_hz` and `other` at `other_speed_hz` are one frequency-locked
/// vibration: within the lock tolerance, while a vibration proportional to speed would
/// have moved by more than twice that.
fn locked_with(
    speed_hz: f64,
    peak: &NsvPeak,
    other_speed_hz: f64,
    other: &NsvPeak,
    c: &Context<'_>,
) -> bool {
    let tolerance = lock_tolerance(peak.frequency_hz, c.tolerance_hz);
    (peak.frequency_hz - other.frequency_hz).abs() <= tolerance
        && peak.order * (speed_hz - other_speed_hz).abs() > 2.0 * tolerance
}

/// Class and explanation of a settled peak, by the checks of the module documentation.
fn name(
    speed_hz: f64,
    peak: &NsvPeak,
    direction: WhirlDirection,
    locked: Option<(f64, NsvPeak)>,
    c: &Context<'_>,
) -> (NsvClass, String) {
    let f = peak.frequency_hz;
    let tol = c.tolerance_hz;
    let sub = f < speed_hz;
    if (f - 0.5 * speed_hz).abs() <= tol {
        return (NsvClass::SubSynchronousWhirl(direction), "0.5X".into());
    }
    if let (true, Some((other_speed, other))) = (sub, locked) {
        let why = format!(
            "locked: {:.1} Hz at {:.1} Hz running speed{}",
            other.frequency_hz,
            other_speed,
            nearest_natural(f, c).map_or(String::new(), |n| format!(", near {}", n.name))
        );
        return (NsvClass::Whip(direction), why);
    }
    if let Some(found) = contact_match(speed_hz, f, c) {
        return found;
    }
    let near = nearest_natural(f, c)
        .filter(|n| (f - n.frequency_hz).abs() <= NATURAL_TOLERANCE * n.frequency_hz);
    if let Some(n) = near {
        let why = format!("near {} ({:.1} Hz)", n.name, n.frequency_hz);
        // Above the running speed a mode ringing at its own frequency is no whip, and no
        // super-harmonic of the speed either.
        let class = if sub {
            NsvClass::Whip(direction)
        } else {
            NsvClass::Other
        };
        return (class, why);
    }
    if f > speed_hz {
        return (NsvClass::SuperHarmonic, format!("{:.3}X", peak.order));
    }
    (NsvClass::Other, format!("{:.3}X", peak.order))
}

/// The natural frequency nearest `f`.
fn nearest_natural<'a>(f: f64, c: &'a Context<'_>) -> Option<&'a NamedFrequency> {
    c.natural.iter().min_by(|a, b| {
        (a.frequency_hz - f)
            .abs()
            .total_cmp(&(b.frequency_hz - f).abs())
    })
}

/// A multiple of a contact frequency, or a combination with the running speed, within the
/// tolerance of `f`.
fn contact_match(speed_hz: f64, f: f64, c: &Context<'_>) -> Option<(NsvClass, String)> {
    let tol = c.tolerance_hz;
    let combinations = speed_hz > COMBINATION_SPACING * tol;
    let multiple = |m: usize, name: &str| {
        if m == 1 {
            name.to_string()
        } else {
            format!("{m} {name}")
        }
    };
    for base in c.contact {
        for m in 1..=MAX_CONTACT_MULTIPLE {
            let fm = m as f64 * base.frequency_hz;
            if (f - fm).abs() <= tol {
                return Some((NsvClass::VaryingCompliance, multiple(m, &base.name)));
            }
            if !combinations {
                continue;
            }
            for n in 1..=MAX_SPEED_MULTIPLE {
                let fn_ = n as f64 * speed_hz;
                for (sign, value) in [("+", fm + fn_), ("-", (fm - fn_).abs())] {
                    if (f - value).abs() <= tol {
                        let why = format!("{} {sign} {n}X", multiple(m, &base.name));
                        return Some((NsvClass::Combination, why));
                    }
                }
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn peak(frequency_hz: f64, speed_hz: f64) -> NsvPeak {
        NsvPeak {
            frequency_hz,
            amplitude_m: 1e-6,
            order: frequency_hz / speed_hz,
            forward_m: 1e-6,
            backward_m: 2e-7,
            decay_ratio: 1.0,
            settling_ratio: Some(1.0),
            standard_error_m: 0.0,
            variation: 0.0,
        }
    }

    fn context<'a>(contact: &'a [NamedFrequency], natural: &'a [NamedFrequency]) -> Context<'a> {
        Context {
            contact,
            natural,
            tolerance_hz: 4.0,
        }
    }

    fn named(name: &str, frequency_hz: f64) -> NamedFrequency {
        NamedFrequency {
            name: name.into(),
            frequency_hz,
        }
    }

    #[test]
    fn each_check_names_its_class() {
        use WhirlDirection::{Backward, Forward};
        let contact = [named("N_b w_c", 365.0)];
        let natural = [named("mode 1F", 50.0)];
        let c = context(&contact, &natural);
        let class = |f: f64, speed: f64| name(speed, &peak(f, speed), Forward, None, &c).0;
        assert_eq!(class(50.5, 100.0), NsvClass::SubSynchronousWhirl(Forward));
        assert_eq!(class(365.0, 100.0), NsvClass::VaryingCompliance);
        assert_eq!(class(730.0, 100.0), NsvClass::VaryingCompliance);
        assert_eq!(class(265.0, 100.0), NsvClass::Combination);
        assert_eq!(class(47.0, 200.0), NsvClass::Whip(Forward));
        assert_eq!(class(150.0, 100.0), NsvClass::SuperHarmonic);
        // The first mode ringing above a low running speed.
        assert_eq!(class(49.0, 30.0), NsvClass::Other);
        assert_eq!(class(20.0, 200.0), NsvClass::Other);
        // A backward whirl near the natural frequency is never plain whip.
        let backward = name(200.0, &peak(47.0, 200.0), Backward, None, &c).0;
        assert_eq!(backward, NsvClass::Whip(Backward));
        assert_eq!(backward.name(), "backward-whip");
    }

    #[test]
    fn an_unsettled_point_has_no_other_class() {
        let mut p = CascadePoint::settled_at(200.0, 1e-5, Some(peak(50.0, 200.0)));
        (p.settled, p.settle_s, p.records) = (false, 4.0, 1);
        let (contact, natural) = ([], [named("mode 1F", 50.0)]);
        let c = [context(&contact, &natural)];
        let nsv = classify(std::slice::from_ref(&p), &c);
        assert_eq!(nsv[0].as_ref().map(|n| n.class), Some(NsvClass::Unsettled));
        p.settled = true;
        let nsv = classify(std::slice::from_ref(&p), &c);
        let class = nsv[0].as_ref().map(|n| n.class);
        assert_eq!(class, Some(NsvClass::Whip(WhirlDirection::Forward)));
    }

    #[test]
    fn every_name_is_distinct() {
        let mut names: Vec<&str> = NsvClass::ALL.iter().map(|c| c.name()).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), NsvClass::ALL.len());
    }

    #[test]
    fn a_frequency_that_stays_put_is_locked_one_that_follows_speed_is_not() {
        let c = context(&[], &[]);
        // 45 Hz at 200 and 210 Hz: a 0.225X component would have moved 2.25 Hz, and the
        // lock tolerance is max(4, 0.9) = 4 Hz: not enough evidence.
        assert!(!locked_with(
            200.0,
            &peak(45.0, 200.0),
            210.0,
            &peak(45.0, 210.0),
            &c
        ));
        // Over 50 Hz of speed it would have moved 11 Hz: locked.
        assert!(locked_with(
            200.0,
            &peak(45.0, 200.0),
            250.0,
            &peak(45.5, 250.0),
            &c
        ));
        // 0.3X follows the speed: 60 Hz then 75 Hz.
        assert!(!locked_with(
            200.0,
            &peak(60.0, 200.0),
            250.0,
            &peak(75.0, 250.0),
            &c
        ));
    }
}
