//! The speed bands where a sweep's synchronous orbit is unstable, read off the sweep's own
//! changes of stability ([`Bifurcation`]) and its points' verdicts: nothing is located
//! again.
//!
//! A band opens where the branch loses stability and closes where it regains it, each edge
//! named by the crossing Floquet multiplier: a fold (+1 where the branch turns: the orbit
//! jumps), symmetry breaking (+1 where it does not), period doubling (-1: a w/2 component
//! appears) or Neimark-Sacker (a complex pair: a component at the exponent's frequency,
//! not commensurate with w, appears: non-synchronous vibration). A band also opens or closes
//! at the ends of the branch and where the path jumped (a stretch not followed), named so.
//! The branch can fold, so a band's speeds are given in path order and as the span they
//! cover, and the stable stretches of the branch elsewhere that cover some of its speeds
//! are reported: there a stable synchronous orbit coexists with the unstable one.

use serde::{Deserialize, Serialize};

use crate::hbm::{Bifurcation, BifurcationKind, Branch};
use crate::units::rad_s_to_hz as hz;

/// What opens or closes an unstable band.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Edge {
    /// A change of stability located by the sweep.
    Bifurcation {
        /// Its kind, from the crossing multiplier.
        bifurcation: BifurcationKind,
        /// Frequency of the crossing exponent, Hz: the emerging component (w/2 at period
        /// doubling, the non-synchronous frequency at Neimark-Sacker, 0 at +1).
        emerging_hz: f64,
        /// Located on the branch (false: interpolated across the bracket reached).
        located: bool,
        /// Whether it holds at twice the samples and stability modes; `None` unchecked.
        resolved: Option<bool>,
    },
    /// The first point of the branch, already unstable.
    BranchStart,
    /// The last point of the branch, still unstable.
    BranchEnd,
    /// The path jumped here: what lies across was not followed.
    Jump,
}

impl Edge {
    /// A short name: the bifurcation's name, `branch start`, `branch end` or `jump`.
    pub fn name(&self) -> &'static str {
        match self {
            Edge::Bifurcation { bifurcation, .. } => bifurcation.name(),
            Edge::BranchStart => "branch start",
            Edge::BranchEnd => "branch end",
            Edge::Jump => "jump",
        }
    }

    /// The emerging frequency, Hz, at a bifurcation.
    pub fn emerging_hz(&self) -> Option<f64> {
        match self {
            Edge::Bifurcation { emerging_hz, .. } => Some(*emerging_hz),
            _ => None,
        }
    }

    fn of(b: &Bifurcation) -> Edge {
        Edge::Bifurcation {
            bifurcation: b.kind,
            emerging_hz: hz(b.exponent_frequency),
            located: b.located,
            resolved: b.resolution.map(|r| r.resolved),
        }
    }
}

/// A stretch of the branch, in path order, where the synchronous orbit is unstable.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct UnstableBand {
    /// Speed where it opens, Hz.
    pub opens_hz: f64,
    /// What opens it.
    pub opens: Edge,
    /// Speed where it closes, Hz (below `opens_hz` where the branch ran back in speed).
    pub closes_hz: f64,
    /// What closes it.
    pub closes: Edge,
    /// The lowest and highest speed the band covers, Hz.
    pub span_hz: [f64; 2],
    /// Stretches of speed within `span_hz` where a stable stretch of the same branch
    /// (elsewhere along the path) gives a stable synchronous orbit too, Hz, ascending.
    pub coexisting_stable_hz: Vec<[f64; 2]>,
    /// What grows inside the band, stretch by stretch in path order: the leading Floquet
    /// multiplier at its points (in a window between two points, with none inside, what
    /// crossed where it opened). A band opened by period doubling can go on unstable
    /// through a complex pair at quite another frequency, which no edge shows.
    pub growing: Vec<Growing>,
    /// The largest real part of the Floquet exponents at the band's points, 1/s: how fast
    /// the orbit is left (a tongue at a few per second against a whip band at hundreds);
    /// `None` for a window between two points, with no point inside.
    pub largest_growth_per_s: Option<f64>,
}

/// How the leading multiplier (the largest modulus) leaves the unit circle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Growth {
    /// Real and negative: a component at w/2 grows (period doubling).
    HalfSpeed,
    /// Real and positive: the orbit drifts to another (near a fold or symmetry breaking).
    Real,
    /// A complex pair: a component at the exponent's frequency grows (NSV).
    Complex,
}

impl Growth {
    /// A short name.
    pub fn name(self) -> &'static str {
        match self {
            Growth::HalfSpeed => "w/2",
            Growth::Real => "real",
            Growth::Complex => "complex",
        }
    }
}

