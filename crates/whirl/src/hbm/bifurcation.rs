//! Where a branch loses or regains stability, and how, from the Floquet multipliers.
//!
//! Stability changes where a Floquet multiplier mu (an eigenvalue of the monodromy matrix,
//! [`super::stability`]) crosses the unit circle, and where it crosses names the bifurcation
//! (Seydel, "Practical Bifurcation and Stability Analysis", ch. 7; Nayfeh & Balachandran,
//! "Applied Nonlinear Dynamics", ch. 5):
//!
//! - a real multiplier at +1: a fold (turning point) when the branch turns there, otherwise
//!   a symmetry-breaking (pitchfork) or branch point;
//! - a real multiplier at -1: period doubling, a subharmonic at w/2 appears;
//! - a complex-conjugate pair exp(+-i theta): Neimark-Sacker, a component at theta / T
//!   (and its combinations k w +- theta / T) appears; this is where non-synchronous
//!   vibration starts.
//!
//! The monodromy matrix is real, so its real eigenvalues come out real (an imaginary part
//! of exactly zero) and the others in conjugate pairs. The kind is named by the
//! multipliers that have left the circle on the unstable side of the crossing, at the
//! unstable point nearest it (`crossing_kind`): one real multiplier is a +1 or -1
//! crossing, a complex one or two equal reals leaving together a pair. One multiplier read at the crossing cannot tell
//! them apart where a pair crosses at -1 (or +1): its imaginary part vanishes there, and
//! the regula falsi puts its trial points there. Each change found between two branch points is located by the
//! Illinois regula falsi on the largest real part of the exponents along the arclength,
//! every trial point corrected onto the branch and its monodromy matrix formed; the
//! multiplier is read where it crosses. Where a trial's arclength corrector fails (a
//! corner of a non-smooth branch, where a contact opens), the search goes on in the speed,
//! each trial solved by Newton at that fixed speed, which is well posed where the branch
//! does not turn: a crossing is then placed on the branch instead of between the path's
//! points, where it would move with where they fall.
//!
//! A window of the other verdict narrower than the spacing of the path's points shows in
//! no point's verdict; where the largest real part reaches an extremum towards zero at a
//! point, closer to zero than it varies to the neighbours, the stretch round it is probed
//! for one, and where a lightly damped mode of the orbit meets half a multiple of the
//! speed between two stable points, that stretch is sampled for a parametric tongue
//! (period doubling at half an odd multiple, a real multiplier through +1 at a whole one;
//! its multiplier need not set the largest real part); both edges of a window found are
//! located as above.

use super::arclength::{arclength_frame, correct, interpolated_orbit};
use super::balance::HbSolution;
use super::branch::{BranchPoint, Fold};
use super::parallel::on_threads;
use super::periodic::Periodic;
use super::stability::{outside_circle, OrbitMode, Stability};
use crate::error::Result;
use crate::linalg::{difference, norm};

pub use super::branch::{Bifurcation, BifurcationKind};

/// A multiplier is real when its imaginary part is below this fraction of its modulus:
/// the real Schur form gives real eigenvalues an imaginary part of exactly zero, and a
/// complex pair this close to the axis would be a collision of two real multipliers,
/// resolved to round-off only.
const ON_AXIS: f64 = 1e-9;

/// The regula falsi stops when the speeds of the bracket's ends are within this fraction
/// of each other (5 mHz at 500 Hz, 0.4 mHz at 40 Hz; the last step's interpolation makes
/// a simple crossing more accurate still), or the bracket is this short in the search's
/// parameter, or after [`MAX_TRIALS`] trial points. The speed is what is reported (to
/// 0.01 Hz in the text summary): along the arclength, where the orbit changes much faster
/// than the speed (a resonance's flank), a bracket of 1e-5 in scaled arclength took up to
/// 10 more trials for a speed already within 1e-5 (BENCHMARKS.md, harmonic balance).
/// What the answer resolves is far coarser: the AFT sample count moves the reference
/// rotor's bifurcations by 0.1 to 2 Hz, and each is checked at 0.5 % of its speed either
/// side ([`super::resolution`]). Where the largest real part jumps across zero (a contact
/// opening at a corner) the bracket only halves per trial: 1e-7 cost 7 more trials each
/// there. A trial whose arclength corrector fails is
/// solved at fixed speed instead, and where Newton stalls there too (a time sample at a
/// contact's edge, where the contact damping makes the force jump) the bracket's middle
/// is tried before the crossing is left interpolated across the bracket reached.
const BRACKET: f64 = 1e-5;
const MAX_TRIALS: usize = 40;

