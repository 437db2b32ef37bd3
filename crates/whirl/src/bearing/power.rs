//! The contact law's power delta^n, the one transcendental function of a time step.
//!
//! The C library's `pow` takes 10-16 ns on this machine and was 15 % of a cascade: every
//! roller in contact evaluates it once per step. The two exponents that models use are
//! evaluated by cheaper routes to within a few ulps of the exact power:
//!
//! - n = 3/2 (point contact, balls): delta sqrt(delta), the square root correctly rounded;
//! - n = 10/9 (line contact, rollers): delta times the ninth root of delta. With delta =
//!   2^e m (1 <= m < 2) the root is 2^(e/9) m^(1/9); 2^(e/9) is 2^q times one of nine
//!   tabled values 2^(r/9) (e = 9 q + r), and m^(1/9) = (m c_j)^(1/9) c_j^(-1/9) with c_j
//!   the tabled reciprocal of the middle of the j-th of 128 slices of [1, 2) that holds m.
//!   Then t = m c_j - 1 lies within +-1/255 and (1 + t)^(1/9) is its binomial series to t^7,
//!   whose first term left out is below 1e-19. About 4 ns.
//!
//! Any other exponent goes to `pow`.

use std::sync::LazyLock;

/// delta^n for one exponent n.
#[derive(Debug, Clone, Copy)]
pub struct Power {
    exponent: f64,
    route: Route,
}

#[derive(Debug, Clone, Copy)]
enum Route {
    TenNinths(&'static NinthRoot),
    ThreeHalves,
    Library,
}

impl Power {
    /// The power for exponent `exponent`, by the cheapest route that exponent has.
    pub fn new(exponent: f64) -> Power {
        let route = if exponent == 10.0 / 9.0 {
            Route::TenNinths(&NINTH_ROOT)
        } else if exponent == 1.5 {
            Route::ThreeHalves
        } else {
            Route::Library
        };
        Power { exponent, route }
    }

    /// The exponent n.
    pub fn exponent(&self) -> f64 {
        self.exponent
    }

