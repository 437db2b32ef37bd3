//! What the largest non-synchronous peak at each speed is: the mechanism behind it, named
//! from how its frequency moves with the running speed, the lines beside it and the
//! bearings' contact frequencies (docs/theory.md section 8; thesis 5.1).
//!
//! The evidence is gathered in [`super::trend`]: the slope `df/dOmega` of the NSV line over
//! the settled neighbours within a window in hertz of speed, and its companions `k Omega -+
//! f` in the point's own spectrum. The rotor-whirl classes carry the whirl direction from
//! the full spectrum of x + i y (forward when the component at +f is the larger, planar
//! when the two are equal within [`PLANAR_FLATNESS`] or their measurement: a line orbit,
//! whose direction round-off would decide): whip is forward precession locked at a natural
//! frequency, and a backward or planar whirl locked the same way is `backward-whip` or
//! `planar-whip`, never plain whip.
//!
//! A point whose run did not settle (see [`crate::nsv`]: its largest non-synchronous peak was
//! still dying away at the longest settling time) is **unsettled**, whatever its frequency;
//! it is never an NSV of any other class. Otherwise the first rule that holds names the
//! peak (`tol` is the cascade's tolerance, `tolerance_bins` times the bin spacing; `s` the
//! slope where it was measured). The rules ask for different slopes, so their order
//! matters only where a frequency fits two mechanisms' ratios:
//!
//! 1. **subharmonic** (`forward-` or `backward-subharmonic`): within `tol` of `Omega/n`
//!    (`n` = 2, 3), moving at `1/n` (`s` within [`SLOPE_TOLERANCE`] of it), or with no
//!    slope measured. A locked whip that crosses `Omega/2` is not one; one that crosses
//!    `Omega/3` while drifting at 0.2-0.3 would be (the slopes overlap there, and the
//!    exact ratio decides).
//! 2. **varying compliance**: within `tol` of `m f_c` or `|m f_c +- n Omega|` (`f_c` a
//!    bearing's `N_b w_c` or waviness frequency `(N_w - 1) w_c`, eq. 4.4; `m` = 1..3,
//!    `n` = 1..8, the sidebands only where the running speed exceeds 4 `tol`, below which
//!    they pack so densely that any frequency would match one), and moving in proportion
//!    to the speed (`s` within [`SLOPE_TOLERANCE`] plus a tenth of `f/Omega` of `f/Omega`),
//!    or with no slope measured. Largest where it meets a natural frequency (the
//!    explanation says so): a varying-compliance resonance.
//! 3. **whip** (`forward-whip`, `backward-whip`), locked: below 1X and `|s|` at most
//!    [`LOCKED_SLOPE`]: the frequency stays at a natural frequency of the rotor on its
//!    contacts while the speed changes (the thesis' "frequency-locked phenomenon"); the
//!    nearest natural frequency of the linearised rotor is named (the contact stiffness is
//!    not the linear one, so it is only near). Above 1X a locked line is a mode ringing:
//!    **other**.
//! 4. **combination resonance** (`forward-` or `backward-combination-resonance`): `|s|`
//!    above [`LOCKED_SLOPE`], and a companion at
//!    `k Omega - f` (sum type `f + f_j = k Omega`) or `k Omega + f` (difference type) in
//!    its spectrum: a frequency that moves with the speed, with `k` or less where the
//!    partner mode is pulled along.
//! 5. **whip**, unmeasured: no settled neighbour within the window shows the line, the peak
//!    is below 1X and within [`NATURAL_TOLERANCE`] of a linearised natural frequency.
//! 6. **super-harmonic**: above 1X and not explained above.
//! 7. **other**: what is left, with its slope where measured (a line that moves without a
//!    companion, or a locked one above 1X).

use serde::{Deserialize, Serialize, Serializer};

use super::point::{CascadePoint, NsvPeak};
use super::trend::{self, Companion, Lines, Reading, Trend};

/// With no slope measured, a sub-synchronous peak within this fraction of a linearised
/// natural frequency is whip.
pub const NATURAL_TOLERANCE: f64 = 0.1;

/// A line moving by at most this many hertz per hertz of speed is locked. The reference
/// rotor's whips hold within 0.1 where they are steady and drift by up to 0.3 where the
/// irregular whip's frequency wanders by a few hertz from speed to speed (20 um clearance,
/// 230-270 Hz); its combination resonance moves by 0.8-1.1 (20 um, 580-600 Hz).
pub const LOCKED_SLOPE: f64 = 0.3;

