//! Implicit Newmark through damped Hertz contacts, and the static equilibrium's safeguards.
//!
//! A roller entering contact with the contact damping on makes its force jump by C times
//! the approach rate: the Newmark balance of a step then has no root for some predictors,
//! and plain Newton cycles. The march cuts such steps in halves (and regrows them) with a
//! line search in each Newton iteration; it agrees with the central difference at a finer
//! step, with HHT-alpha too. When no step size helps (a force that is not finite), it stops
//! with an error naming the time and the sub-step. The static equilibrium
//! condenses onto the nonlinear forces' coordinates, so a fine mesh costs no more
//! iterations; where no equilibrium exists, the simulation starts from rest and says why.

use std::f64::consts::PI;

use whirl::bearing::ContactLaw;
use whirl::fe::{assemble, dof, gravity_force, Bearings, Direction, DOFS_PER_NODE};
use whirl::force::{Kinematics, NonlinearForce};
use whirl::model::{Clearance, Model};
use whirl::post::order_component;
use whirl::system::{SpeedProfile, System};
use whirl::time::{
    newmark, simulate, simulate_with, Hooks, Initial, MarchOptions, Method, NewmarkScheme,
    RunStatus, SimulationOptions, SimulationResult,
};
use whirl::Result;

use crate::common::{reference_rotor, reference_rotor_text_meshed, Oscillator};

fn reference(clearance: f64) -> Model {
    let mut model = reference_rotor();
    for b in &mut model.roller_bearings {
        b.clearance = Clearance::Constant(clearance);
    }
    model
}

/// Running speed of the contact cases, Hz, and the disk's node.
const SPEED_HZ: f64 = 330.0;
const DISK: usize = 10;

/// The reference rotor reduced to 12 fixed-interface modes at 330 Hz from its static
/// equilibrium, 0.2 s of which the last 0.1 s (33 revolutions) are analysed.
fn contact_options(method: Method, step: f64) -> SimulationOptions {
    SimulationOptions {
        speed: SpeedProfile::Constant(2.0 * PI * SPEED_HZ),
        duration: 0.2,
        step: Some(step),
        method,
        reduction: Some(12),
        settle: Some(0.1),
        nodes: Some(vec![DISK]),
        initial: Initial::StaticEquilibrium,
        divergence_bound: 0.01,
        contact: Some(ContactLaw::Hertz),
        record_every: Some(1),
        record_rollers: true,
        progress: None,
    }
}

