//! Run-up and coast-down of a linear rotor against an independent integration of the same
//! transient and against the steady unbalance response; bad input refused by field.

use num_complex::Complex64;
use whirl::model::Model;
use whirl::post::{amplitude_spectrum_with, SpectrumOptions, Window};
use whirl::runup::{runup, Direction, Runup, RunupOptions, Steady, Sweep, SweepResult};
use whirl::units::{hz_to_rad_s, parse_angular_acceleration, parse_speed_range, rad_s_to_hz};
use whirl::Error;

use crate::common::{reference_rotor, ONE_MASS};

/// Sweep of the one-mass rotor.
const LOW_HZ: f64 = 30.0;
const HIGH_HZ: f64 = 70.0;

/// Time step, s: omega h = 0.03 at the critical speed.
const STEP: f64 = 1e-4;

fn one_mass() -> Model {
    Model::from_toml_str(&ONE_MASS.model_file(0.0), None).unwrap()
}

/// The sweep of the one-mass rotor at `rate_hz_per_s`, both directions, no steady
/// cascade, on the Guyan-reduced model (the hanging shaft element's stiff modes would
/// otherwise set a step of nanoseconds), node 0's u_x analysed.
fn sweep(model: &Model, rate_hz_per_s: f64) -> Runup {
    let mut o = RunupOptions::new(
        model,
        hz_to_rad_s(LOW_HZ),
        hz_to_rad_s(HIGH_HZ),
        hz_to_rad_s(rate_hz_per_s),
    );
    o.steady = Steady::None;
    o.cascade.reduction = Some(0);
    o.cascade.step = Some(STEP);
    o.cascade.node = 0;
    o.cascade.component = whirl::nsv::Component::Ux;
    runup(model, &o, None).unwrap()
}

/// The same transient integrated independently: m z'' + c z' + k z = m e (Omega^2 -
/// i Omega') e^(i phi) for z = u_x + i u_y (the unbalance force of a spin that accelerates
/// has the tangential part m e Omega'), by classical Runge-Kutta at `STEP`, from rest at the
/// starting speed (gravity only shifts the mean, which the spectra remove). Returns u_x at
/// t = n STEP.
fn independent(r: &Runup, sweep: Sweep) -> Vec<f64> {
    let o = &r.options;
    let (from, to) = match sweep {
        Sweep::Up => (o.low, o.high),
        Sweep::Down => (o.high, o.low),
    };
    let ramp = o.ramp_s();
    let accel = (to - from) / ramp;
    let kinematics = |t: f64| {
        let tau = (t - o.hold).clamp(0.0, ramp);
        let before = t.min(o.hold);
        let after = (t - o.hold - ramp).max(0.0);
        let speed = from + accel * tau;
        let angle = from * (before + tau) + 0.5 * accel * tau * tau + to * after;
        let a = if t >= o.hold && t <= o.hold + ramp {
            accel
        } else {
            0.0
        };
        (speed, angle, a)
    };
    let j = ONE_MASS;
    let f = |t: f64, z: Complex64, v: Complex64| {
        let (w, phi, a) = kinematics(t);
        let force = j.unbalance * Complex64::new(w * w, -a) * Complex64::from_polar(1.0, phi);
        (force - j.damping * v - j.stiffness * z) / j.mass
    };
    let end = o.hold + ramp + 0.5 * r.resolved.window_s + 3.0 * STEP;
    let steps = (end / STEP).ceil() as usize;
    let (mut z, mut v) = (Complex64::new(0.0, 0.0), Complex64::new(0.0, 0.0));
    let mut x = Vec::with_capacity(steps + 1);
    let h = STEP;
    for n in 0..=steps {
        x.push(z.re);
        let t = n as f64 * h;
        let (k1z, k1v) = (v, f(t, z, v));
        let (k2z, k2v) = (
            v + 0.5 * h * k1v,
            f(t + 0.5 * h, z + 0.5 * h * k1z, v + 0.5 * h * k1v),
        );
        let (k3z, k3v) = (
            v + 0.5 * h * k2v,
            f(t + 0.5 * h, z + 0.5 * h * k2z, v + 0.5 * h * k2v),
        );
        let (k4z, k4v) = (v + h * k3v, f(t + h, z + h * k3z, v + h * k3v));
        z += h / 6.0 * (k1z + 2.0 * k2z + 2.0 * k3z + k4z);
        v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
    }
    x
}

