//! Which parameter matters most: each sweep's effect on the largest NSV.
//!
//! The effect of a sweep is the relative change of the largest NSV over its range of
//! values, (max - min) / min over its points: 0 when the parameter changes nothing, 9 when
//! the largest NSV grows tenfold (thesis 5.1.1: "close to ten times"). A sweep whose
//! smallest NSV is zero (no non-synchronous peak at all at some value) has an unbounded
//! effect and ranks first. Per parameter, the largest effect among its sweeps stands for it.

use serde::Serialize;

/// One sweep's effect on the largest NSV.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Effect {
    /// The sweep's name.
    pub sweep: String,
    /// The parameter path it varies.
    pub parameter: String,
    /// Smallest largest-NSV over the sweep's points, m.
    pub smallest: f64,
    /// Largest largest-NSV over the sweep's points, m.
    pub largest: f64,
    /// (largest - smallest) / smallest; `None` when the smallest is zero (unbounded).
    pub relative_change: Option<f64>,
}

/// The effect of one sweep, from the largest NSV at each of its points (m, not negative).
/// `None` for a sweep of fewer than two points, which shows no change at all.
pub fn effect(sweep: &str, parameter: &str, nsv: &[f64]) -> Option<Effect> {
    if nsv.len() < 2 {
        return None;
    }
    let smallest = nsv.iter().copied().reduce(f64::min)?;
    let largest = nsv.iter().copied().reduce(f64::max)?;
    Some(Effect {
        sweep: sweep.to_string(),
        parameter: parameter.to_string(),
        smallest,
        largest,
        relative_change: (smallest > 0.0).then(|| (largest - smallest) / smallest),
    })
}

/// Sorts effects from the largest to the smallest (unbounded ones first).
pub fn rank(mut effects: Vec<Effect>) -> Vec<Effect> {
    let key = |e: &Effect| e.relative_change.unwrap_or(f64::INFINITY);
    effects.sort_by(|a, b| key(b).total_cmp(&key(a)));
    effects
}

/// One effect per parameter path: the largest among the sweeps of that parameter (a
/// parameter swept at several settings of the others matters as much as it can), from the
/// largest to the smallest.
pub fn by_parameter(effects: &[Effect]) -> Vec<Effect> {
    let mut best: Vec<Effect> = Vec::new();
    for e in rank(effects.to_vec()) {
        if !best.iter().any(|b| b.parameter == e.parameter) {
            best.push(e);
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranks_by_relative_change_with_unbounded_first() {
        let e = |name: &str, nsv: &[f64]| effect(name, "p", nsv).unwrap();
        let ranked = rank(vec![
            e("rollers", &[3e-5, 2.9e-5, 2.8e-5]),
            e("clearance", &[3e-5, 1.2e-4, 3e-4]),
            e("unbalance", &[0.0, 1e-6, 3e-5]),
        ]);
        let order: Vec<&str> = ranked.iter().map(|e| e.sweep.as_str()).collect();
        assert_eq!(order, ["unbalance", "clearance", "rollers"]);
        // (3e-4 - 3e-5) / 3e-5 = 9: a tenfold growth.
        assert!((ranked[1].relative_change.unwrap() - 9.0).abs() < 1e-12);
        assert!((ranked[2].relative_change.unwrap() - 0.2e-5 / 2.8e-5).abs() < 1e-12);
        assert_eq!(ranked[0].relative_change, None);
        // Per parameter, the larger of two sweeps of one parameter stands for it.
        let per = by_parameter(&[
            effect("rollers at 20 um", "rollers", &[3e-5, 2e-5]).unwrap(),
            effect("clearance", "clearance", &[3e-5, 3e-4]).unwrap(),
            effect("rollers at 120 um", "rollers", &[3e-4, 1e-4]).unwrap(),
        ]);
        let order: Vec<&str> = per.iter().map(|e| e.sweep.as_str()).collect();
        assert_eq!(order, ["clearance", "rollers at 120 um"]);
        assert!(effect("none", "p", &[]).is_none());
        assert!(effect("one point", "p", &[1e-5]).is_none());
    }
}