/// The 1X amplitudes (ux, uy) of the disk over the analysed part, m.
fn disk_one_x(r: &SimulationResult) -> [f64; 2] {
    let start = r.settled_start();
    let angle: Vec<f64> = r.time[start..]
        .iter()
        .map(|t| 2.0 * PI * SPEED_HZ * t)
        .collect();
    ["n10.ux", "n10.uy"].map(|name| {
        let c = r.channels.iter().find(|c| c.name == name).unwrap();
        order_component(&angle, &c.values[start..], 1.0)
            .unwrap()
            .amplitude
    })
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn newmark_marches_through_damped_contact_entry() {
    // Before the step control, Newmark at the default 1e-5 s stopped at t = 0.00089 s
    // (30 um) and 0.0299 s (20 um) on this model, with "Newton iterations did not
    // converge". The reference is the central difference at 2.5e-6 s, 13 times below its
    // stability limit: halving its step again moves the disk 1X by 1.6e-4 (measured).
    for clearance in [20e-6, 30e-6] {
        let model = reference(clearance);
        let cd = SimulationOptions {
            record_every: Some(4),
            ..contact_options(Method::CentralDifference, 2.5e-6)
        };
        let cd = simulate(&model, &cd).unwrap();
        let reference = disk_one_x(&cd);
        for scheme in [NewmarkScheme::AverageAcceleration, NewmarkScheme::Hht(-0.1)] {
            let options = contact_options(Method::Newmark(scheme), 1e-5);
            let r = simulate(&model, &options).unwrap();
            assert_eq!(r.status, RunStatus::Completed, "{scheme:?}");
            // Every output time is on the asked grid, although some steps were halved.
            assert_eq!(r.time.len(), 20_000);
            assert!((r.time[12_345] - 12_345.0 * 1e-5).abs() < 1e-15);
            let one_x = disk_one_x(&r);
            // Measured 0.05 % to 0.14 % (HHT a little more: its numerical damping): the
            // contact instants resolved to a (sub-)step, Newmark's period error at 330 Hz,
            // (w h)^2 / 12 = 4e-5, being smaller. 0.5 % leaves room for that and still
            // catches a Newton iteration stopped short or a wrong sub-step state.
            for (a, b) in one_x.iter().zip(reference) {
                assert!(
                    relative(*a, b) < 5e-3,
                    "{clearance:e} m, {scheme:?}: {one_x:?} against {reference:?}"
                );
            }
        }
    }
}

/// A spring F = -k q whose model breaks down from time `from` on (its force is not
/// finite): no step size gives a root there.
struct Breaking {
    dof: [usize; 1],
    stiffness: f64,
    from: f64,
}

impl NonlinearForce for Breaking {
    fn name(&self) -> String {
        "breaking spring".into()
    }
    fn dofs(&self) -> &[usize] {
        &self.dof
    }
    fn force(&mut self, at: &Kinematics, q: &[f64], _: &[f64], out: &mut [f64]) {
        out[0] = if at.time < self.from {
            -self.stiffness * q[0]
        } else {
            f64::NAN
        };
    }
    fn jacobian(&mut self, _: &Kinematics, _: &[f64], _: &[f64], dq: &mut [f64], dv: &mut [f64]) {
        dq[0] = -self.stiffness;
        dv[0] = 0.0;
    }
    fn stiffness_bound(&self) -> Vec<f64> {
        vec![self.stiffness]
    }
}

#[test]
fn a_step_without_a_root_at_any_size_stops_with_the_time_and_the_sub_step() {
    // Mass 1 kg on the breaking spring, 1e-4 s steps: the steps up to 0.01 s converge,
    // the one ending there fails at every sub-step down to 1e-4 / 2^12.
    let mass = Oscillator {
        mass: 1.0,
        stiffness: 0.0,
        damping: 0.0,
    };
    let mut problem = System {
        nonlinear: vec![Box::new(Breaking {
            dof: [0],
            stiffness: 1e4,
            from: 0.01,
        })],
        ..mass.system()
    };
    let options = MarchOptions {
        speed: SpeedProfile::Constant(0.0),
        step: 1e-4,
        steps: 1000,
        divergence_bound: 1.0,
    };
    let mut last = 0.0;
    let error = newmark(
        &mut problem,
        &[0.01],
        &[0.0],
        NewmarkScheme::AverageAcceleration,
        &options,
        &mut |t, _, _| {
            last = t;
            std::ops::ControlFlow::Continue(())
        },
    )
    .unwrap_err()
    .to_string();
    // The last step seen ends 1e-4 s before the break (to its round-off).
    assert!((last - 0.0099).abs() < 1e-12, "stopped at {last} s");
    for part in [
        "did not converge at t = 0.010000 s",
        "cut 4096 times to 2.441e-8 s",
        "the forces are not finite there",
    ] {
        assert!(error.contains(part), "{part:?} not in {error:?}");
    }
}

/// The reference rotor's text with `elements` per span: disk at mid-span, bearings at the
/// ends.
fn meshed(elements: usize) -> Model {
    Model::from_toml_str(&reference_rotor_text_meshed(elements), None).unwrap()
}

/// The rotor's weight, N: the vertical gravity loads of every node.
fn weight(model: &Model) -> f64 {
    let system = assemble(model, Bearings::NonlinearApart);
    -gravity_force(model, &system)
        .iter()
        .skip(1)
        .step_by(DOFS_PER_NODE)
        .sum::<f64>()
}

/// A short run's options that only need the start (bearing node 0 recorded).
fn start_options(initial: Initial) -> SimulationOptions {
    SimulationOptions {
        speed: SpeedProfile::Constant(2.0 * PI * 50.0),
        duration: 3e-5,
        step: Some(1e-5),
        method: Method::Newmark(NewmarkScheme::AverageAcceleration),
        reduction: None,
        settle: Some(0.0),
        nodes: Some(vec![0]),
        initial,
        divergence_bound: 0.01,
        contact: Some(ContactLaw::Hertz),
        record_every: Some(1),
        record_rollers: true,
        progress: None,
    }
}

#[test]
fn the_static_equilibrium_of_a_fine_mesh_matches_the_hertz_closed_form() {
    // Before the condensation, 160 elements stopped with "did not converge" (residual
    // 9.5e-6 N against a tolerance of 1e-6 N, after 25 s). The rotor is symmetric, so each
    // bearing carries half the weight W on its bottom roller, which the Hertz law
    // Q = K d^n compresses by (W / 2 K)^(1/n) beyond the clearance.
    let model = meshed(160);
    let r = simulate(&model, &start_options(Initial::StaticEquilibrium)).unwrap();
    assert_eq!(r.start_fallback, None);
    let b = &model.roller_bearings[0];
    let clearance = 20e-6;
    let drop =
        clearance + (weight(&model) / 2.0 / b.contact_stiffness).powf(1.0 / b.contact_exponent);
    for node in [0, 160] {
        let c = r
            .channels
            .iter()
            .find(|c| c.name == format!("n{node}.uy"))
            .unwrap();
        // The solver stops at 1e-10 of the load; the drop follows to that relative
        // accuracy divided by n = 10/9, far below 1e-6.
        assert!(
            relative(-c.values[0], drop) < 1e-6,
            "node {node}: {} against {drop}",
            -c.values[0]
        );
    }
}

/// A support on (ux, uy) whose force saturates: F = -k u up to `limit` in each direction.
struct Saturating {
    dofs: [usize; 2],
    stiffness: f64,
    limit: f64,
}

impl NonlinearForce for Saturating {
    fn name(&self) -> String {
        "saturating support".into()
    }
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }
    fn force(&mut self, _: &Kinematics, q: &[f64], _: &[f64], out: &mut [f64]) {
        for (o, x) in out.iter_mut().zip(q) {
            *o = (-self.stiffness * x).clamp(-self.limit, self.limit);
        }
    }
    fn jacobian(&mut self, _: &Kinematics, q: &[f64], _: &[f64], dq: &mut [f64], dv: &mut [f64]) {
        dq.iter_mut().for_each(|x| *x = 0.0);
        dv.iter_mut().for_each(|x| *x = 0.0);
        for (a, x) in q.iter().enumerate() {
            if (self.stiffness * x).abs() < self.limit {
                dq[a * 2 + a] = -self.stiffness;
            }
        }
    }
    fn stiffness_bound(&self) -> Vec<f64> {
        vec![self.stiffness, 0.0, 0.0, self.stiffness]
    }
}