/// The 1X of the independent history in each of the sweep's windows, read as the run-up
/// reads its own (the window ends where its middle lies half a window from either side).
fn independent_one_x(r: &Runup, s: &SweepResult) -> Vec<f64> {
    let x = independent(r, s.sweep);
    let n = r.resolved.window_samples;
    let half = 0.5 * (n - 1) as f64 * STEP;
    let options = SpectrumOptions {
        window: Window::Hann,
        remove_mean: true,
    };
    s.windows
        .iter()
        .map(|w| {
            let start = ((w.time_s - half) / STEP).round() as usize;
            let spectrum =
                amplitude_spectrum_with(&x[start..start + n], r.resolved.sample_rate_hz, options)
                    .unwrap();
            whirl::post::amplitude_at(&spectrum, w.speed_hz)
        })
        .collect()
}

/// The steady 1X of u_x at `speed_hz` (closed form: the unbalance analysis agrees with it to
/// 1e-6, tests/suite/unbalance.rs).
fn steady_one_x(speed_hz: f64) -> f64 {
    ONE_MASS.response(hz_to_rad_s(speed_hz), 0.0).norm()
}

/// The window with the largest 1X: (speed Hz, amplitude m).
fn peak(s: &SweepResult) -> (f64, f64) {
    s.windows
        .iter()
        .map(|w| (w.speed_hz, w.one_x_m))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap()
}

/// RMS of the sweep's 1X minus the steady one over its windows, relative to the steady RMS.
fn relative_rms_from_steady(s: &SweepResult) -> f64 {
    let (mut d, mut e) = (0.0, 0.0);
    for w in &s.windows {
        let steady = steady_one_x(w.speed_hz);
        d += (w.one_x_m - steady).powi(2);
        e += steady * steady;
    }
    (d / e).sqrt()
}

#[test]
fn a_linear_rotor_swept_through_its_critical_speed_follows_lewis() {
    let model = one_mass();
    let steady_peak_hz = rad_s_to_hz(ONE_MASS.peak_speed());
    let steady_peak_m = steady_one_x(steady_peak_hz);
    let mut previous: Option<(f64, f64, f64)> = None;
    // Dimensionless accelerations alpha / omega_n^2 of 6e-5, 6e-4 and 2.5e-3: from nearly
    // steady to a passage much shorter than the resonance's time constant.
    for rate in [1.0, 10.0, 40.0] {
        let r = sweep(&model, rate);
        let up = r.sweep(Sweep::Up).unwrap();
        let down = r.sweep(Sweep::Down).unwrap();
        // whirl's transient against the independent integration, window by window. The
        // central difference's natural frequency is low by (omega h)^2 / 24 = 4e-5, which
        // near the resonance (half-power width 2 zeta = 0.047) moves the response by up to
        // 4e-5 / zeta = 2e-3 of the peak (measured: 8.9e-4 at 1 Hz/s, 4.8e-4 at 40 Hz/s).
        for s in [up, down] {
            let reference = independent_one_x(&r, s);
            for (w, expected) in s.windows.iter().zip(&reference) {
                assert!(
                    (w.one_x_m - expected).abs() < 2e-3 * steady_peak_m,
                    "{rate} Hz/s {}: {} Hz: {} vs {expected}",
                    s.sweep.name(),
                    w.speed_hz,
                    w.one_x_m
                );
            }
        }
        let (up_hz, up_m) = peak(up);
        let (down_hz, down_m) = peak(down);
        // Lewis: the run-up's peak comes late (above the steady peak), the coast-down's
        // early (below it), and both are lower than the steady peak.
        assert!(
            up_hz > steady_peak_hz && down_hz < steady_peak_hz,
            "{rate} Hz/s: {up_hz}, {down_hz}"
        );
        assert!(
            up_m < steady_peak_m && down_m < steady_peak_m,
            "{rate} Hz/s"
        );
        let error = relative_rms_from_steady(up).max(relative_rms_from_steady(down));
        if let Some((shift, lowest, error_before)) = previous {
            // ... and the faster, the later and the lower, and the farther from the steady
            // response.
            assert!(
                up_hz - down_hz > shift,
                "{rate} Hz/s: shift {}",
                up_hz - down_hz
            );
            assert!(up_m.max(down_m) < lowest, "{rate} Hz/s");
            assert!(
                error > error_before,
                "{rate} Hz/s: {error} vs {error_before}"
            );
        } else {
            // Slowly (1 Hz/s: the speed crosses the half-power band in 2.4 s, 18 time
            // constants 1 / (zeta omega_n)), the sweep is the steady response to a few per
            // cent: the window (1 s, a 1 Hz bin) averages the peak over +-0.5 Hz.
            assert!(error < 0.05, "1 Hz/s: {error}");
            assert!(up_m > 0.85 * steady_peak_m, "{up_m} vs {steady_peak_m}");
        }
        previous = Some((up_hz - down_hz, up_m.max(down_m), error));
    }
}

