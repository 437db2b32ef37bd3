//! The cost of one central-difference step of the cascade's system (the reference rotor
//! reduced 8 + 12, Hertz rollers at both bearings) against a plain loop that does the same
//! arithmetic written out as tightly as we know how: the dense step with precomputed
//! matrices by columns, four added at a time down each whole column (row blocks of eight
//! held in registers took 230 ns for the product alone, the column form about 120 ns by
//! difference), the rollers' and the unbalance's directions advanced by a rotation per
//! step, and no other work (delta^(10/9) by the library's `bearing::Power`, as the step:
//! the C library's `pow` took 10-16 ns, two cube roots three times as long). Both march the same steps from the same start, and the bench
//! checks that they end in the same place, so the plain loop is known to do the same work.
//! Figures go to BENCHMARKS.md.
//! Run with `cargo bench -p whirl-rotordynamics --bench step`.

mod common;
// The test models; a benchmark uses only the reference rotor.
#[allow(dead_code)]
#[path = "../tests/suite/common/reference.rs"]
mod reference;

use std::f64::consts::PI;
use std::ops::ControlFlow;
use std::time::Duration;

use faer::linalg::solvers::DenseSolveCore;
use faer::traits::pulp::{Arch, Simd, WithSimd};
use faer::Mat;
use nix::time::{clock_gettime, ClockId};
use reference::reference_rotor;
use whirl::bearing::{hertz_bearings, ContactLaw, Power};
use whirl::model::{Model, RollerBearing};
use whirl::nsv::{cascade, CascadeOptions};
use whirl::system::{linear, SpeedProfile, System};
use whirl::time::{
    central_difference, stable_step_of, MarchOptions, DEFAULT_MODES, STABLE_FRACTION,
};

/// Steps per timed run: 1 s of motion at the cascade's step, long enough for the rotor to
/// fall into its bearings and bounce in them as it does through a cascade's records.
const STEPS: usize = 100_000;

/// Steps over which the two marches are compared. Contacts make the motion sensitive to
/// round-off (the plain loop sums in another order), so the comparison stops before
/// rounding differences grow to the size of the motion: at 0.02 s the rotor has fallen
/// onto its rollers and bounced several times.
const COMPARED_STEPS: usize = 2_000;

fn main() {
    faer::set_global_parallelism(faer::Par::Seq);
    let model = reference_rotor();
    let law = ContactLaw::Hertz;
    let linear = linear(&model, Some(DEFAULT_MODES), law.bearings()).expect("reduces");
    let h = STABLE_FRACTION * stable_step_of(&model, &linear, law).expect("limit");
    for hz in [50.0, 300.0, 595.0] {
        let speed = SpeedProfile::Constant(2.0 * PI * hz);
        let built = || {
            linear
                .with_forces(&model, &hertz_bearings)
                .expect("builds")
                .system
        };
        let mut plain = PlainStep::new(&model, &built(), speed, h);
        let (real_end, plain_end) = (
            march(&mut built(), speed, h, COMPARED_STEPS),
            plain.march(COMPARED_STEPS),
        );
        check_same_motion(&real_end, &plain_end);
        let real = on_cpu(&format!("{hz} Hz, cascade step, {STEPS} steps"), 9, || {
            march(&mut built(), speed, h, STEPS)
        });
        let loop_ = on_cpu(&format!("{hz} Hz, plain loop, {STEPS} steps"), 9, || {
            plain.march(STEPS)
        });
        let ns = |d: Duration| d.as_secs_f64() * 1e9 / STEPS as f64;
        println!(
            "{:<55} {:.0} ns per step, plain loop {:.0} ns: {:.2}x (medians; minima {:.0}, {:.0} ns: {:.2}x)",
            "",
            ns(real.0),
            ns(loop_.0),
            ns(real.0) / ns(loop_.0),
            ns(real.1),
            ns(loop_.1),
            ns(real.1) / ns(loop_.1)
        );
    }
    one_speed_cascade(&model);
}