/// The reference rotor on saturating supports at its bearing nodes.
fn on_saturating_supports(model: &Model, initial: Initial, limit: f64) -> SimulationResult {
    let forces =
        |m: &Model, map: &dyn Fn(usize) -> Option<usize>| -> Result<Vec<Box<dyn NonlinearForce>>> {
            Ok(m.roller_bearings
                .iter()
                .map(|b| {
                    let node = b.station.node;
                    let at = |d| map(dof(node, d)).expect("the full model keeps every DOF");
                    Box::new(Saturating {
                        dofs: [at(Direction::Ux), at(Direction::Uy)],
                        stiffness: 1e8,
                        limit,
                    }) as Box<dyn NonlinearForce>
                })
                .collect())
        };
    let hooks = Hooks {
        forces: Some((Bearings::NonlinearApart, &forces)),
        ..Hooks::default()
    };
    simulate_with(model, &start_options(initial), hooks).unwrap()
}

#[test]
fn without_a_static_equilibrium_the_run_starts_from_rest_and_says_why() {
    let model = reference(20e-6);
    // 171.6 N per support hold the 343 N rotor: each sinks by 171.6 N / 1e8 N/m.
    let held = on_saturating_supports(&model, Initial::StaticEquilibrium, 300.0);
    assert_eq!(held.start_fallback, None);
    let uy = held.channels.iter().find(|c| c.name == "n0.uy").unwrap();
    let half_weight = 0.5 * weight(&model);
    // The static solve's tolerance, 1e-10 of the load, and the weight's round-off.
    assert!(
        relative(-uy.values[0], half_weight / 1e8) < 1e-8,
        "{}",
        uy.values[0]
    );

    // Supports that give way at 100 N cannot carry 171.6 N each: no equilibrium. Before,
    // the simulation stopped with the solver's error.
    let falls = on_saturating_supports(&model, Initial::StaticEquilibrium, 100.0);
    let why = falls.start_fallback.expect("a fallback");
    assert!(
        why.contains("no static equilibrium was found, so the run started from rest"),
        "{why}"
    );
    assert!(falls.channels.iter().all(|c| c.values[0] == 0.0));
    let rest = on_saturating_supports(&model, Initial::Rest, 100.0);
    assert_eq!(rest.start_fallback, None);
    assert_eq!(falls.channels[1].values, rest.channels[1].values);
}