/// The changes of stability along `points`, each located on the branch, except across
/// `boundaries` (indices after which the path jumped), on `problems` (copies of one
/// problem, one a thread: [`on_threads`]). `folds` are the branch's turning points: a +1
/// crossing in the same interval is that fold.
///
/// # Errors
/// When the Floquet problem cannot be built (a singular mass matrix).
pub(super) fn locate_bifurcations<H: Periodic + Send>(
    problems: &mut [&mut H],
    points: &[BranchPoint],
    folds: &[Fold],
    boundaries: &[usize],
) -> Result<Vec<Bifurcation>> {
    let changes = points
        .windows(2)
        .enumerate()
        .filter(|(i, pair)| {
            let verdicts = (&pair[0].stability, &pair[1].stability);
            let change = matches!(verdicts, (Some(a), Some(b)) if a.stable != b.stable);
            change && !boundaries.contains(i)
        })
        .map(|(i, _)| Stretch::Change(i));
    let windows = (1..points.len().saturating_sub(1))
        .filter(|&i| {
            let turns = folds.iter().any(|f| f.after + 1 == i || f.after == i);
            !(turns || boundaries.contains(&(i - 1)) || boundaries.contains(&i))
        })
        .map(Stretch::Window);
    let tongues = points
        .windows(2)
        .enumerate()
        .filter(|(i, _)| !(folds.iter().any(|f| f.after == *i) || boundaries.contains(i)))
        .flat_map(|(i, pair)| {
            [Side::MinusOne, Side::PlusOne]
                .into_iter()
                .filter(|&side| may_split_between(&pair[0], &pair[1], side))
                .map(move |side| Stretch::Tongue(i, side))
        });
    let stretches: Vec<Stretch> = changes.chain(windows).chain(tongues).collect();
    let found = on_threads(problems, stretches.len(), |hb, k| match stretches[k] {
        Stretch::Change(i) => change_after(&mut **hb, points, folds, i),
        Stretch::Window(i) => window_round(&mut **hb, points, i),
        Stretch::Tongue(i, side) => tongue_after(&mut **hb, points, i, side),
    })?;
    let mut found: Vec<Bifurcation> = found.into_iter().flatten().collect();
    in_path_order(&mut found, points);
    // A window lies between two points of the same verdict, where no other change is;
    // the two probes can find the same one.
    found.dedup_by(|a, b| {
        a.after == b.after
            && a.loses_stability == b.loses_stability
            && (a.frequency - b.frequency).abs() <= 10.0 * BRACKET * b.frequency
    });
    Ok(found)
}

/// Sorts `found` in the order the path meets them: by stretch, and within a stretch by
/// speed the way the path goes there. Past a fold the path goes down in speed, and two
/// changes in one stretch (a window's edges) read in speed order would swap which one
/// opens the window and which closes it (the reference rotor at 120 um: a window at
/// 387.05-387.07 Hz on the way down from the 436.9 Hz fold read that way closed the band
/// there, and the orbit, unstable up to 750 Hz, was mapped stable).
fn in_path_order(found: &mut [Bifurcation], points: &[BranchPoint]) {
    let downward = |i: usize| {
        points
            .get(i + 1)
            .is_some_and(|next| next.solution.frequency < points[i].solution.frequency)
    };
    found.sort_by(|a, b| {
        let by_speed = a.frequency.total_cmp(&b.frequency);
        let along = if downward(a.after) {
            by_speed.reverse()
        } else {
            by_speed
        };
        a.after.cmp(&b.after).then(along)
    });
}

/// Where a change of stability is sought: between points i and i + 1 of different
/// verdicts, round point i ([`probe`]), or between stable points i and i + 1 where a
/// multiplier may leave the circle at -1 or +1 ([`tongue_after`]).
#[derive(Clone, Copy)]
enum Stretch {
    Change(usize),
    Window(usize),
    Tongue(usize, Side),
}

/// Where a parametric tongue's multiplier leaves the unit circle: the orbit's stiffness,
/// periodic at the speed w, drives a mode of frequency w_i unstable where w_i is half a
/// multiple of w, k w / 2, the multiplier exp(i w_i T) then at (-1)^k.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Side {
    /// At -1, where w_i = (m + 1/2) w: period doubling.
    MinusOne,
    /// At +1, where w_i = m w (m >= 1): a real multiplier grows, as at symmetry breaking
    /// (reference rotor, 60 um: a 0.7 Hz tongue at 30.5-31.2 Hz, exponent up to +6.6/s,
    /// where a mode near 122 Hz meets 4 w, between points at 29.1 and 31.6 Hz).
    PlusOne,
}

impl Side {
    /// w_i / w at a meeting, less a whole number.
    fn offset(self) -> f64 {
        match self {
            Side::MinusOne => 0.5,
            Side::PlusOne => 0.0,
        }
    }

    /// The least whole number m of a meeting at m + [`Side::offset`]: a mode meeting 0 w
    /// is a static one, not a resonance.
    fn first(self) -> f64 {
        match self {
            Side::MinusOne => 0.0,
            Side::PlusOne => 1.0,
        }
    }
}

/// The change of stability between points `i` and `i + 1` (of different verdicts). A +1
/// crossing where the branch turns between them is the fold, whether or not the fold
/// locator placed the turn on the branch (where it fell back to the Hermite estimate the
/// crossing used to be named symmetry breaking: 5 changes at 60 and 120 um).
fn change_after(
    hb: &mut impl Periodic,
    points: &[BranchPoint],
    folds: &[Fold],
    i: usize,
) -> Result<Vec<Bifurcation>> {
    let (p, q) = (&points[i], &points[i + 1]);
    let (Some(a), Some(b)) = (&p.stability, &q.stability) else {
        return Ok(Vec::new());
    };
    let fold = folds.iter().find(|f| f.after == i && f.refined);
    let turns = folds.iter().any(|f| f.after == i);
    let crossing = match fold {
        // The exponent crosses zero as the square root of the distance at a fold,
        // which regula falsi converges to slowly: the fold is already on the branch.
        Some(f) => {
            let unstable = if a.stable { b.clone() } else { a.clone() };
            Located {
                frequency: f.frequency,
                located: true,
                nearest: unstable.clone(),
                unstable,
            }
        }
        None => crossing(hb, (p, a), (q, b), turns)?,
    };
    Ok(vec![classify(crossing, i, a.stable, turns)])
}