/// A line moves in proportion to the speed when its slope is within this (plus a tenth of
/// its order, for the steep super-synchronous tones) of its order `f/Omega`: a
/// tolerance-wide step of speed (two bins) reads a slope to about a quarter of a bin over
/// two bins, 0.125, before the median over the neighbours.
pub const SLOPE_TOLERANCE: f64 = 0.15;

/// Sidebands `|m f_c +- n Omega|` are named only when the running speed exceeds this many
/// tolerances.
const COMBINATION_SPACING: f64 = 4.0;

/// Multiples m of a contact frequency tried ...
const MAX_CONTACT_MULTIPLE: usize = 3;
/// ... and n of the running speed in its sidebands: the reference rotor shows
/// `n Omega - N_b w_c` up to `n` = 8 (4.35X at 510 Hz).
const MAX_SPEED_MULTIPLE: usize = 8;

/// Orders n of the subharmonics `Omega/n` named (from the fourth on, at slope 1/4 or less,
/// the slope would not tell them from a lock).
const MAX_SUBHARMONIC: usize = 3;

/// An orbit whose minor axis is under this fraction of its major one is planar: a line,
/// not a whirl in either direction.
pub const PLANAR_FLATNESS: f64 = 0.05;

/// Whirl direction of a peak, from the full spectrum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum WhirlDirection {
    /// With the spin (its +frequency component is the larger).
    Forward,
    /// Against the spin.
    Backward,
    /// Neither: the two components are equal within the orbit's flatness limit or their
    /// measurement, so the orbit is a line whose direction round-off would decide.
    Planar,
}

impl WhirlDirection {
    /// `forward`, `backward` or `planar`.
    pub fn name(self) -> &'static str {
        match self {
            WhirlDirection::Forward => "forward",
            WhirlDirection::Backward => "backward",
            WhirlDirection::Planar => "planar",
        }
    }

    /// The direction of an orbit with circular components `forward` (at +f) and `backward`
    /// (at -f), each known to `relative_error`. The orbit's minor axis over its major is
    /// |F - B| / (F + B); below [`PLANAR_FLATNESS`], or below twice the standard error of
    /// F - B (`relative_error` sqrt(F^2 + B^2)), the orbit is planar: the reference rotor's
    /// locked whips on anisotropic contacts have orbits this flat, and their larger
    /// component changed with the last bit of the contact solve.
    pub fn of(forward: f64, backward: f64, relative_error: f64) -> Self {
        let difference = forward - backward;
        let undecided = (PLANAR_FLATNESS * (forward + backward))
            .max(2.0 * relative_error * forward.hypot(backward));
        if difference.abs() <= undecided {
            WhirlDirection::Planar
        } else if difference > 0.0 {
            WhirlDirection::Forward
        } else {
            WhirlDirection::Backward
        }
    }
}

/// What kind of non-synchronous vibration a peak is (rules in the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum NsvClass {
    /// At `Omega/n` and moving at `1/n`, whirling this way.
    Subharmonic(WhirlDirection),
    /// Locked near a natural frequency while the speed changes, whirling this way.
    Whip(WhirlDirection),
    /// Moving with the speed, with a companion at `k Omega -+ f`: whirling this way.
    CombinationResonance(WhirlDirection),
    /// A multiple of a bearing's varying-compliance (or waviness) frequency, or a sideband
    /// of one with the running speed.
    VaryingCompliance,
    /// Above 1X, at no multiple of it, not otherwise explained.
    SuperHarmonic,
    /// None of the above.
    Other,
    /// The start had not died away at the longest settling time: no NSV.
    Unsettled,
}

impl NsvClass {
    /// Every class, in the order of the module documentation's list.
    pub const ALL: [NsvClass; 13] = [
        NsvClass::Subharmonic(WhirlDirection::Forward),
        NsvClass::Subharmonic(WhirlDirection::Backward),
        NsvClass::Subharmonic(WhirlDirection::Planar),
        NsvClass::VaryingCompliance,
        NsvClass::Whip(WhirlDirection::Forward),
        NsvClass::Whip(WhirlDirection::Backward),
        NsvClass::Whip(WhirlDirection::Planar),
        NsvClass::CombinationResonance(WhirlDirection::Forward),
        NsvClass::CombinationResonance(WhirlDirection::Backward),
        NsvClass::CombinationResonance(WhirlDirection::Planar),
        NsvClass::SuperHarmonic,
        NsvClass::Other,
        NsvClass::Unsettled,
    ];