/// Times `f` as [`common::time`] does, by the CPU time of this thread rather than the wall
/// clock: on a machine shared with other jobs the step's cost is then not inflated by the
/// time the thread waits for a core. Prints and returns the median and the minimum.
fn on_cpu<T>(name: &str, runs: usize, mut f: impl FnMut() -> T) -> (Duration, Duration) {
    let cpu = || {
        Duration::from(
            clock_gettime(ClockId::CLOCK_THREAD_CPUTIME_ID).expect("the thread's CPU clock"),
        )
    };
    std::hint::black_box(f());
    let mut samples: Vec<Duration> = (0..runs)
        .map(|_| {
            let start = cpu();
            std::hint::black_box(f());
            cpu() - start
        })
        .collect();
    samples.sort();
    let (median, min) = (samples[runs / 2], samples[0]);
    println!(
        "{name:<55} median {:>10.3} ms   min {:>10.3} ms   ({runs} runs, CPU time)",
        median.as_secs_f64() * 1e3,
        min.as_secs_f64() * 1e3
    );
    (median, min)
}

/// The displacements after `steps` steps of the library's central difference from rest.
fn march(system: &mut System, speed: SpeedProfile, h: f64, steps: usize) -> Vec<f64> {
    let n = system.size();
    let options = MarchOptions {
        speed,
        step: h,
        steps,
        divergence_bound: 1.0,
    };
    let mut last = vec![0.0; n];
    let end = (steps - 1) as f64 * h;
    let zero = vec![0.0; n];
    central_difference(system, &zero, &zero, &options, &mut |t, q, _| {
        if t >= end {
            last.copy_from_slice(q);
        }
        ControlFlow::Continue(())
    })
    .expect("marches");
    last
}

/// The two marches' ends agree to 1e-6 of the largest displacement: they differ only by
/// the order of sums, which 2,000 steps with impacts amplify to about 1e-9 (measured);
/// a term left out or done twice shows at 1e-2 or more.
fn check_same_motion(real: &[f64], plain: &[f64]) {
    let scale = real.iter().fold(0.0f64, |s, x| s.max(x.abs()));
    let worst = real
        .iter()
        .zip(plain)
        .fold(0.0f64, |s, (a, b)| s.max((a - b).abs()));
    println!(
        "{:<55} plain loop against cascade step: {:.1e}",
        "",
        worst / scale
    );
    assert!(worst <= 1e-6 * scale, "{worst:e} of {scale:e}");
}

/// Whole cascade of one speed (reduction, static start, march, recording, spectra) per
/// simulated step, for the share the step has of it.
fn one_speed_cascade(model: &Model) {
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    for hz in [300.0, 595.0] {
        let options = CascadeOptions::new(model, vec![2.0 * PI * hz]);
        let mut steps = 0.0;
        let whole = common::time(&format!("one-speed cascade, {hz} Hz"), 3, || {
            let c = one.install(|| cascade(model, &options, None, None).expect("runs"));
            let p = &c.points[0];
            steps = (p.settle_s + p.records as f64 * options.record) / c.resolved.step;
            c
        });
        println!(
            "{:<55} {:.0} ns per simulated step ({steps:.0} steps)",
            "",
            whole.as_secs_f64() * 1e9 / steps
        );
    }
}

/// Steps between exact sines and cosines in the plain loop; in between, each angle is
/// advanced by a rotation.
const RESEED: usize = 256;

/// (sin, cos) rotated forward by the angle whose (sin, cos) is `by`.
#[inline(always)]
fn rotate((s, c): (f64, f64), (sb, cb): (f64, f64)) -> (f64, f64) {
    (s * cb + c * sb, c * cb - s * sb)
}

/// One Hertz roller bearing as the plain loop sees it (one slice per roller, no tilt,
/// skew or waviness: the reference rotor's bearings), its rollers' directions held in
/// arrays and turned by the cage's advance each step.
struct PlainBearing {
    x: usize,
    y: usize,
    pitch: Vec<f64>,
    cage_ratio: f64,
    cage_speed: f64,
    clearance: f64,
    stiffness: f64,
    damping: f64,
    power: Power,
    sin: Vec<f64>,
    cos: Vec<f64>,
}

impl PlainBearing {
    fn new(b: &RollerBearing, dofs: &[usize], speed: f64) -> PlainBearing {
        assert!(b.slices == 1 && !b.roller_tilt && b.skew_angle == 0.0);
        assert!(b.waviness.is_empty() && dofs.len() == 2);
        let rollers = b.rollers;
        PlainBearing {
            x: dofs[0],
            y: dofs[1],
            pitch: (0..rollers)
                .map(|j| 2.0 * PI * j as f64 / rollers as f64 + b.cage_angle)
                .collect(),
            cage_ratio: b.cage_speed_ratio,
            cage_speed: b.cage_speed_ratio * speed,
            clearance: b.clearance.at_speed(speed),
            stiffness: b.contact_stiffness,
            damping: b.contact_damping,
            power: Power::new(b.contact_exponent),
            sin: vec![0.0; rollers],
            cos: vec![0.0; rollers],
        }
    }

