//! Order tracking: the part of a signal locked to the shaft angle (a "1X tracking filter").
//!
//! A record `x_n` taken at shaft angles `phi_n` is fitted by weighted least squares,
//!
//! ```text
//! minimise sum_n w_n (x_n - mean - a cos(k phi_n) - b sin(k phi_n))^2
//! x ~ mean + A cos(k phi + phase),   A = sqrt(a^2 + b^2),   phase = atan2(-b, a)
//! ```
//!
//! for the order `k` (1 for the synchronous 1X), with `w_n` the Hann window over the record.
//! The phase follows the unbalance response's convention, `Re(Q e^(i Omega t))` with
//! `phase = arg Q` (see [`crate::response`]), so a settled time history and the
//! frequency-domain response compare directly. A record that is exactly of this form is
//! recovered to round-off with any number of revolutions, also when the speed varies (the
//! angle, not the time, is the abscissa). Other content leaks in as far as it correlates with
//! `cos(k phi)` over the record: without weights a component `d` cycles per record away
//! leaks about `1 / (pi d)` of itself; the Hann weights cut that to its side lobes
//! (about `1 / (pi d^3)`, e.g. 0.8 % at d = 3.5).

use std::f64::consts::PI;

use faer::Mat;
use serde::Serialize;

use super::spectrum::Window;
use crate::{Error, Result};

/// One order of a signal: `mean + amplitude cos(order phi + phase)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OrderComponent {
    /// The order `k` (1 = once per revolution).
    pub order: f64,
    /// Zero-to-peak amplitude (the signal's unit).
    pub amplitude: f64,
    /// Phase, rad, in (-pi, pi]; negative when the signal lags the angle.
    pub phase: f64,
    /// The record's offset fitted with it (the signal's unit).
    pub mean: f64,
}

/// Fits the `order` component of `signal`, sampled at shaft angles `angle` (rad).
///
/// # Errors
/// [`Error::InvalidOption`] when the lengths differ, a value is not finite, there are fewer than
/// three samples, or `order` times the angles spans less than half a turn, too little to
/// tell the cosine from the sine and the offset (e.g. a shaft at rest).
pub fn order_component(angle: &[f64], signal: &[f64], order: f64) -> Result<OrderComponent> {
    let bad = |why: String| Err(Error::InvalidOption(format!("order tracking: {why}")));
    if angle.len() != signal.len() {
        return bad(format!(
            "{} angles but {} samples",
            angle.len(),
            signal.len()
        ));
    }
    if signal.len() < 3 {
        return bad(format!("{} samples; at least 3 are needed", signal.len()));
    }
    if angle.iter().chain(signal).any(|v| !v.is_finite()) || !order.is_finite() {
        return bad("a value is not finite (did the simulation diverge?)".into());
    }
    let (low, high) = angle
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &a| {
            (l.min(a), h.max(a))
        });
    if order.abs() * (high - low) < PI {
        return bad(format!(
            "order {order} turns through {:.3} rad over the record; at least pi is needed",
            order.abs() * (high - low)
        ));
    }
    // Weighted normal equations of the three-column basis [1, cos, sin].
    let len = signal.len();
    let mut normal = Mat::<f64>::zeros(3, 3);
    let mut rhs = Mat::<f64>::zeros(3, 1);
    for (n, (&phi, &x)) in angle.iter().zip(signal).enumerate() {
        let w = Window::Hann.sample(n, len);
        let (s, c) = (order * phi).sin_cos();
        let basis = [1.0, c, s];
        for i in 0..3 {
            rhs[(i, 0)] += w * basis[i] * x;
            for j in 0..3 {
                normal[(i, j)] += w * basis[i] * basis[j];
            }
        }
    }
    let lu = normal.partial_piv_lu();
    faer::linalg::solvers::Solve::solve_in_place(&lu, rhs.as_mut());
    let (mean, a, b) = (rhs[(0, 0)], rhs[(1, 0)], rhs[(2, 0)]);
    Ok(OrderComponent {
        order,
        amplitude: a.hypot(b),
        phase: (-b).atan2(a),
        mean,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `revolutions` turns sampled uniformly at 2000 points.
    fn angles(revolutions: f64) -> Vec<f64> {
        (0..2000)
            .map(|n| n as f64 * revolutions * 2.0 * PI / 2000.0)
            .collect()
    }

    #[test]
    fn recovers_a_component_with_an_offset_over_a_partial_revolution_count() {
        let angle = angles(7.3);
        let signal: Vec<f64> = angle.iter().map(|&p| 2.0 + 3.0 * (p - 0.7).cos()).collect();
        let one = order_component(&angle, &signal, 1.0).unwrap();
        // The model is exact for this record: only round-off remains.
        assert!((one.amplitude - 3.0).abs() < 1e-12, "{one:?}");
        assert!((one.phase + 0.7).abs() < 1e-12, "{one:?}");
        assert!((one.mean - 2.0).abs() < 1e-12, "{one:?}");
    }

    #[test]
    fn other_orders_do_not_leak_in_over_whole_revolutions() {
        let angle = angles(7.0);
        let signal: Vec<f64> = angle
            .iter()
            .map(|&p| 3.0 * (p - 0.7).cos() + 0.5 * (2.0 * p).sin() + 0.2 * (0.5 * p).cos())
            .collect();
        let one = order_component(&angle, &signal, 1.0).unwrap();
        // 0.5X lies 3.5 cycles per record from 1X: the Hann side lobe there is 0.8 %, so
        // 0.2 leaks in as about 1.6e-3; 2X, 7 cycles away, much less.
        assert!((one.amplitude - 3.0).abs() < 3e-3, "{one:?}");
        let two = order_component(&angle, &signal, 2.0).unwrap();
        assert!((two.amplitude - 0.5).abs() < 3e-3, "{two:?}");
    }

    #[test]
    fn refuses_bad_records() {
        assert!(order_component(&[0.0, 1.0], &[1.0, 2.0], 1.0).is_err());
        assert!(order_component(&[0.0, 1.0, 2.0], &[1.0, 2.0], 1.0).is_err());
        assert!(order_component(&[0.0, 1.0, 2.0], &[1.0, f64::NAN, 2.0], 1.0).is_err());
        // A shaft at rest: cosine and offset cannot be told apart.
        assert!(order_component(&[0.0; 10], &[1.0; 10], 1.0).is_err());
    }
}