    /// Name as in tables: `forward-whip`, `backward-combination-resonance`, ...
    pub fn name(self) -> &'static str {
        use WhirlDirection::{Backward, Forward, Planar};
        match self {
            NsvClass::Subharmonic(Forward) => "forward-subharmonic",
            NsvClass::Subharmonic(Backward) => "backward-subharmonic",
            NsvClass::Subharmonic(Planar) => "planar-subharmonic",
            NsvClass::Whip(Forward) => "forward-whip",
            NsvClass::Whip(Backward) => "backward-whip",
            NsvClass::Whip(Planar) => "planar-whip",
            NsvClass::CombinationResonance(Forward) => "forward-combination-resonance",
            NsvClass::CombinationResonance(Backward) => "backward-combination-resonance",
            NsvClass::CombinationResonance(Planar) => "planar-combination-resonance",
            NsvClass::VaryingCompliance => "varying-compliance",
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
    /// Why: `Omega/2`, `N_b w_c - 1X (bearing A)`, `locked: 0.01 Hz per Hz ...`, ...
    pub explanation: String,
    /// Forward or backward whirl.
    pub direction: WhirlDirection,
    /// How fast its frequency moves with the running speed, Hz per Hz (median over the
    /// settled neighbours within the window that show the line); `None` where no
    /// neighbour does, or the point did not settle.
    pub slope: Option<f64>,
}

/// What the classification of one speed knows besides its spectrum.
pub(super) struct Context<'a> {
    /// Contact frequencies at this speed.
    pub contact: &'a [NamedFrequency],
    /// Natural frequencies of the linearised rotor at this speed.
    pub natural: &'a [NamedFrequency],
}

/// How close two speeds' NSV frequencies must be to count as one line, Hz: the tolerance,
/// or 2 % of the frequency (a whip drifts a little as the contact stiffness changes with
/// speed), whichever is larger.
pub fn lock_tolerance(frequency_hz: f64, tolerance_hz: f64) -> f64 {
    tolerance_hz.max(0.02 * frequency_hz)
}

/// The evidence about one settled peak.
struct Evidence<'a> {
    speed_hz: f64,
    peak: NsvPeak,
    direction: WhirlDirection,
    trend: Option<Trend>,
    companion: Option<Companion>,
    context: &'a Context<'a>,
    tolerance_hz: f64,
}

/// Classifies every point's peak; `reading` says how the points' spectra were taken.
pub(super) fn classify(
    points: &[CascadePoint],
    contexts: &[Context<'_>],
    reading: &Reading,
) -> Vec<Option<Nsv>> {
    let lines: Vec<Lines> = points.iter().map(|p| Lines::of(p, reading)).collect();
    points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let peak = p.peak?;
            let direction = WhirlDirection::of(
                peak.forward_m,
                peak.backward_m,
                peak.standard_error_m / peak.amplitude_m,
            );
            if !p.settled {
                let why = format!(
                    "still dying away after {:.2} s: {:.2} of its amplitude per half record",
                    p.settle_s, peak.decay_ratio
                );
                return Some(Nsv {
                    speed_hz: p.speed_hz,
                    peak,
                    class: NsvClass::Unsettled,
                    explanation: why,
                    direction,
                    slope: None,
                });
            }
            let evidence = Evidence {
                speed_hz: p.speed_hz,
                peak,
                direction,
                trend: trend::trend(points, &lines, i, reading),
                companion: trend::companion(p, &lines[i], reading),
                context: &contexts[i],
                tolerance_hz: reading.tolerance_hz,
            };
            let (class, explanation) = name(&evidence);
            Some(Nsv {
                speed_hz: p.speed_hz,
                peak,
                class,
                explanation,
                direction,
                slope: evidence.trend.map(|t| t.slope),
            })
        })
        .collect()
}