    /// x^n for x > 0.
    #[inline(always)]
    pub fn of(&self, x: f64) -> f64 {
        match self.route {
            Route::TenNinths(root) if x.is_normal() => x * root.of(x),
            Route::ThreeHalves => x * x.sqrt(),
            _ => x.powf(self.exponent),
        }
    }
}

/// Slices of the mantissa's range [1, 2) (its leading 7 bits).
const SLICES: usize = 128;

/// The tables of the ninth root; see the module documentation.
#[derive(Debug)]
struct NinthRoot {
    /// c_j, the reciprocal of the middle of slice j.
    reciprocal: [f64; SLICES],
    /// c_j^(-1/9).
    root_of_middle: [f64; SLICES],
    /// 2^(r/9), r = 0..8.
    root_of_two: [f64; 9],
}

static NINTH_ROOT: LazyLock<NinthRoot> = LazyLock::new(|| {
    let reciprocal: [f64; SLICES] =
        std::array::from_fn(|j| 1.0 / (1.0 + (j as f64 + 0.5) / SLICES as f64));
    NinthRoot {
        reciprocal,
        root_of_middle: reciprocal.map(|c| c.powf(-1.0 / 9.0)),
        root_of_two: std::array::from_fn(|r| 2f64.powf(r as f64 / 9.0)),
    }
});

/// Coefficients of (1 + t)^(1/9) = 1 + sum_k a_k t^k, k = 1..7: a_k = a_(k-1) (1/9 - k + 1)/k.
const SERIES: [f64; 7] = [
    1.0 / 9.0,
    -4.0 / 81.0,
    68.0 / 2187.0,
    -442.0 / 19_683.0,
    3094.0 / 177_147.0,
    -22_100.0 / 1_594_323.0,
    160_225.0 / 14_348_907.0,
];

impl NinthRoot {
    /// x^(1/9) for a normal, positive, finite x.
    #[inline(always)]
    fn of(&self, x: f64) -> f64 {
        const MANTISSA: u64 = (1 << 52) - 1;
        let bits = x.to_bits();
        let e = ((bits >> 52) & 0x7ff) as i64 - 1023;
        let j = ((bits >> 45) & (SLICES as u64 - 1)) as usize;
        let m = f64::from_bits((bits & MANTISSA) | 1023 << 52);
        let t = m * self.reciprocal[j] - 1.0;
        let s = &SERIES;
        let series =
            t * (s[0] + t * (s[1] + t * (s[2] + t * (s[3] + t * (s[4] + t * (s[5] + t * s[6]))))));
        let (q, r) = (e.div_euclid(9), e.rem_euclid(9) as usize);
        let two_q = f64::from_bits(((q + 1023) as u64) << 52);
        (self.root_of_middle[j] * (two_q * self.root_of_two[r])) * (1.0 + series)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Relative distance from the library's pow.
    fn error(power: &Power, x: f64) -> f64 {
        relative(power.of(x), x.powf(power.exponent()))
    }

    fn relative(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    #[test]
    fn the_ten_ninths_power_is_exact_within_a_few_ulps_over_every_mantissa_and_scale() {
        // The reference is x (x^(1/3))^(1/3), each cube root within an ulp: 3 ulps. The
        // route's roundings: the tabled root (half an ulp), t (an ulp of m c_j, times 1/9
        // in the result), the series and four products (half an ulp each): about 5 ulps.
        // Together 8 ulps of 1, 1.8e-15. Every slice of the mantissa, at scales from
        // 1e-250 to 1e250, whose powers are normal numbers (approaches are 1e-12 to 1e-4 m).
        // pow itself is not the reference there: the exponent 10/9 as a double is 6e-17
        // above 10/9, which moves x^n by 6e-17 ln x relative (3.6e-14 at 1e250, 7e-16 at
        // approaches of 1e-5 m).
        let power = Power::new(10.0 / 9.0);
        assert!(matches!(power.route, Route::TenNinths(_)));
        let exact = |x: f64| x * x.cbrt().cbrt();
        let mut worst: f64 = 0.0;
        for scale in -250..=250 {
            for k in 0..1000 {
                let x = 10f64.powi(scale) * (1.0 + 9.0 * (k as f64 * 0.618_033_988_75).fract());
                worst = worst.max(relative(power.of(x), exact(x)));
            }
        }
        assert!(worst < 1.8e-15, "worst relative error {worst:e}");
        // Each slice's edges, where |t| is largest; and pow at contact approaches.
        for j in 0..=SLICES {
            let m = 1.0 + j as f64 / SLICES as f64;
            for x in [m, m * (1.0 - f64::EPSILON), 3.7e-6 * m] {
                assert!(relative(power.of(x), exact(x)) < 1.8e-15, "{x:e}");
            }
            assert!(error(&power, 3.7e-6 * m) < 2.6e-15, "{m}");
        }
    }

    #[test]
    fn other_exponents_and_awkward_numbers_are_the_library_pow() {
        let three_halves = Power::new(1.5);
        for x in [1e-200, 2.5e-9, 1.0, 7.3e4] {
            // sqrt is correctly rounded, so two roundings: an ulp.
            assert!(error(&three_halves, x) < 2.3e-16, "{x:e}");
        }
        let other = Power::new(1.3);
        assert_eq!(other.of(2.5e-6), 2.5e-6f64.powf(1.3));
        let ten_ninths = Power::new(10.0 / 9.0);
        let subnormal = f64::MIN_POSITIVE / 8.0;
        assert_eq!(ten_ninths.of(subnormal), subnormal.powf(10.0 / 9.0));
        assert!(ten_ninths.of(f64::INFINITY).is_infinite());
        assert!(ten_ninths.of(f64::NAN).is_nan());
    }
}
