//! What the largest non-synchronous peak at each speed is (SPEC section 9; thesis 5.1).
//!
//! Checks in this order, the first that holds names the peak (`tol` is the cascade's
//! tolerance, `tolerance_bins` times the bin spacing):
//!
//! 1. **transient**: free vibration from the start still dying away, not a steady NSV
//!    (settle longer). Its amplitude is measured over three equal stretches, the end of
//!    the settling time and the record's two halves: it is transient when it falls to
//!    less than [`DECAY_PER_STRETCH`] from each stretch to the next, the second fall not
//!    more than 2x gentler than the first, as an exponential decay does. Two components
//!    closer than a bin (a mode's forward and backward whirl, split by a hertz) beat
//!    instead: their envelope does not keep falling. When the settling time is shorter than
//!    half the record only the record's halves are compared, against
//!    [`TRANSIENT_DECAY`].
//! 2. **sub-synchronous whirl**: within `tol` of 0.5X (the thesis' whirl "at twice the
//!    first critical speed").
//! 3. **whip**, frequency-locked: sub-synchronous, and a neighbouring speed's NSV lies
//!    within [`lock_tolerance`] of it although a vibration proportional to speed would have
//!    moved by more than twice that (the thesis' "frequency-locked phenomenon": the whip's
//!    frequency does not follow the speed).
//! 4. **varying compliance** `m N_b w_c` (`m` = 1..3, eq. 4.4; waviness frequencies
//!    `(N_w - 1) w_c` likewise), and **combination** tones `|m f_c +- n Omega|` (`n` = 1..3),
//!    within `tol`. Combinations are named only where the running speed exceeds 4 `tol`:
//!    below that they pack so densely that any frequency would match one.
//! 5. **whip**, near a natural frequency: sub-synchronous and within [`NATURAL_TOLERANCE`]
//!    of a natural frequency of the rotor on linearised bearings at that speed (Campbell):
//!    the contact stiffness of a bearing with clearance is not its linear stiffness, so the
//!    match is loose.
//! 6. **super-harmonic**: above 1X and not explained above (a peak above 1X within
//!    [`NATURAL_TOLERANCE`] of a natural frequency is a mode ringing, named **other**).
//! 7. **other**.

use serde::{Deserialize, Serialize};

use super::point::{CascadePoint, NsvPeak};

/// Below this ratio of second-half to first-half amplitude a peak is transient when only
/// the record's halves are compared. Free vibration at 2 % damping of a 50 Hz mode decays
/// by exp(-0.02 * 2 pi * 50 * 0.25) = 0.21 over a quarter second (half the default record);
/// a steady vibration keeps a ratio near 1, and on the reference rotor beats of the first
/// mode's forward and backward whirl were seen down to 0.33 over 0.25 s, so the line is
/// drawn below that.
pub const TRANSIENT_DECAY: f64 = 0.25;

/// With three stretches compared, a peak is transient when each stretch holds less than
/// this fraction of the amplitude of the one before (the second fraction at most twice the
/// first). The 50 Hz mode above gives 0.21 per quarter second, and 0.53 per tenth of
/// a second (0.2 s records).
pub const DECAY_PER_STRETCH: f64 = 0.6;

/// A sub-synchronous peak within this fraction of a linearised natural frequency is whip.
pub const NATURAL_TOLERANCE: f64 = 0.1;

/// Combination tones are named only when the running speed exceeds this many tolerances.
const COMBINATION_SPACING: f64 = 4.0;

/// Multiples m of a contact frequency and n of the running speed tried.
const MAX_CONTACT_MULTIPLE: usize = 3;
const MAX_SPEED_MULTIPLE: usize = 3;

/// What kind of non-synchronous vibration a peak is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum NsvClass {
    /// Near half the running speed.
    SubSynchronousWhirl,
    /// Locked near a natural frequency while the speed changes.
    Whip,
    /// A multiple of a bearing's varying-compliance (or waviness) frequency.
    VaryingCompliance,
    /// A combination `|m f_c +- n Omega|` of a contact frequency and the running speed.
    Combination,
    /// Above 1X, at no multiple of it, not otherwise explained.
    SuperHarmonic,
    /// Free vibration still dying away over the record.
    Transient,
    /// None of the above.
    Other,
}

impl NsvClass {
    /// Every class, in the order of the module documentation's list.
    pub const ALL: [NsvClass; 7] = [
        NsvClass::Transient,
        NsvClass::SubSynchronousWhirl,
        NsvClass::Whip,
        NsvClass::VaryingCompliance,
        NsvClass::Combination,
        NsvClass::SuperHarmonic,
        NsvClass::Other,
    ];

    /// Name as in tables: `sub-synchronous-whirl`, `whip`, ...
    pub fn name(self) -> &'static str {
        match self {
            NsvClass::SubSynchronousWhirl => "sub-synchronous-whirl",
            NsvClass::Whip => "whip",
            NsvClass::VaryingCompliance => "varying-compliance",
            NsvClass::Combination => "combination",
            NsvClass::SuperHarmonic => "super-harmonic",
            NsvClass::Transient => "transient",
            NsvClass::Other => "other",
        }
    }
}

/// Whirl direction of a peak, from the full spectrum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum WhirlDirection {
    /// With the spin (its +frequency component is the larger).
    Forward,
    /// Against the spin.
    Backward,
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