/// Class and explanation of a settled peak, by the rules of the module documentation.
fn name(e: &Evidence<'_>) -> (NsvClass, String) {
    let f = e.peak.frequency_hz;
    let slope = e.trend.map(|t| t.slope);
    let sub = f < e.speed_hz;
    if let Some(n) = subharmonic(e) {
        let why = format!("Omega/{n}{}", moving(e.trend));
        return (NsvClass::Subharmonic(e.direction), why);
    }
    if let Some(tone) = contact_match(e) {
        let why = format!("{tone}{}{}", moving(e.trend), at_natural(f, e.context));
        return (NsvClass::VaryingCompliance, why);
    }
    if let Some(s) = slope {
        if s.abs() <= LOCKED_SLOPE {
            let why = format!("locked{}{}", moving(e.trend), near_natural(f, e.context));
            if sub {
                return (NsvClass::Whip(e.direction), why);
            }
            return (NsvClass::Other, format!("{why}, above 1X: a mode ringing"));
        }
        if let Some(c) = e.companion {
            let why = format!("{}{}", partner(&c), moving(e.trend));
            return (NsvClass::CombinationResonance(e.direction), why);
        }
    }
    let near = nearest_natural(f, e.context)
        .filter(|n| (f - n.frequency_hz).abs() <= NATURAL_TOLERANCE * n.frequency_hz);
    if let (None, true, Some(n)) = (slope, sub, near) {
        let why = format!(
            "near {} ({:.1} Hz); no neighbour within {:.0} Hz shows whether it is locked",
            n.name,
            n.frequency_hz,
            trend::window_hz(e.tolerance_hz)
        );
        return (NsvClass::Whip(e.direction), why);
    }
    let why = format!("{:.3}X{}", e.peak.order, moving(e.trend));
    if f > e.speed_hz {
        return (NsvClass::SuperHarmonic, why);
    }
    let no_companion = if slope.is_some() {
        ", no companion at k Omega -+ f"
    } else {
        ""
    };
    (NsvClass::Other, format!("{why}{no_companion}"))
}

/// The subharmonic order `n` whose `Omega/n` the peak sits at and moves with.
fn subharmonic(e: &Evidence<'_>) -> Option<usize> {
    (2..=MAX_SUBHARMONIC).find(|&n| {
        let order = 1.0 / n as f64;
        (e.peak.frequency_hz - order * e.speed_hz).abs() <= e.tolerance_hz
            && e.trend
                .is_none_or(|t| (t.slope - order).abs() <= SLOPE_TOLERANCE)
    })
}

/// Whether a slope `s` is that of a line proportional to the speed at `order`.
fn proportional(s: f64, order: f64) -> bool {
    (s - order).abs() <= SLOPE_TOLERANCE + 0.1 * order
}

/// `: 0.84 Hz per Hz over 584.1-604.2 Hz (9 speeds)`, or nothing without a trend.
fn moving(trend: Option<Trend>) -> String {
    trend.map_or(String::new(), |t| {
        format!(
            ": {:.2} Hz per Hz over {:.1}-{:.1} Hz ({} speeds)",
            t.slope,
            t.span_hz.0,
            t.span_hz.1,
            t.neighbours + 1
        )
    })
}

/// `, near mode 1 backward (49.5 Hz)`, naming the nearest linearised natural frequency.
fn near_natural(f: f64, c: &Context<'_>) -> String {
    nearest_natural(f, c).map_or(String::new(), |n| {
        format!(", near {} ({:.1} Hz)", n.name, n.frequency_hz)
    })
}

/// `, at mode 1 backward (49.5 Hz)` where `f` is within [`NATURAL_TOLERANCE`] of a
/// linearised natural frequency (a varying-compliance resonance), else nothing.
fn at_natural(f: f64, c: &Context<'_>) -> String {
    nearest_natural(f, c)
        .filter(|n| (f - n.frequency_hz).abs() <= NATURAL_TOLERANCE * n.frequency_hz)
        .map_or(String::new(), |n| {
            format!(", at {} ({:.1} Hz)", n.name, n.frequency_hz)
        })
}

/// `f + 545.1 Hz = 1X` (sum type) or `546.3 Hz - f = 1X` (difference type), with the
/// companion's share of the NSV.
fn partner(c: &Companion) -> String {
    let k = format!("{}X", c.order);
    let relation = if c.sum {
        format!("f + {:.1} Hz = {k}", c.frequency_hz)
    } else {
        format!("{:.1} Hz - f = {k}", c.frequency_hz)
    };
    format!("{relation} (companion {:.1} % of it)", 100.0 * c.relative)
}