/// The window of the other verdict round point `i`, if [`probe`] finds one: its two
/// changes of stability.
fn window_round(
    hb: &mut impl Periodic,
    points: &[BranchPoint],
    i: usize,
) -> Result<Vec<Bifurcation>> {
    match probe(hb, &points[i - 1..=i + 1])? {
        Some((k, inside)) => {
            let (before, after) = (&points[i - 1 + k], &points[i + k]);
            window(hb, before, &inside, after, i - 1 + k)
        }
        None => Ok(Vec::new()),
    }
}

/// The two changes of stability round `inside`, a point of the branch between `before`
/// and `after` (both of the other verdict), in path order; `after_index` is `before`'s.
fn window(
    hb: &mut impl Periodic,
    before: &BranchPoint,
    inside: &BranchPoint,
    after: &BranchPoint,
    after_index: usize,
) -> Result<Vec<Bifurcation>> {
    let (Some(sa), Some(si), Some(sb)) = (&before.stability, &inside.stability, &after.stability)
    else {
        return Ok(Vec::new());
    };
    let into = crossing(hb, (before, sa), (inside, si), false)?;
    let out = crossing(hb, (inside, si), (after, sb), false)?;
    Ok(vec![
        classify(into, after_index, sa.stable, false),
        classify(out, after_index, si.stable, false),
    ])
}

/// Trial points a window's probe spends at most on one extremum.
const PROBE_TRIALS: usize = 8;

/// A period-doubling tongue opens where a lightly damped mode of the orbit meets half an
/// odd multiple of the speed, w_i = (m + 1/2) w (its multiplier exp(i w_i T) at -1): the
/// parametric resonance the map also draws as a line; at a whole multiple the same holds
/// at +1 ([`Side`]). Its multiplier pair closes on -1
/// like the square root of the distance to the collision, and the multiplier that leaves
/// is not the least damped at the path's points, so neither the points' verdicts nor g's
/// extremum show it (reference rotor, 28 um: a 0.3 Hz tongue at 34.9-35.2 Hz, where the
/// second mode's forward whirl meets 7.5 w, between points at 34.6 and 36.6 Hz). The
/// mode's frequency is that of the orbit's averaged linearisation ([`OrbitMode`]), not the
/// exponent itself (there 7.54 w, 0.5 % off), so a meeting within this much of w_i / w
/// either side of the stretch counts.
const HALF_ORDER_MARGIN: f64 = 0.01;

/// The highest w_i / w sought: a tongue at w_i = k w / 2 is a parametric resonance of the
/// bearings' stiffness harmonic k along the orbit, and those above the 16th are too weak
/// to open one (the reference rotor's highest found: w_i = 7.5 w).
const MAX_HALF_ORDER: f64 = 8.0;

/// The least modulus of the meeting mode's multiplier, exp(-zeta w_i T / sqrt(1 - zeta^2)):
/// the two reals a pair of modulus r splits into keep their product near r^2, so the
/// larger reaches 1 only if the smaller falls to about r^2; below a half that asks a split
/// of more than four to one (the reference rotor's 28 um tongue opens from a pair of 0.74).
const LIVELY_MODULUS: f64 = 0.5;

/// Evenly spaced speeds sampled between two such points before the meeting mode's
/// multiplier is followed by parabolas: a tongue 0.3 Hz wide in a split stretch 0.6 Hz
/// wide, between points 2 Hz apart, falls on one of them.
const TONGUE_SAMPLES: usize = 2;

/// The largest modulus of a real multiplier on `side`'s half of the axis: what leaves the
/// circle there, once its pair has met the axis.
fn split_on_axis(s: &Stability, side: Side) -> f64 {
    s.multipliers
        .iter()
        .filter(|&&(re, _)| (re < 0.0) == (side == Side::MinusOne) && re != 0.0)
        .filter(|&&(re, im)| im.abs() <= ON_AXIS * re.abs())
        .map(|(re, _)| re.abs())
        .fold(0.0, f64::max)
}

/// Whether a tongue on `side` may hide between two stable points: a mode of the orbit
/// whose multiplier is at least [`LIVELY_MODULUS`] meets w_i = (m + [`Side::offset`]) w
/// there.
fn may_split_between(a: &BranchPoint, b: &BranchPoint, side: Side) -> bool {
    let (Some(sa), Some(sb)) = (&a.stability, &b.stability) else {
        return false;
    };
    if !(sa.stable && sb.stable) {
        return false;
    }
    let (wa, wb) = (a.solution.frequency, b.solution.frequency);
    let lively = |m: &OrbitMode, w: f64| {
        let zeta = m.damping_ratio.clamp(0.0, 0.999);
        let decay = zeta * m.frequency / (1.0 - zeta * zeta).sqrt();
        (-decay * std::f64::consts::TAU / w).exp() >= LIVELY_MODULUS
    };
    sa.orbit_modes.iter().zip(&sb.orbit_modes).any(|(ma, mb)| {
        let (ra, rb) = (ma.frequency / wa, mb.frequency / wb);
        let margin = HALF_ORDER_MARGIN * ra.max(rb);
        let (low, high) = (ra.min(rb) - side.offset(), ra.max(rb) - side.offset());
        let meets = (low - margin).ceil().max(side.first()) <= (high + margin).floor();
        meets && ra.min(rb) <= MAX_HALF_ORDER && (lively(ma, wa) || lively(mb, wb))
    })
}