/// A stretch of a band's points whose leading multiplier grows the same way.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Growing {
    /// How.
    pub growth: Growth,
    /// First and last speed of the stretch's points, Hz, in path order.
    pub speeds_hz: [f64; 2],
    /// Lowest and highest frequency of the growing component over the stretch, Hz (the
    /// exponent's, folded into 0 to w/2).
    pub frequency_hz: [f64; 2],
}

impl UnstableBand {
    /// The fraction of the band's span where a stable orbit coexists, 0 to 1.
    pub fn coexisting_fraction(&self) -> f64 {
        let width = self.span_hz[1] - self.span_hz[0];
        if width <= 0.0 {
            return 0.0;
        }
        let covered: f64 = self.coexisting_stable_hz.iter().map(|s| s[1] - s[0]).sum();
        (covered / width).min(1.0)
    }
}

/// A band being read: where it opened, and the points inside it.
struct Open {
    speed: f64,
    edge: Edge,
    points: Vec<usize>,
}

/// The unstable bands of `branch` in path order (none without stability).
pub fn unstable_bands(branch: &Branch) -> Vec<UnstableBand> {
    let mut bands = Vec::new();
    let mut open: Option<Open> = None;
    let points = &branch.points;
    let stable = |i: usize| points[i].stability.as_ref().map(|s| s.stable);
    let speed = |i: usize| hz(points[i].solution.frequency);
    for i in 0..points.len() {
        let Some(verdict) = stable(i) else {
            return Vec::new();
        };
        let jumped = i > 0 && branch.jumped_after.contains(&(i - 1));
        match (&mut open, verdict) {
            (None, false) if i == 0 || jumped => {
                let edge = if i == 0 {
                    Edge::BranchStart
                } else {
                    Edge::Jump
                };
                open = Some(Open {
                    speed: speed(i),
                    edge,
                    points: Vec::new(),
                });
            }
            (Some(o), true) if jumped => {
                let before = speed(i - 1);
                bands.push(close(branch, o, before, Edge::Jump));
                open = None;
            }
            _ => {}
        }
        if let Some(o) = &mut open {
            o.points.push(i);
        }
        for b in branch.bifurcations.iter().filter(|b| b.after == i) {
            open = step(branch, open, b, &mut bands);
        }
    }
    if let Some(o) = open {
        let last = points.len() - 1;
        bands.push(close(branch, &o, speed(last), Edge::BranchEnd));
    }
    bands
}

/// The band state after bifurcation `b`: opened at a loss, closed (into `bands`) at a
/// regain. A loss while open, or a regain while closed, cannot follow from the sweep's
/// alternating verdicts and leaves the state as it is.
fn step(
    branch: &Branch,
    open: Option<Open>,
    b: &Bifurcation,
    bands: &mut Vec<UnstableBand>,
) -> Option<Open> {
    match (open, b.loses_stability) {
        (None, true) => Some(Open {
            speed: hz(b.frequency),
            edge: Edge::of(b),
            points: Vec::new(),
        }),
        (Some(o), false) => {
            bands.push(close(branch, &o, hz(b.frequency), Edge::of(b)));
            None
        }
        (state, _) => state,
    }
}

/// The band `o` closed at `speed` by `edge`, with its span and the stable orbits that
/// coexist within it.
fn close(branch: &Branch, o: &Open, speed: f64, edge: Edge) -> UnstableBand {
    let inside = o
        .points
        .iter()
        .map(|&i| hz(branch.points[i].solution.frequency));
    let (lo, hi) = inside
        .chain([o.speed, speed])
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), w| {
            (lo.min(w), hi.max(w))
        });
    UnstableBand {
        opens_hz: o.speed,
        opens: o.edge,
        closes_hz: speed,
        closes: edge,
        span_hz: [lo, hi],
        coexisting_stable_hz: stable_within(branch, lo, hi),
        growing: growing(branch, &o.points)
            .unwrap_or_else(|| grows_by(&o.edge, lo, hi).into_iter().collect()),
        largest_growth_per_s: o
            .points
            .iter()
            .filter_map(|&i| branch.points[i].stability.as_ref())
            .map(|s| s.max_real)
            .reduce(f64::max),
    }
}

/// A multiplier counts as real when its imaginary part is below this share of its modulus:
/// the eigen-solver returns real ones with an imaginary part of exactly zero, and a complex
/// pair near the real axis has a frequency within a millionth of w/2 or 0 of it.
const REAL: f64 = 1e-6;