    /// The rollers' directions at spin angle `phi`, exactly.
    fn seed(&mut self, phi: f64) {
        for j in 0..self.pitch.len() {
            (self.sin[j], self.cos[j]) = (self.pitch[j] + self.cage_ratio * phi).sin_cos();
        }
    }

    /// The rollers' directions turned by the cage's advance, whose (sin, cos) is `by`.
    fn turn(&mut self, (sb, cb): (f64, f64)) {
        for j in 0..self.sin.len() {
            (self.sin[j], self.cos[j]) = rotate((self.sin[j], self.cos[j]), (sb, cb));
        }
    }

    /// Adds the rollers' force to `f`.
    #[inline(always)]
    fn add_force(&self, q: &[f64], v: &[f64], f: &mut [f64]) {
        let (qx, qy, vx, vy) = (q[self.x], q[self.y], v[self.x], v[self.y]);
        let (mut fx, mut fy) = (0.0, 0.0);
        for (&s, &c) in self.sin.iter().zip(&self.cos) {
            let delta = c * qx + s * qy - self.clearance;
            if delta <= 0.0 {
                continue;
            }
            let rate = c * vx + s * vy + self.cage_speed * (c * qy - s * qx);
            let load = self.stiffness * self.power.of(delta) + self.damping * rate;
            if load > 0.0 {
                fx -= load * c;
                fy -= load * s;
            }
        }
        f[self.x] += fx;
        f[self.y] += fy;
    }
}

/// The central difference written out: q_{n+1} = [P | Q] [q_n; q_{n-1}] + S F_n with P, Q,
/// S formed as the library forms them and stored by columns, so that the product runs
/// down contiguous columns.
struct PlainStep {
    n: usize,
    /// n rounded up to a multiple of 8: the columns' length, padded with zeros.
    rows: usize,
    speed: f64,
    h: f64,
    /// [P | Q] by columns, n x 2n.
    pq: Vec<f64>,
    /// S by columns, n x n.
    s: Vec<f64>,
    s_constant: Vec<f64>,
    s_unbalance: [Vec<f64>; 2],
    bearings: Vec<PlainBearing>,
    /// q_{-1} for a start from rest.
    before: Vec<f64>,
}

impl PlainStep {
    fn new(model: &Model, system: &System, profile: SpeedProfile, h: f64) -> PlainStep {
        let n = system.size();
        assert_eq!(2 * n % 4, 0, "the product takes four columns at a time");
        let rows = n.next_multiple_of(8);
        let speed = profile.max_speed();
        let m = &system.matrices;
        let d = |i: usize, j: usize| m.damping[(i, j)] + speed * m.gyroscopic[(i, j)];
        let lhs = Mat::<f64>::from_fn(n, n, |i, j| m.mass[(i, j)] / (h * h) + d(i, j) / (2.0 * h));
        let s = lhs.partial_piv_lu().inverse();
        let a = Mat::<f64>::from_fn(n, n, |i, j| {
            2.0 * m.mass[(i, j)] / (h * h) - m.stiffness[(i, j)]
        });
        let b = Mat::<f64>::from_fn(n, n, |i, j| d(i, j) / (2.0 * h) - m.mass[(i, j)] / (h * h));
        let (p, q) = (&s * &a, &s * &b);
        let times_s = |v: &[f64]| -> Vec<f64> {
            (0..n)
                .map(|i| (0..n).map(|j| s[(i, j)] * v[j]).sum())
                .collect()
        };
        // From rest the first step's acceleration is M^-1 F_0 (no contact at q = 0, and the
        // unbalance at t = 0 is c_re = w^2 times its real part).
        let force: Vec<f64> = (0..n)
            .map(|i| system.constant_force[i] + speed * speed * system.unbalance_re[i])
            .collect();
        let mass_inverse = m.mass.partial_piv_lu().inverse();
        let before = (0..n)
            .map(|i| 0.5 * h * h * (0..n).map(|j| mass_inverse[(i, j)] * force[j]).sum::<f64>())
            .collect();
        let bearings = model
            .roller_bearings
            .iter()
            .zip(&system.nonlinear)
            .map(|(b, f)| PlainBearing::new(b, f.dofs(), speed))
            .collect();
        PlainStep {
            n,
            speed,
            h,
            rows,
            pq: (0..2 * n)
                .flat_map(|j| (0..rows).map(move |i| (i, j)))
                .map(|(i, j)| match (i < n, j < n) {
                    (false, _) => 0.0,
                    (true, true) => p[(i, j)],
                    (true, false) => q[(i, j - n)],
                })
                .collect(),
            s: (0..n)
                .flat_map(|j| (0..rows).map(move |i| (i, j)))
                .map(|(i, j)| if i < n { s[(i, j)] } else { 0.0 })
                .collect(),
            s_constant: times_s(&system.constant_force),
            s_unbalance: [times_s(&system.unbalance_re), times_s(&system.unbalance_im)],
            bearings,
            before,
        }
    }