/// The tongue on `side` between stable points `i` and `i + 1`, if one is found: the
/// g-probe ([`probe`]) misses it, because the multiplier that leaves the circle need not
/// be the least damped one at the points (g is set by another, or is flat), and it leaves
/// within a fraction of a hertz of where its pair met the axis. [`TONGUE_SAMPLES`] speeds
/// between the points are solved (Newton at fixed speed: the stretch does not turn); where
/// one of them or of the points holds a real multiplier on `side` of at least
/// [`LIVELY_MODULUS`] (the pair has split), the largest is followed by successive
/// parabolas round the best, at most [`PROBE_TRIALS`] more points. The first unstable
/// point found is the inside of a window, whose edges are located as [`window`] does.
fn tongue_after(
    hb: &mut impl Periodic,
    points: &[BranchPoint],
    i: usize,
    side: Side,
) -> Result<Vec<Bifurcation>> {
    let (before, after) = (&points[i], &points[i + 1]);
    let (Some(sa), Some(sb)) = (&before.stability, &after.stability) else {
        return Ok(Vec::new());
    };
    let level = |s: &Stability| split_on_axis(s, side).max(f64::MIN_POSITIVE).ln();
    let mut ends = vec![
        End::new(
            before.solution.frequency,
            level(sa),
            before.solution.clone(),
        ),
        End::new(after.solution.frequency, level(sb), after.solution.clone()),
    ];
    let (wa, wb) = (ends[0].at, ends[1].at);
    let inside = |point: HbSolution, verdict: Stability| BranchPoint {
        solution: point,
        frequency_slope: before.frequency_slope,
        stability: Some(verdict),
    };
    for k in 1..=TONGUE_SAMPLES {
        let w = wa + (wb - wa) * k as f64 / (TONGUE_SAMPLES + 1) as f64;
        let Some((point, verdict)) = judged_at(hb, &ends[0], &ends[ends.len() - 1], w)? else {
            return Ok(Vec::new());
        };
        if !verdict.stable {
            return window(hb, before, &inside(point, verdict), after, i);
        }
        let end = End::new(w, level(&verdict), point);
        ends.insert(ends.len() - 1, end);
    }
    if ends.iter().all(|e| e.max_real < LIVELY_MODULUS.ln()) {
        return Ok(Vec::new());
    }
    match unstable_round_largest(hb, ends, level)? {
        Some((point, verdict)) => window(hb, before, &inside(point, verdict), after, i),
        None => Ok(Vec::new()),
    }
}

/// The largest of `ends` (`level` of their verdicts) followed by successive parabolas round
/// the best, at most [`PROBE_TRIALS`] more points: the first unstable point found, with
/// its verdict ([`tongue_after`]).
fn unstable_round_largest(
    hb: &mut impl Periodic,
    mut ends: Vec<End>,
    level: impl Fn(&Stability) -> f64,
) -> Result<Option<(HbSolution, Stability)>> {
    // Ascending in speed whichever way the path went; the best interior end and its two
    // neighbours bracket the largest.
    ends.sort_by(|x, y| x.at.total_cmp(&y.at));
    let best = (1..ends.len() - 1)
        .max_by(|&x, &y| ends[x].max_real.total_cmp(&ends[y].max_real))
        .unwrap_or(1);
    let mut three = ends.drain(best - 1..=best + 1);
    let (Some(mut lo), Some(mut mid), Some(mut hi)) = (three.next(), three.next(), three.next())
    else {
        return Ok(None);
    };
    for _ in 0..PROBE_TRIALS {
        if hi.at - lo.at < BRACKET * mid.at.abs() {
            break;
        }
        let w = vertex(&lo, &mid, &hi);
        let Some((point, verdict)) = judged_within(hb, [&lo, &mid, &hi], w)? else {
            break;
        };
        if !verdict.stable {
            return Ok(Some((point, verdict)));
        }
        let trial = End::new(w, level(&verdict), point);
        (lo, mid, hi) = best_bracketed(lo, mid, hi, trial);
    }
    Ok(None)
}