/// The natural frequency nearest `f`.
fn nearest_natural<'a>(f: f64, c: &'a Context<'_>) -> Option<&'a NamedFrequency> {
    c.natural.iter().min_by(|a, b| {
        (a.frequency_hz - f)
            .abs()
            .total_cmp(&(b.frequency_hz - f).abs())
    })
}

/// The contact tone `m f_c` or `|m f_c +- n Omega|` within the tolerance of the peak that
/// moves as it should (see the module documentation), named.
fn contact_match(e: &Evidence<'_>) -> Option<String> {
    let (f, speed_hz, tol) = (e.peak.frequency_hz, e.speed_hz, e.tolerance_hz);
    let sidebands = if speed_hz > COMBINATION_SPACING * tol {
        MAX_SPEED_MULTIPLE
    } else {
        0
    };
    let follows = e.trend.is_none_or(|t| proportional(t.slope, f / speed_hz));
    if !follows {
        return None;
    }
    let multiple = |m: usize, name: &str| {
        if m == 1 {
            name.to_string()
        } else {
            format!("{m} {name}")
        }
    };
    for base in e.context.contact {
        for m in 1..=MAX_CONTACT_MULTIPLE {
            let fm = m as f64 * base.frequency_hz;
            if (f - fm).abs() <= tol {
                return Some(multiple(m, &base.name));
            }
            for n in 1..=sidebands {
                let fn_ = n as f64 * speed_hz;
                for (sign, value) in [("+", fm + fn_), ("-", (fm - fn_).abs())] {
                    if (f - value).abs() <= tol {
                        return Some(format!("{} {sign} {n}X", multiple(m, &base.name)));
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
    use crate::post::Window;

    /// Bin spacing of the synthetic spectra, Hz (the default 0.5 s record), ...
    const DF: f64 = 2.0;
    /// ... and the default tolerance of two bins.
    const TOL: f64 = 4.0;
    /// The reference rotor's roller passage frequency over the running speed,
    /// `N_b (1 - D_b/D_p) / 2`.
    const PASSAGE_ORDER: f64 = 8.0 * (1.0 - 6.1 / 69.6) / 2.0;

    fn reading() -> Reading {
        Reading {
            resolution_hz: DF,
            window: Window::Hann,
            tolerance_hz: TOL,
        }
    }

    /// A spectral line: frequency (Hz) and amplitude (m).
    type Line = (f64, f64);

    /// A settled point at `speed_hz` whose spectrum holds a 100 um 1X, a floor of 1e-10 m,
    /// the NSV `nsv` (whirling backward if `backward`) and the other `lines`, each as the
    /// Hann window's main lobe.
    fn point(speed_hz: f64, nsv: Line, backward: bool, lines: &[Line]) -> CascadePoint {
        let bins = (3.0 * speed_hz.max(nsv.0) / DF) as usize + 8;
        let mut amplitude = vec![1e-10; bins];
        for &(f, a) in [(speed_hz, 1e-4), nsv].iter().chain(lines) {
            let at = f / DF;
            let first = (at - 2.0).ceil().max(0.0) as usize;
            for (k, bin) in amplitude.iter_mut().enumerate().skip(first).take(4) {
                let delta = (k as f64 - at).abs();
                if delta < 2.0 {
                    *bin += a * Window::Hann.response(delta);
                }
            }
        }
        let (major, minor) = (nsv.1, 0.2 * nsv.1);
        let (forward_m, backward_m) = if backward {
            (minor, major)
        } else {
            (major, minor)
        };
        let peak = NsvPeak {
            frequency_hz: nsv.0,
            amplitude_m: nsv.1,
            order: nsv.0 / speed_hz,
            forward_m,
            backward_m,
            decay_ratio: 1.0,
            settling_ratio: Some(1.0),
            standard_error_m: 0.0,
            variation: 0.0,
        };
        let mut p = CascadePoint::settled_at(speed_hz, 1e-4, Some(peak));
        p.amplitude = amplitude;
        p
    }

    fn named(name: &str, frequency_hz: f64) -> NamedFrequency {
        NamedFrequency {
            name: name.into(),
            frequency_hz,
        }
    }

    /// Classes of `points` with the reference rotor's roller passage frequency and first
    /// natural frequencies at each speed.
    fn classes(points: &[CascadePoint]) -> Vec<NsvClass> {
        let contact: Vec<[NamedFrequency; 1]> = points
            .iter()
            .map(|p| [named("N_b w_c", PASSAGE_ORDER * p.speed_hz)])
            .collect();
        let natural = [
            named("mode 1 backward", 49.5),
            named("mode 1 forward", 50.5),
        ];
        let contexts: Vec<Context<'_>> = contact
            .iter()
            .map(|c| Context {
                contact: c,
                natural: &natural,
            })
            .collect();
        classify(points, &contexts, &reading())
            .into_iter()
            .map(|n| n.map_or(NsvClass::Other, |n| n.class))
            .collect()
    }

    /// Speeds from `first` to `last` Hz in steps of `step`.
    fn speeds(first: f64, last: f64, step: f64) -> Vec<f64> {
        let n = ((last - first) / step).round() as usize;
        (0..=n).map(|k| first + k as f64 * step).collect()
    }

    /// The reference rotor's 20 um maximum as measured with 0.5 Hz bins: backward, sliding
    /// at 0.84 Hz per Hz through 49.5 Hz at 594.8 Hz, with its partner at Omega - f (0.8 %
    /// of it); `companion` false leaves the partner out.
    fn sliding(speed_hz: f64, companion: bool) -> CascadePoint {
        let f = 49.5 + 0.84 * (speed_hz - 594.8);
        let lines = if companion {
            vec![(speed_hz - f, 1.2e-6)]
        } else {
            Vec::new()
        };
        point(speed_hz, (f, 1.5e-4), true, &lines)
    }

    /// The 60 um maximum: a forward whip at 48.4-48.7 Hz over 496-539 Hz, with the
    /// intermodulation companions Omega -+ f (0.4 % and 0.2 %) that every whip has.
    fn locked(speed_hz: f64) -> CascadePoint {
        let f = 48.4 + 0.007 * (speed_hz - 496.0);
        let lines = [(speed_hz - f, 2e-6), (speed_hz + f, 1e-6)];
        point(speed_hz, (f, 4.5e-4), false, &lines)
    }

    #[test]
    fn a_locked_line_is_whip_even_with_companions() {
        let points: Vec<_> = speeds(496.0, 539.0, 5.0).into_iter().map(locked).collect();
        for class in classes(&points) {
            assert_eq!(class, NsvClass::Whip(WhirlDirection::Forward));
        }
    }

    #[test]
    fn a_line_sliding_with_its_companion_is_a_combination_resonance() {
        let with: Vec<_> = speeds(586.0, 602.0, 2.0)
            .into_iter()
            .map(|w| sliding(w, true))
            .collect();
        for class in classes(&with) {
            assert_eq!(
                class,
                NsvClass::CombinationResonance(WhirlDirection::Backward)
            );
        }
        // The same slide with no partner line is not explained.
        let without: Vec<_> = speeds(586.0, 602.0, 2.0)
            .into_iter()
            .map(|w| sliding(w, false))
            .collect();
        for class in classes(&without) {
            assert_eq!(class, NsvClass::Other);
        }
    }

    #[test]
    fn a_refined_or_reordered_grid_names_the_same() {
        let coarse: Vec<_> = speeds(580.0, 610.0, 5.0)
            .into_iter()
            .map(|w| sliding(w, true))
            .collect();
        let mut fine: Vec<_> = speeds(580.0, 610.0, 0.5)
            .into_iter()
            .map(|w| sliding(w, true))
            .collect();
        fine.reverse();
        let expected = NsvClass::CombinationResonance(WhirlDirection::Backward);
        assert!(classes(&coarse).iter().all(|&c| c == expected));
        assert!(classes(&fine).iter().all(|&c| c == expected));
    }

    #[test]
    fn a_subharmonic_moves_at_one_over_n() {
        for n in [2.0, 3.0] {
            let points: Vec<_> = speeds(300.0, 340.0, 5.0)
                .into_iter()
                .map(|w| point(w, (w / n, 1e-5), false, &[]))
                .collect();
            for class in classes(&points) {
                assert_eq!(class, NsvClass::Subharmonic(WhirlDirection::Forward));
            }
        }
    }

    #[test]
    fn a_locked_line_crossing_half_speed_is_whip() {
        let points: Vec<_> = speeds(85.0, 115.0, 5.0)
            .into_iter()
            .map(|w| point(w, (49.4, 2e-6), true, &[]))
            .collect();
        // At 100 Hz the line sits at Omega/2, within the tolerance: still a lock.
        for class in classes(&points) {
            assert_eq!(class, NsvClass::Whip(WhirlDirection::Backward));
        }
    }

    #[test]
    fn varying_compliance_lines_and_sidebands_follow_the_speed() {
        // N_b w_c crossing the first natural frequency at 13.6 Hz running speed.
        let resonance: Vec<_> = speeds(9.0, 19.0, 0.5)
            .into_iter()
            .map(|w| point(w, (PASSAGE_ORDER * w, 2e-5), false, &[]))
            .collect();
        // 7X - N_b w_c, 3.351X, over 380-420 Hz.
        let sideband: Vec<_> = speeds(380.0, 420.0, 5.0)
            .into_iter()
            .map(|w| point(w, ((7.0 - PASSAGE_ORDER) * w, 2e-7), true, &[]))
            .collect();
        for class in classes(&resonance).into_iter().chain(classes(&sideband)) {
            assert_eq!(class, NsvClass::VaryingCompliance);
        }
    }

    #[test]
    fn a_point_without_neighbours_falls_back_on_the_natural_frequencies() {
        let near = [point(300.0, (47.0, 1e-5), false, &[])];
        assert_eq!(classes(&near), [NsvClass::Whip(WhirlDirection::Forward)]);
        let far = [point(300.0, (20.0, 1e-5), false, &[])];
        assert_eq!(classes(&far), [NsvClass::Other]);
        let above = [point(300.0, (450.0, 1e-5), false, &[])];
        assert_eq!(classes(&above), [NsvClass::SuperHarmonic]);
    }

    #[test]
    fn a_line_orbit_has_no_direction() {
        use WhirlDirection::{Backward, Forward, Planar};
        // The 32-roller locked whip whose larger component changed with round-off (um,
        // relative standard error 0.6 %): planar both ways.
        assert_eq!(WhirlDirection::of(46.09, 46.35, 0.006), Planar);
        assert_eq!(WhirlDirection::of(46.58, 46.09, 0.006), Planar);
        // Minor axis 2 % of the major, measured exactly: still a line.
        assert_eq!(WhirlDirection::of(10.0, 9.6, 0.0), Planar);
        // Minor axis 11 % of the major: a whirl when measured to 1 %, not when to 10 %
        // (the difference, 2, is within twice its error 0.1 x 12.8).
        assert_eq!(WhirlDirection::of(10.0, 8.0, 0.01), Forward);
        assert_eq!(WhirlDirection::of(8.0, 10.0, 0.01), Backward);
        assert_eq!(WhirlDirection::of(10.0, 8.0, 0.1), Planar);
        // A circle each way.
        assert_eq!(WhirlDirection::of(1.0, 0.0, 0.0), Forward);
        assert_eq!(WhirlDirection::of(0.0, 1.0, 0.0), Backward);
    }

    #[test]
    fn a_locked_line_orbit_is_planar_whip() {
        let mut p = point(300.0, (47.0, 1e-5), false, &[]);
        let peak = p.peak.as_mut().unwrap();
        (peak.forward_m, peak.backward_m) = (5.0e-6, 5.1e-6);
        assert_eq!(classes(&[p]), [NsvClass::Whip(WhirlDirection::Planar)]);
    }

    #[test]
    fn an_unsettled_point_has_no_other_class() {
        let mut p = point(300.0, (47.0, 1e-5), false, &[]);
        (p.settled, p.settle_s, p.records) = (false, 4.0, 1);
        assert_eq!(classes(std::slice::from_ref(&p)), [NsvClass::Unsettled]);
        p.settled = true;
        let class = classes(std::slice::from_ref(&p));
        assert_eq!(class, [NsvClass::Whip(WhirlDirection::Forward)]);
    }

    #[test]
    fn every_name_is_distinct() {
        let mut names: Vec<&str> = NsvClass::ALL.iter().map(|c| c.name()).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), NsvClass::ALL.len());
    }
}
