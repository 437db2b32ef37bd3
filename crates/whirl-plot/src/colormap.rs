//! The colour map of heat maps: viridis.
//!
//! Viridis (van der Walt and Smith, matplotlib 2.0) is perceptually uniform, reads in grey scale
//! and suits the common forms of colour blindness. We interpolate linearly between nine samples of
//! the matplotlib table, which is indistinguishable from the 256-entry table at plot scale.

/// Viridis at t = 0, 1/8, ..., 1.
const VIRIDIS: [(u8, u8, u8); 9] = [
    (68, 1, 84),
    (71, 45, 123),
    (59, 82, 139),
    (44, 114, 142),
    (33, 145, 140),
    (40, 174, 128),
    (94, 201, 98),
    (173, 220, 48),
    (253, 231, 37),
];

/// Colour of cells without a value (NaN, or not positive on a logarithmic colour scale).
pub(crate) const MISSING: (u8, u8, u8) = (225, 225, 225);

/// The viridis colour at `t` in 0..=1 (dark purple to yellow); `t` is clamped into that range and
/// NaN gives light grey.
pub fn viridis(t: f64) -> (u8, u8, u8) {
    if t.is_nan() {
        return MISSING;
    }
    let s = t.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let i = (s.floor() as usize).min(VIRIDIS.len() - 2);
    let f = s - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    let mix = |u: u8, v: u8| (f64::from(u) + f * (f64::from(v) - f64::from(u))).round() as u8;
    (mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ends_and_clamping() {
        assert_eq!(viridis(0.0), VIRIDIS[0]);
        assert_eq!(viridis(1.0), VIRIDIS[8]);
        assert_eq!(viridis(-5.0), VIRIDIS[0]);
        assert_eq!(viridis(7.0), VIRIDIS[8]);
        assert_eq!(viridis(0.5), VIRIDIS[4]);
        assert_eq!(viridis(f64::NAN), MISSING);
    }
}