/// A window of the other verdict narrower than the spacing of the path's points lies
/// between two points of the same verdict, where g, the largest real part of the
/// exponents, reaches an extremum towards zero. `three` are successive points of one
/// verdict; where the middle one's g is such an extremum and closer to zero than g varies
/// to either neighbour, the extremum between them is sought by successive parabolic
/// interpolation in the speed (Newton at fixed speed, the stretch does not turn), at most
/// [`PROBE_TRIALS`] points. For a smooth g sampled at equal spacing the parabola through
/// three points rises above the middle one by at most a quarter of its larger difference
/// to the other two: the margin leaves a factor of 4 for uneven spacing and the corners
/// of a non-smooth branch. The first trial point of the other verdict found, and whether
/// it lies after the first (0) or the second (1) of `three`; `None` when the extremum
/// stays of the points' verdict (to [`BRACKET`] of the speed) or moves away from zero.
fn probe(hb: &mut impl Periodic, three: &[BranchPoint]) -> Result<Option<(usize, BranchPoint)>> {
    let verdicts: Vec<&Stability> = three.iter().filter_map(|p| p.stability.as_ref()).collect();
    let [first, middle, last] = verdicts[..] else {
        return Ok(None);
    };
    let stable = middle.stable;
    if first.stable != stable || last.stable != stable {
        return Ok(None);
    }
    // g turned towards zero: negative on both verdicts, largest at the extremum sought.
    let toward = |g: f64| if stable { g } else { -g };
    let end = |p: &BranchPoint, s: &Stability| {
        End::new(p.solution.frequency, toward(s.max_real), p.solution.clone())
    };
    let (mut lo, mut mid, mut hi) = (
        end(&three[0], first),
        end(&three[1], middle),
        end(&three[2], last),
    );
    if lo.at > hi.at {
        std::mem::swap(&mut lo, &mut hi);
    }
    let centre = mid.at;
    for _ in 0..PROBE_TRIALS {
        let rise = (mid.max_real - lo.max_real).max(mid.max_real - hi.max_real);
        let extremum = mid.max_real > lo.max_real && mid.max_real > hi.max_real;
        if !extremum || -mid.max_real >= rise || hi.at - lo.at < BRACKET * centre {
            return Ok(None);
        }
        let w = vertex(&lo, &mid, &hi);
        let Some((point, verdict)) = judged_within(hb, [&lo, &mid, &hi], w)? else {
            return Ok(None);
        };
        if verdict.stable != stable {
            // Between the first two points when on the first's side of the middle one.
            let side = usize::from((w - centre) * (three[0].solution.frequency - centre) < 0.0);
            let inside = BranchPoint {
                solution: point,
                frequency_slope: three[side].frequency_slope,
                stability: Some(verdict),
            };
            return Ok(Some((side, inside)));
        }
        let trial = End::new(w, toward(verdict.max_real), point);
        (lo, mid, hi) = best_bracketed(lo, mid, hi, trial);
    }
    Ok(None)
}

/// The branch point at speed `w` within the bracket `[lo, mid, hi]` (Newton from the
/// interpolation of the two ends round `w`) and its stability; `None` where Newton fails.
fn judged_within(
    hb: &mut impl Periodic,
    [lo, mid, hi]: [&End; 3],
    w: f64,
) -> Result<Option<(HbSolution, Stability)>> {
    let (a, b) = if w < mid.at { (lo, mid) } else { (mid, hi) };
    judged_at(hb, a, b, w)
}

/// The branch point at speed `w` between `a` and `b` ([`at_speed`]) and its stability;
/// `None` where Newton fails.
fn judged_at(
    hb: &mut impl Periodic,
    a: &End,
    b: &End,
    w: f64,
) -> Result<Option<(HbSolution, Stability)>> {
    let Some(point) = at_speed(hb, a, b, w) else {
        return Ok(None);
    };
    let verdict = hb
        .floquet_problem(&point.coefficients, point.frequency)?
        .solve()?;
    Ok(Some((point, verdict)))
}

/// The bracket after `trial`: the largest value kept as the middle, bracketed by its two
/// neighbours.
fn best_bracketed(lo: End, mid: End, hi: End, trial: End) -> (End, End, End) {
    match (trial.max_real > mid.max_real, trial.at < mid.at) {
        (true, true) => (lo, trial, mid),
        (true, false) => (mid, trial, hi),
        (false, true) => (trial, mid, hi),
        (false, false) => (lo, mid, trial),
    }
}

/// The speed of the vertex of the parabola through the three ends (by speed, values
/// `max_real`), or the middle of the larger half of the bracket where the vertex is not
/// strictly inside it or falls on the middle end (a percent of the bracket from it).
fn vertex(lo: &End, mid: &End, hi: &End) -> f64 {
    let (x0, x1, x2) = (lo.at, mid.at, hi.at);
    let (y0, y1, y2) = (lo.max_real, mid.max_real, hi.max_real);
    let p = (x1 - x0).powi(2) * (y1 - y2) - (x1 - x2).powi(2) * (y1 - y0);
    let q = (x1 - x0) * (y1 - y2) - (x1 - x2) * (y1 - y0);
    let x = x1 - 0.5 * p / q;
    let inside = x > x0 && x < x2 && (x - x1).abs() > 0.01 * (x2 - x0);
    if inside {
        x
    } else if x1 - x0 > x2 - x1 {
        0.5 * (x0 + x1)
    } else {
        0.5 * (x1 + x2)
    }
}

/// Where the largest real part crosses zero, the stability nearest the crossing, and the
/// unstable one nearest it.
struct Located {
    frequency: f64,
    located: bool,
    nearest: Stability,
    unstable: Stability,
}

/// One end of a regula falsi bracket: a point on the branch, where it lies in the search's
/// parameter, and the largest real part of its exponents (as the Illinois rule weights it,
/// and as it is).
struct End {
    at: f64,
    weighted: f64,
    max_real: f64,
    solution: HbSolution,
}

impl End {
    fn new(at: f64, max_real: f64, solution: HbSolution) -> End {
        End {
            at,
            weighted: max_real,
            max_real,
            solution,
        }
    }