    /// The displacements after `steps` steps from rest.
    fn march(&mut self, steps: usize) -> Vec<f64> {
        let n = self.n;
        let (w, h) = (self.speed, self.h);
        // [q_n; q_{n-1}].
        let mut history = vec![0.0; 2 * n];
        history[n..].copy_from_slice(&self.before);
        let mut next = vec![0.0; n];
        let mut velocity = vec![0.0; n];
        let mut force = vec![0.0; n];
        let spin_turn = (w * h).sin_cos();
        let cage_turns: Vec<(f64, f64)> = self
            .bearings
            .iter()
            .map(|b| (b.cage_ratio * w * h).sin_cos())
            .collect();
        let mut spin = (0.0, 1.0);
        for step in 0..steps - 1 {
            if step % RESEED == 0 {
                let phi = w * (step as f64 * h);
                spin = phi.sin_cos();
                self.bearings.iter_mut().for_each(|b| b.seed(phi));
            } else {
                spin = rotate(spin, spin_turn);
                for (b, &turn) in self.bearings.iter_mut().zip(&cage_turns) {
                    b.turn(turn);
                }
            }
            let (c_re, c_im) = (w * w * spin.1, -w * w * spin.0);
            if step > 0 {
                for i in 0..n {
                    velocity[i] = (history[i] - history[n + i]) / h;
                }
            }
            for b in &self.bearings {
                force[b.x] = 0.0;
                force[b.y] = 0.0;
            }
            for b in &self.bearings {
                b.add_force(&history[..n], &velocity, &mut force);
            }
            Arch::new().dispatch(Product {
                step: self,
                history: &history,
                force: &force,
                unbalance: (c_re, c_im),
                next: &mut next,
            });
            history.copy_within(..n, n);
            history[..n].copy_from_slice(&next);
        }
        history[..n].to_vec()
    }
}

/// One step's product, compiled for the processor's widest vectors as the library's step
/// is.
struct Product<'a> {
    step: &'a PlainStep,
    history: &'a [f64],
    force: &'a [f64],
    unbalance: (f64, f64),
    next: &'a mut [f64],
}

impl WithSimd for Product<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _: S) {
        self.step
            .product(self.history, self.force, self.unbalance, self.next)
    }
}

impl PlainStep {
    /// q_{n+1} = [P | Q] [q_n; q_{n-1}] + S F_n into `next`, with F_n the constant force,
    /// the unbalance (coefficients `c_re`, `c_im`) and the bearings' `force`: four columns
    /// at a time added down the whole (contiguous) column, so that the row loop vectorises
    /// and each element of `next` takes four products per pass; the bearings' force only
    /// through the columns of S of the coordinates it acts on.
    // One index over several slices, as the library's kernel writes it.
    #[allow(clippy::needless_range_loop)]
    #[inline(always)]
    fn product(&self, history: &[f64], force: &[f64], (c_re, c_im): (f64, f64), next: &mut [f64]) {
        let (n, rows) = (self.n, self.rows);
        let next = &mut next[..n];
        for i in 0..n {
            next[i] =
                self.s_constant[i] + c_re * self.s_unbalance[0][i] + c_im * self.s_unbalance[1][i];
        }
        let column = |j: usize| &self.pq[j * rows..j * rows + n];
        for j in (0..2 * n).step_by(4) {
            let (c0, c1, c2, c3) = (column(j), column(j + 1), column(j + 2), column(j + 3));
            let x = &history[j..j + 4];
            for i in 0..n {
                next[i] += (x[0] * c0[i] + x[1] * c1[i]) + (x[2] * c2[i] + x[3] * c3[i]);
            }
        }
        for b in &self.bearings {
            for d in [b.x, b.y] {
                let col = &self.s[d * rows..d * rows + n];
                for i in 0..n {
                    next[i] += col[i] * force[d];
                }
            }
        }
    }
}