#[test]
fn a_linear_rotor_swept_slowly_has_no_hysteresis() {
    let r = sweep(&one_mass(), 1.0);
    let h = r.hysteresis().unwrap();
    // Run-up and coast-down differ only by the transient shift of the resonance, which at
    // 1 Hz/s stays well inside the default ratio of 2.
    assert!(h.points.len() > 100);
    assert!(h.bands.is_empty(), "{:?}", h.bands);
}

/// The field an error names.
fn field_of(e: Error) -> String {
    match e {
        Error::Input(input) => input.field.clone().unwrap_or_default(),
        other => panic!("not an input error: {other}"),
    }
}

#[test]
fn bad_sweeps_are_refused_naming_the_field() {
    let model = reference_rotor();
    let ok = RunupOptions::new(
        &model,
        hz_to_rad_s(10.0),
        hz_to_rad_s(100.0),
        hz_to_rad_s(20.0),
    );
    let refused = |change: &dyn Fn(&mut RunupOptions)| {
        let mut o = ok.clone();
        change(&mut o);
        field_of(runup(&model, &o, None).unwrap_err())
    };
    assert_eq!(refused(&|o| o.rate = 0.0), "rate");
    assert_eq!(refused(&|o| o.rate = -1.0), "rate");
    assert_eq!(refused(&|o| o.rate = f64::NAN), "rate");
    assert_eq!(refused(&|o| o.high = o.low), "speeds");
    assert_eq!(
        refused(&|o| std::mem::swap(&mut o.low, &mut o.high)),
        "speeds"
    );
    assert_eq!(refused(&|o| o.low = -1.0), "speeds");
    assert_eq!(refused(&|o| o.overlap = 1.0), "overlap");
    assert_eq!(refused(&|o| o.hysteresis_ratio = 1.0), "hysteresis_ratio");
    assert_eq!(refused(&|o| o.window = Some(100.0)), "window");
    assert_eq!(refused(&|o| o.hold = -1.0), "hold");
    // Only the direction asked for is swept.
    assert_eq!(Direction::Up.sweeps(), vec![Sweep::Up]);
}

#[test]
fn a_sweep_reads_its_range_and_rate_with_units() {
    // The bound without a unit borrows the other's, as in a range with a count.
    let (low, high) = parse_speed_range("1:750Hz").unwrap();
    assert!((low - hz_to_rad_s(1.0)).abs() < 1e-12 && (high - hz_to_rad_s(750.0)).abs() < 1e-9);
    let rpm = parse_angular_acceleration("1200rpm/s").unwrap();
    assert!((rpm - hz_to_rad_s(20.0)).abs() < 1e-12);
    assert_eq!(parse_angular_acceleration("5").unwrap(), 5.0);
    assert!(parse_speed_range("1:750Hz:3").is_err());
    assert!(parse_angular_acceleration("20Hx/s").is_err());
}