    /// The same point as an end of a search in another parameter, unweighted.
    fn moved_to(self, at: f64) -> End {
        End::new(at, self.max_real, self.solution)
    }
}

/// A crossing's search: the trial points spent, the stability nearest the crossing so
/// far (the crossing exponent is the one with the largest real part on both sides, so it
/// is read at the trial where that is smallest in magnitude), and the unstable one
/// nearest it (the smallest largest real part above zero), whose multipliers outside the
/// circle are the ones that cross.
struct Search {
    trials: usize,
    nearest: Stability,
    unstable: Stability,
}

/// Where g(s), the largest real part of the exponents at the branch point with parameter
/// s, crosses zero between `before` and `after`. First along the arclength from `before`
/// (its tangent, each trial corrected onto the branch). Should a trial's corrector fail (a
/// corner between the points), at fixed speed between the two nearest points found so
/// far: Newton from their interpolation, well posed where the branch does not turn between
/// them (`turns` false), so that the speed is a parameter of the branch. Only where both
/// fail is the crossing interpolated linearly between those two points (`located`
/// false); it then depends on where they fall. A failed arclength trial costs a plain and
/// a line-search corrector run (on the reference rotor about 65 condensations, against one
/// for a trial at fixed speed), and the search at fixed speed tries the bracket's middle
/// itself, so the arclength search tries it only where no search at fixed speed follows.
fn crossing(
    hb: &mut impl Periodic,
    (before, sa): (&BranchPoint, &Stability),
    (after, sb): (&BranchPoint, &Stability),
    turns: bool,
) -> Result<Located> {
    let unstable = if sa.stable { sb.clone() } else { sa.clone() };
    let mut search = Search {
        trials: 0,
        nearest: unstable.clone(),
        unstable,
    };
    let mut a = End::new(0.0, sa.max_real, before.solution.clone());
    let mut b = End::new(0.0, sb.max_real, after.solution.clone());
    if let Ok((y0, t0, chord_length, scaling)) =
        arclength_frame(hb, &before.solution, &after.solution)
    {
        let along =
            |hb: &mut _, _: &End, _: &End, sigma| correct(hb, &y0, &t0, sigma, &scaling).ok();
        let (reached_a, reached_b, located) =
            search.narrow(hb, a, b.moved_to(chord_length), turns, along)?;
        if located {
            return Ok(search.interpolated(&reached_a, &reached_b, true));
        }
        (a, b) = (reached_a, reached_b);
    }
    if turns {
        return Ok(search.interpolated(&a, &b, false));
    }
    // The speed relative to `before`'s, so the bracket is the same relative change.
    let w0 = before.solution.frequency;
    let (wa, wb) = (a.solution.frequency / w0, b.solution.frequency / w0);
    let at = |hb: &mut _, a: &End, b: &End, at| at_speed(hb, a, b, at * w0);
    let (a, b, located) = search.narrow(hb, a.moved_to(wa), b.moved_to(wb), true, at)?;
    Ok(search.interpolated(&a, &b, located))
}

impl Search {
    /// Illinois regula falsi between `a` and `b` (values of opposite signs) with trial
    /// points `trial(hb, a, b, s)`, until the bracket is shorter than [`BRACKET`] in the
    /// parameter or in the relative speed (true) or a trial fails (false); with
    /// `middle`, a failed trial is tried again at the bracket's middle first. The bracket
    /// reached, either way.
    fn narrow<H: Periodic>(
        &mut self,
        hb: &mut H,
        mut a: End,
        mut b: End,
        middle: bool,
        mut trial: impl FnMut(&mut H, &End, &End, f64) -> Option<HbSolution>,
    ) -> Result<(End, End, bool)> {
        let mut kept_side = 0;
        while self.trials < MAX_TRIALS && !bracketed(&a, &b) {
            let falsi = (a.at * b.weighted - b.at * a.weighted) / (b.weighted - a.weighted);
            self.trials += 1;
            // Newton stalls where a time sample sits at a contact's edge (the contact
            // damping makes the force jump there); the bracket's middle moves the samples off
            // it.
            let halfway = 0.5 * (a.at + b.at);
            let Some((at, point)) = [falsi, halfway]
                .into_iter()
                .take(if middle { 2 } else { 1 })
                .find_map(|at| Some((at, trial(hb, &a, &b, at)?)))
            else {
                return Ok((a, b, false));
            };
            let verdict = hb
                .floquet_problem(&point.coefficients, point.frequency)?
                .solve()?;
            let g = verdict.max_real;
            if !verdict.stable && g < self.unstable.max_real {
                self.unstable = verdict.clone();
            }
            if g.abs() < self.nearest.max_real.abs() {
                self.nearest = verdict;
            }
            let end = End::new(at, g, point);
            // Illinois: halve the value kept twice in a row, so both ends move.
            if g * a.max_real > 0.0 {
                a = end;
                if kept_side == 1 {
                    b.weighted /= 2.0;
                }
                kept_side = 1;
            } else {
                b = end;
                if kept_side == -1 {
                    a.weighted /= 2.0;
                }
                kept_side = -1;
            }
        }
        Ok((a, b, true))
    }