/// Classifies every point's peak; `neighbours[i]` are the indices of the points next to
/// `i` in speed.
pub(super) fn classify(
    points: &[CascadePoint],
    contexts: &[Context<'_>],
    neighbours: &[Vec<usize>],
) -> Vec<Option<Nsv>> {
    points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let peak = p.peak?;
            let locked = neighbours[i]
                .iter()
                .filter_map(|&j| points[j].peak.map(|q| (points[j].speed_hz, q)))
                .find(|(speed_hz, q)| locked_with(p.speed_hz, &peak, *speed_hz, q, &contexts[i]));
            let (class, explanation) = name(p.speed_hz, &peak, locked, &contexts[i]);
            Some(Nsv {
                speed_hz: p.speed_hz,
                peak,
                class,
                explanation,
                direction: if peak.forward_m >= peak.backward_m {
                    WhirlDirection::Forward
                } else {
                    WhirlDirection::Backward
                },
            })
        })
        .collect()
}

/// Whether `peak` at `speed_hz` and `other` at `other_speed_hz` are one frequency-locked
/// vibration: both steady, within the lock tolerance, while a vibration proportional to
/// speed would have moved by more than twice that.
fn locked_with(
    speed_hz: f64,
    peak: &NsvPeak,
    other_speed_hz: f64,
    other: &NsvPeak,
    c: &Context<'_>,
) -> bool {
    let tolerance = lock_tolerance(peak.frequency_hz, c.tolerance_hz);
    !transient(peak)
        && !transient(other)
        && (peak.frequency_hz - other.frequency_hz).abs() <= tolerance
        && peak.order * (speed_hz - other_speed_hz).abs() > 2.0 * tolerance
}

/// Class and explanation, by the checks of the module documentation.
fn name(
    speed_hz: f64,
    peak: &NsvPeak,
    locked: Option<(f64, NsvPeak)>,
    c: &Context<'_>,
) -> (NsvClass, String) {
    let f = peak.frequency_hz;
    let tol = c.tolerance_hz;
    let sub = f < speed_hz;
    if transient(peak) {
        let why = format!(
            "decays to {:.2} of its first-half amplitude over the record",
            peak.decay_ratio
        );
        return (NsvClass::Transient, why);
    }
    if (f - 0.5 * speed_hz).abs() <= tol {
        return (NsvClass::SubSynchronousWhirl, "0.5X".into());
    }
    if let (true, Some((other_speed, other))) = (sub, locked) {
        let why = format!(
            "locked: {:.1} Hz at {:.1} Hz running speed{}",
            other.frequency_hz,
            other_speed,
            nearest_natural(f, c).map_or(String::new(), |n| format!(", near {}", n.name))
        );
        return (NsvClass::Whip, why);
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
        let class = if sub { NsvClass::Whip } else { NsvClass::Other };
        return (class, why);
    }
    if f > speed_hz {
        return (NsvClass::SuperHarmonic, format!("{:.3}X", peak.order));
    }
    (NsvClass::Other, format!("{:.3}X", peak.order))
}

/// Whether `peak` is free vibration dying away (rule 1 of the module documentation).
fn transient(peak: &NsvPeak) -> bool {
    let later = peak.decay_ratio;
    match peak.settling_ratio {
        Some(earlier) => {
            // Falling on, not rebounding: the later fall may be steeper (a decay that
            // reaches the level of other components' leakage).
            let falls_on = later <= 2.0 * earlier;
            earlier < DECAY_PER_STRETCH && later < DECAY_PER_STRETCH && falls_on
        }
        None => later < TRANSIENT_DECAY,
    }
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
        let contact = [named("N_b w_c", 365.0)];
        let natural = [named("mode 1F", 50.0)];
        let c = context(&contact, &natural);
        let class = |f: f64, speed: f64| name(speed, &peak(f, speed), None, &c).0;
        assert_eq!(class(50.5, 100.0), NsvClass::SubSynchronousWhirl);
        assert_eq!(class(365.0, 100.0), NsvClass::VaryingCompliance);
        assert_eq!(class(730.0, 100.0), NsvClass::VaryingCompliance);
        assert_eq!(class(265.0, 100.0), NsvClass::Combination);
        assert_eq!(class(47.0, 200.0), NsvClass::Whip);
        assert_eq!(class(150.0, 100.0), NsvClass::SuperHarmonic);
        // The first mode ringing above a low running speed.
        assert_eq!(class(49.0, 30.0), NsvClass::Other);
        assert_eq!(class(20.0, 200.0), NsvClass::Other);
        // Falling by about 0.2 per stretch, twice: an exponential decay.
        let mut dying = peak(47.0, 200.0);
        dying.decay_ratio = 0.2;
        dying.settling_ratio = Some(0.25);
        assert_eq!(name(200.0, &dying, None, &c).0, NsvClass::Transient);
        // Steady, then falling: a beat, not a decay.
        dying.settling_ratio = Some(0.9);
        assert_eq!(name(200.0, &dying, None, &c).0, NsvClass::Whip);
        // Without the settling stretch, only a fall below TRANSIENT_DECAY counts.
        dying.settling_ratio = None;
        dying.decay_ratio = 0.3;
        assert_eq!(name(200.0, &dying, None, &c).0, NsvClass::Whip);
        dying.decay_ratio = 0.1;
        assert_eq!(name(200.0, &dying, None, &c).0, NsvClass::Transient);
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