/// The leading multiplier's growth and frequency (Hz) at branch point `i`; `None` where the
/// point is stable or has no stability.
fn leading(branch: &Branch, i: usize) -> Option<(Growth, f64)> {
    let p = &branch.points[i];
    let s = p.stability.as_ref().filter(|s| !s.stable)?;
    let k = (0..s.multipliers.len()).max_by(|&a, &b| {
        let m = |j: usize| s.multipliers[j].0.hypot(s.multipliers[j].1);
        m(a).total_cmp(&m(b))
    })?;
    let (re, im) = s.multipliers[k];
    let growth = if im.abs() > REAL * re.hypot(im) {
        Growth::Complex
    } else if re < 0.0 {
        Growth::HalfSpeed
    } else {
        Growth::Real
    };
    Some((growth, hz(s.exponents[k].1.abs())))
}

/// What grows in a window between two path points (`lo`-`hi` Hz, no point inside to read):
/// what crossed at the bifurcation that opened it.
fn grows_by(edge: &Edge, lo: f64, hi: f64) -> Option<Growing> {
    let Edge::Bifurcation {
        bifurcation,
        emerging_hz,
        ..
    } = *edge
    else {
        return None;
    };
    let growth = match bifurcation {
        BifurcationKind::PeriodDoubling => Growth::HalfSpeed,
        BifurcationKind::NeimarkSacker => Growth::Complex,
        BifurcationKind::Fold | BifurcationKind::SymmetryBreaking => Growth::Real,
    };
    Some(Growing {
        growth,
        speeds_hz: [lo, hi],
        frequency_hz: [emerging_hz; 2],
    })
}

/// The stretches of `points` (a band's, in path order) whose leading multiplier grows the
/// same way; `None` when no point lies inside.
fn growing(branch: &Branch, points: &[usize]) -> Option<Vec<Growing>> {
    let mut out: Vec<Growing> = Vec::new();
    for &i in points {
        let Some((growth, f)) = leading(branch, i) else {
            continue;
        };
        let speed = hz(branch.points[i].solution.frequency);
        match out.last_mut() {
            Some(g) if g.growth == growth => {
                g.speeds_hz[1] = speed;
                g.frequency_hz = [g.frequency_hz[0].min(f), g.frequency_hz[1].max(f)];
            }
            _ => out.push(Growing {
                growth,
                speeds_hz: [speed, speed],
                frequency_hz: [f, f],
            }),
        }
    }
    (!points.is_empty()).then_some(out)
}

/// The speeds within [lo, hi] (Hz) that a stable stretch of `branch` covers: each segment
/// between two successive stable points (not across a jump) covers the speeds between
/// them; merged and ascending.
/// A window between two stable points (its bifurcations both lie after the first) is not
/// stable: it is left out of their segment.
fn stable_within(branch: &Branch, lo: f64, hi: f64) -> Vec<[f64; 2]> {
    let points = &branch.points;
    let stable = |i: usize| points[i].stability.as_ref().is_some_and(|s| s.stable);
    let window = |i: usize| {
        let inside = branch.bifurcations.iter().filter(|b| b.after == i);
        let (a, b) = inside.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(hz(x.frequency)), b.max(hz(x.frequency)))
        });
        (a < b).then_some([a, b])
    };
    spans_where(branch, stable, window, lo, hi)
}

/// The speeds (Hz) the branch was followed over: every segment between two successive
/// points, not across a jump; merged and ascending. Outside them the sweep says nothing.
pub fn followed_spans(branch: &Branch) -> Vec<[f64; 2]> {
    spans_where(branch, |_| true, |_| None, f64::NEG_INFINITY, f64::INFINITY)
}

/// The speeds within [lo, hi] (Hz) covered by the segments between successive points that
/// both satisfy `keep` (not across a jump), less each segment's `gap`, merged and
/// ascending.
fn spans_where(
    branch: &Branch,
    keep: impl Fn(usize) -> bool,
    gap: impl Fn(usize) -> Option<[f64; 2]>,
    lo: f64,
    hi: f64,
) -> Vec<[f64; 2]> {
    let points = &branch.points;
    let mut covered: Vec<[f64; 2]> = (0..points.len().saturating_sub(1))
        .filter(|&i| keep(i) && keep(i + 1) && !branch.jumped_after.contains(&i))
        .flat_map(|i| {
            let (a, b) = (
                hz(points[i].solution.frequency),
                hz(points[i + 1].solution.frequency),
            );
            let (a, b) = (a.min(b), a.max(b));
            let parts = match gap(i) {
                Some([g0, g1]) => [[a, g0], [g1, b]],
                None => [[a, b], [b, b]],
            };
            parts.map(|[x, y]| [x.max(lo), y.min(hi)])
        })
        .filter(|[a, b]| b > a)
        .collect();
    covered.sort_by(|x, y| x[0].total_cmp(&y[0]));
    let mut merged: Vec<[f64; 2]> = Vec::new();
    for s in covered {
        match merged.last_mut() {
            Some(m) if s[0] <= m[1] => m[1] = m[1].max(s[1]),
            _ => merged.push(s),
        }
    }
    merged
}