    /// The crossing between the ends `a` and `b`: the largest real part is linear in the
    /// parameter through a simple crossing, so it is interpolated linearly in the speed
    /// across a bracket narrowed to [`BRACKET`] (`located`), and across whatever the
    /// search reached otherwise.
    fn interpolated(self, a: &End, b: &End, located: bool) -> Located {
        let (wa, wb) = (a.solution.frequency, b.solution.frequency);
        let u = a.max_real / (a.max_real - b.max_real);
        Located {
            frequency: wa + u * (wb - wa),
            located,
            nearest: self.nearest,
            unstable: self.unstable,
        }
    }
}

/// Whether the ends `a` and `b` lie within [`BRACKET`] of each other in the search's
/// parameter or in the speed, relative.
fn bracketed(a: &End, b: &End) -> bool {
    let (wa, wb) = (a.solution.frequency, b.solution.frequency);
    (b.at - a.at).abs() < BRACKET || (wb - wa).abs() < BRACKET * wa.abs()
}

/// The branch point at speed `frequency` between the ends `a` and `b`: Newton at that
/// speed from the linear interpolation of their orbits. Newton at a fixed speed may find
/// another orbit where several coexist; one farther from the interpolation than the ends
/// are from each other is not on this stretch and is refused.
fn at_speed(hb: &mut impl Periodic, a: &End, b: &End, frequency: f64) -> Option<HbSolution> {
    let guess = interpolated_orbit(&a.solution, &b.solution, frequency);
    let solution = hb.solve(frequency, &guess).ok()?;
    let spread = difference(&b.solution.coefficients, &a.solution.coefficients);
    (norm(&difference(&solution.coefficients, &guess)) <= norm(&spread)).then_some(solution)
}

/// The bifurcation at `crossing`: its kind from the multipliers that have left the circle
/// on its unstable side ([`crossing_kind`]), the multiplier and its frequency from the
/// multiplier of largest modulus nearest it.
fn classify(crossing: Located, after: usize, loses_stability: bool, at_fold: bool) -> Bifurcation {
    let w = crossing.frequency;
    let kind = crossing_kind(&crossing.unstable, at_fold);
    let (re, im) = largest(&crossing.nearest.multipliers).unwrap_or((1.0, 0.0));
    let period = std::f64::consts::TAU / w;
    Bifurcation {
        kind,
        frequency: w,
        located: crossing.located,
        multiplier: (re, im.abs()),
        exponent_frequency: im.abs().atan2(re) / period,
        after,
        loses_stability,
        resolution: None,
    }
}

/// The multiplier of largest modulus.
fn largest(multipliers: &[(f64, f64)]) -> Option<(f64, f64)> {
    multipliers
        .iter()
        .copied()
        .max_by(|x, y| x.0.hypot(x.1).total_cmp(&y.0.hypot(y.1)))
}

/// Two real multipliers within this fraction of each other are a conjugate pair that meets
/// the real axis: a pair whose imaginary part is below [`ON_AXIS`] can come out of the
/// eigen-solver as two reals split by round-off (about 1e-16 of |Phi| where the pair is
/// semisimple, as with a symmetric rotor's two whirls; up to its square root, 1e-8, where it
/// is about to split), while two distinct real multipliers that leave the circle at the
/// same speed, other than such a pair, would be a coincidence.
const PAIR: f64 = 1e-6;

/// The kind of a crossing, named by the multiplier of largest modulus of `unstable` (the
/// unstable point nearest it) and by how many outside the unit circle share it; `at_fold`
/// when the branch turns there. Complex, or real with a twin outside the circle equal to
/// [`PAIR`], it is a pair crossing: Neimark-Sacker, whatever its angle (at exactly -1 or +1
/// a pair's two exponents sit at +-w/2 or 0 as a real multiplier's would, and the locator's
/// trial points crowd there). Real and alone, it names the crossing by its sign: through +1
/// a fold where the branch turns and symmetry breaking elsewhere, through -1 period
/// doubling. The largest, not any multiplier outside, because a point a resolution check
/// reads 0.5 % away can hold the multipliers of earlier crossings outside as well.
pub(super) fn crossing_kind(unstable: &Stability, at_fold: bool) -> BifurcationKind {
    let (re, im) = largest(&unstable.multipliers).unwrap_or((1.0, 0.0));
    let complex = im.abs() > ON_AXIS * re.hypot(im);
    let twins = unstable
        .multipliers
        .iter()
        .filter(|&&m| outside_circle(m) && (m.0 - re).abs() <= PAIR * re.abs())
        .count();
    match (complex || twins >= 2, re > 0.0) {
        (true, _) => BifurcationKind::NeimarkSacker,
        (false, false) => BifurcationKind::PeriodDoubling,
        (false, true) if at_fold => BifurcationKind::Fold,
        (false, true) => BifurcationKind::SymmetryBreaking,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stability with these multipliers at w.
    fn stability(frequency: f64, multipliers: Vec<(f64, f64)>) -> Stability {
        let period = std::f64::consts::TAU / frequency;
        let exponents: Vec<(f64, f64)> = multipliers
            .iter()
            .map(|&(re, im)| (re.hypot(im).ln() / period, im.atan2(re) / period))
            .collect();
        let max_real = exponents.iter().map(|e| e.0).fold(f64::MIN, f64::max);
        Stability {
            multipliers,
            exponents,
            max_real,
            stable: max_real * period < 1e-10,
            orbit_modes: Vec::new(),
        }
    }

    /// A crossing at w whose nearest trial has these multipliers, and its nearest unstable
    /// one the same multipliers grown by 1e-6.
    fn crossing(frequency: f64, multipliers: Vec<(f64, f64)>) -> Located {
        let grown = multipliers
            .iter()
            .map(|&(re, im)| (1.000001 * re, 1.000001 * im))
            .collect();
        Located {
            frequency,
            located: true,
            nearest: stability(frequency, multipliers),
            unstable: stability(frequency, grown),
        }
    }

    /// A path point at w, stable or not, with nothing else of a solution.
    fn point(frequency: f64) -> BranchPoint {
        BranchPoint {
            solution: HbSolution {
                frequency,
                coefficients: Vec::new(),
                iterations: 0,
                relative_residual: 0.0,
            },
            frequency_slope: 0.0,
            stability: None,
        }
    }

    #[test]
    fn changes_are_listed_in_the_order_the_path_meets_them() {
        // Up from 1 to 3, past a fold, down to 2: a window's edges in each stretch.
        let points: Vec<BranchPoint> = [1.0, 3.0, 2.0].into_iter().map(point).collect();
        let change = |frequency: f64, after: usize, loses_stability: bool| {
            let mut b = classify(
                crossing(frequency, vec![(-1.000001, 0.0)]),
                after,
                true,
                false,
            );
            b.loses_stability = loses_stability;
            b
        };
        let mut found = vec![
            change(2.4, 1, true),
            change(2.6, 1, false),
            change(1.6, 0, false),
            change(1.4, 0, true),
        ];
        in_path_order(&mut found, &points);
        let order: Vec<(f64, bool)> = found
            .iter()
            .map(|b| (b.frequency, b.loses_stability))
            .collect();
        assert_eq!(
            order,
            [(1.4, true), (1.6, false), (2.6, false), (2.4, true)]
        );
    }

    #[test]
    fn crossing_multipliers_name_the_bifurcation() {
        let w = 10.0;
        let kind = |multipliers, fold| classify(crossing(w, multipliers), 0, true, fold).kind;
        let on_circle = |turns: f64| {
            let a = std::f64::consts::TAU * turns;
            (1.000001 * a.cos(), 1.000001 * a.sin())
        };
        // A complex pair at +-0.3 turns, with a damped real multiplier.
        let (c, s) = on_circle(0.3);
        assert_eq!(
            kind(vec![(c, s), (c, -s), (0.2, 0.0)], false),
            BifurcationKind::NeimarkSacker
        );
        // A complex pair close to -1 (0.49 turns) is still a pair.
        let (c, s) = on_circle(0.49);
        assert_eq!(
            kind(vec![(c, s), (c, -s)], false),
            BifurcationKind::NeimarkSacker
        );
        // One real multiplier through -1.
        let doubling = vec![(-1.000001, 0.0), (0.3, 0.1), (0.3, -0.1)];
        assert_eq!(kind(doubling, false), BifurcationKind::PeriodDoubling);
        // A real multiplier through +1: a fold where the branch turns, symmetry breaking
        // elsewhere.
        let real = vec![(1.000001, 0.0), (0.3, 0.2), (0.3, -0.2)];
        assert_eq!(kind(real.clone(), true), BifurcationKind::Fold);
        assert_eq!(kind(real, false), BifurcationKind::SymmetryBreaking);
    }

    #[test]
    fn a_pair_on_the_real_axis_is_told_from_one_real_multiplier_by_the_count() {
        let kind = |multipliers| crossing_kind(&stability(10.0, multipliers), false);
        // A pair at -1 whose imaginary part is below round-off, or split into two reals by
        // it: both have left the circle.
        let pair = vec![(-1.00001, 2e-13), (-1.00001, -2e-13), (0.5, 0.0)];
        assert_eq!(kind(pair), BifurcationKind::NeimarkSacker);
        let split = vec![(-1.00001, 0.0), (-1.0000100000001, 0.0), (0.5, 0.0)];
        assert_eq!(kind(split), BifurcationKind::NeimarkSacker);
        // Two real multipliers near -1, one outside: period doubling.
        let one = vec![(-1.00001, 0.0), (-0.99, 0.0), (0.5, 0.0)];
        assert_eq!(kind(one), BifurcationKind::PeriodDoubling);
        // Two distinct reals outside: the largest names it.
        let two = vec![(-1.3, 0.0), (1.1, 0.0)];
        assert_eq!(kind(two), BifurcationKind::PeriodDoubling);
    }

    #[test]
    fn the_emerging_frequency_is_the_multiplier_s_angle_per_period() {
        // A pair at +-i: a quarter turn per period T = 2 pi / 10, so 2.5 rad/s.
        let b = classify(
            crossing(10.0, vec![(0.0, 1.0), (0.0, -1.0)]),
            3,
            false,
            false,
        );
        assert_eq!(b.kind, BifurcationKind::NeimarkSacker);
        assert_eq!(b.multiplier, (0.0, 1.0));
        assert!((b.exponent_frequency - 2.5).abs() < 1e-15);
        assert!(!b.loses_stability && b.after == 3);
        // Period doubling: half a turn, w / 2.
        let b = classify(crossing(10.0, vec![(-1.0, 0.0)]), 0, true, false);
        assert!((b.exponent_frequency - 5.0).abs() < 1e-15);
    }
}
