//! Squeeze-film dampers around a bearing's housing: the film force the solvers see on a
//! prescribed circular orbit, and the film linearised for the linear analyses, against the
//! short-bearing closed forms (Vance 1988, ch. 6; San Andres, Texas A&M notes); bad dampers
//! refused with the field named.

use std::f64::consts::PI;

use whirl::bearing::{hertz_bearings, ContactLaw};
use whirl::fe::{assemble, Bearings};
use whirl::force::{no_forces, Kinematics};
use whirl::model::{Cavitation, Model};
use whirl::squeeze_film::{circular_orbit, circular_orbit_closed_form};
use whirl::system::{build, SpeedProfile};
use whirl::time::{simulate, stable_step, Initial, Method, RunStatus, SimulationOptions};
use whirl::Error;

const RADIUS: f64 = 0.04;
const LENGTH: f64 = 0.012;
const CLEARANCE: f64 = 120e-6;
const VISCOSITY: f64 = 0.02;
/// The centring spring, N/m.
const SPRING: f64 = 2e6;

/// A short stiff shaft on two roller bearings, each in a 2 kg housing on a centring spring
/// with a damper of `cavitation`; no gravity, so the static position is the centre.
fn model(cavitation: &str) -> Model {
    let damper = format!(
        "squeeze_film = {{ radius = {RADIUS}, length = {LENGTH}, clearance = {CLEARANCE:e}, \
         viscosity = {VISCOSITY}, cavitation = \"{cavitation}\" }}"
    );
    let bearing = |node: usize, housing: &str| {
        format!(
            "[[roller_bearing]]\nnode = {node}\nhousing = \"{housing}\"\nrollers = 8\n\
             pitch_diameter = 0.0696\nroller_diameter = 0.0061\nroller_length = 0.007\n\
             clearance = \"20 um\"\ncontact_stiffness = 4.52e8\nlinear_stiffness = 1e8\n"
        )
    };
    let text = format!(
        "gravity = 0\n[[material]]\nname = \"steel\"\nyoung_modulus = 2.1e11\ndensity = 7800\n\
         [[shaft]]\nlength = 0.4\nouter_diameter = 0.05\nmaterial = \"steel\"\nelements = 4\n\
         [[housing]]\nname = \"A\"\nmass = 2\nkxx = {SPRING:e}\nkyy = {SPRING:e}\n{damper}\n\
         [[housing]]\nname = \"B\"\nmass = 2\nkxx = {SPRING:e}\nkyy = {SPRING:e}\n{damper}\n\
         {}{}",
        bearing(0, "A"),
        bearing(4, "B")
    );
    Model::from_toml_str(&text, None).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The film force the solvers see (the system's nonlinear forces, as time marching and
/// harmonic balance evaluate them) on both housings moving on a centred circular orbit of
/// eccentricity ratio eps at w, the shaft moving with them (so the rollers stay in their
/// clearance and push nothing), against the closed forms' radial and tangential force at
/// 16 instants of a period. The quadrature's error is 1e-12 of the force up to eps = 0.9
/// (unit tests); 1e-9 also covers the rotation of the frame.
#[test]
fn the_film_force_on_a_circular_orbit_is_the_closed_form() {
    for (name, cavitation) in [("pi", Cavitation::Pi), ("full", Cavitation::Full)] {
        let model = model(name);
        let mut system = build(&model, None, Bearings::NonlinearApart, &hertz_bearings)
            .unwrap()
            .system;
        let n = system.size();
        let housings = [model.housing_dofs(0), model.housing_dofs(1)];
        let damper = model.housings[0].squeeze_film.clone().unwrap();
        assert_eq!(damper.cavitation, cavitation);
        let mut scratch = system.scratch();
        let w = 2.0 * PI * 80.0;
        for eps in [0.1, 0.3, 0.5, 0.7, 0.9] {
            let exact = circular_orbit_closed_form(&damper, eps, w);
            let e = eps * CLEARANCE;
            for k in 0..16 {
                let t = k as f64 / 16.0 / 80.0;
                let (c, s) = ((w * t).cos(), (w * t).sin());
                let mut q = vec![0.0; n];
                let mut v = vec![0.0; n];
                // Housing A and the whole shaft translate together on the orbit.
                for node in 0..5 {
                    q[4 * node] = e * c;
                    q[4 * node + 1] = e * s;
                    v[4 * node] = -e * w * s;
                    v[4 * node + 1] = e * w * c;
                }
                for [hx, hy] in housings {
                    q[hx] = e * c;
                    q[hy] = e * s;
                    v[hx] = -e * w * s;
                    v[hy] = e * w * c;
                }
                let at = Kinematics {
                    time: t,
                    speed: 0.0,
                    angle: 0.0,
                };
                let mut f = vec![0.0; n];
                system.add_nonlinear(&at, &q, &v, &mut f, &mut scratch);
                let expected = [
                    exact.radial_force * c - exact.tangential_force * s,
                    exact.radial_force * s + exact.tangential_force * c,
                ];
                let scale = exact.tangential_force.abs();
                for [hx, hy] in housings {
                    for (got, want) in [f[hx], f[hy]].iter().zip(expected) {
                        assert!(
                            (got - want).abs() < 1e-9 * scale,
                            "{name} eps {eps} t {t}: {got} against {want}"
                        );
                    }
                }
                // Nothing pushes the shaft: the rollers are in their clearance.
                let shaft = f[..4 * 5].iter().map(|x| x.abs()).fold(0.0, f64::max);
                assert_eq!(shaft, 0.0);
            }
        }
    }
}

/// The equivalent coefficients of the film on centred circular orbits, K = -F_r / e and
/// C = -F_t / (e w), against the closed forms: pi film K = 2 mu R L^3 w eps / (c^3 (1 -
/// eps^2)^2), C = pi mu R L^3 / (2 c^3 (1 - eps^2)^(3/2)); full film K = 0, C = pi mu R
/// L^3 / (c^3 (1 - eps^2)^(3/2)). Quadrature error: 1e-10.
#[test]
fn circular_orbit_coefficients_match_the_closed_forms() {
    for name in ["pi", "full"] {
        let damper = model(name).housings[0].squeeze_film.clone().unwrap();
        let w = 2.0 * PI * 100.0;
        for eps in [0.05, 0.2, 0.4, 0.6, 0.8, 0.9] {
            let got = circular_orbit(&damper, eps, w);
            let exact = circular_orbit_closed_form(&damper, eps, w);
            let mu_r_l3 = VISCOSITY * RADIUS * LENGTH.powi(3);
            let one = 1.0 - eps * eps;
            let c = match name {
                "pi" => PI * mu_r_l3 / (2.0 * CLEARANCE.powi(3) * one.powf(1.5)),
                _ => PI * mu_r_l3 / (CLEARANCE.powi(3) * one.powf(1.5)),
            };
            let k = match name {
                "pi" => 2.0 * mu_r_l3 * w * eps / (CLEARANCE.powi(3) * one * one),
                _ => 0.0,
            };
            assert!((exact.damping / c - 1.0).abs() < 1e-14);
            assert!((exact.stiffness - k).abs() <= 1e-14 * k);
            assert!(
                (got.damping / c - 1.0).abs() < 1e-10,
                "{name} {eps}: {got:?}"
            );
            assert!(
                (got.stiffness - k).abs() < 1e-10 * c * w,
                "{name} {eps}: {got:?}"
            );
        }
    }
}

/// Linear analyses see the film linearised at the static position, here the centre: the
/// assembled damping on a housing's translation is the mounting's (none) plus
/// pi mu R L^3 / c^3, halved for the pi film, the closed forms' eps -> 0 limits; the
/// coupling between x and y is zero. Round-off of a sum of quadrature weights: 1e-12.
#[test]
fn the_linearised_film_damps_the_housing_by_the_centred_closed_form() {
    for (name, share) in [("pi", 0.5), ("full", 1.0)] {
        let model = model(name);
        let c = assemble(&model, Bearings::Linearised).damping;
        let [hx, hy] = model.housing_dofs(1);
        let expected = share * PI * VISCOSITY * RADIUS * LENGTH.powi(3) / CLEARANCE.powi(3);
        assert!(
            (c[(hx, hx)] / expected - 1.0).abs() < 1e-12,
            "{}",
            c[(hx, hx)]
        );
        assert!(
            (c[(hy, hy)] / expected - 1.0).abs() < 1e-12,
            "{}",
            c[(hy, hy)]
        );
        assert!(c[(hx, hy)].abs() < 1e-12 * expected);
        // With the bearings apart the film acts by its nonlinear force instead.
        let apart = assemble(&model, Bearings::NonlinearApart).damping;
        assert_eq!(apart[(hx, hx)], 0.0);
        // The solvers' systems (time marching, harmonic balance) take the film's own force
        // whatever the bearings, linear ones included, and leave it out of the matrices.
        let built = build(&model, None, Bearings::Linearised, &no_forces).unwrap();
        assert_eq!(built.system.nonlinear.len(), 2);
        assert_eq!(built.system.matrices.damping[(hx, hx)], 0.0);
    }
}

#[test]
fn bad_dampers_are_refused_with_the_field_named() {
    let good = model("pi");
    assert_eq!(good.housings.len(), 2);
    let text = |field: &str, value: &str| {
        let damper = format!(
            "squeeze_film = {{ radius = {RADIUS}, length = {LENGTH}, clearance = {CLEARANCE:e}, \
             viscosity = {VISCOSITY} }}"
        );
        let bad = damper.replace(
            &format!("{field} = {}", value_of(field)),
            &format!("{field} = {value}"),
        );
        format!(
            "[[material]]\nname = \"steel\"\nyoung_modulus = 2.1e11\ndensity = 7800\n\
             [[shaft]]\nlength = 0.4\nouter_diameter = 0.05\nmaterial = \"steel\"\n\
             elements = 4\n[[housing]]\nname = \"A\"\nmass = 2\nkxx = 1e6\nkyy = 1e6\n{bad}\n"
        )
    };
    for field in ["radius", "length", "clearance", "viscosity"] {
        for value in ["0", "-1e-3"] {
            match Model::from_toml_str(&text(field, value), None) {
                Err(Error::Input(e)) => assert_eq!(
                    e.field.as_deref(),
                    Some(format!("housing[0].squeeze_film.{field}").as_str()),
                    "{e}"
                ),
                other => panic!("{field} = {value} accepted: {:?}", other.map(|m| m.name)),
            }
        }
    }
}

fn value_of(field: &str) -> String {
    match field {
        "radius" => RADIUS.to_string(),
        "length" => LENGTH.to_string(),
        "clearance" => format!("{CLEARANCE:e}"),
        _ => VISCOSITY.to_string(),
    }
}

/// Time marching with the film's nonlinear force: the reference rotor with a damper at each
/// bearing (examples/reference_rotor_sfd.toml) runs at 100 Hz on its Hertz rollers, and
/// on average the rollers carry the rotor's weight (the housings do not accelerate on
/// average, nor does the rotor): the mean vertical roller force on the shaft is half the
/// rotor's weight at each bearing. The support modes (37 Hz, 15 % damped) die out within
/// the 0.3 s settling time to e^-10; what is left of the transient and the averaging over
/// a whole number of periods (within one step) stay below 1e-3.
#[test]
fn the_rollers_carry_the_rotor_through_the_dampers_on_average() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/reference_rotor_sfd.toml");
    let model = Model::from_file(&path).unwrap();
    let step = 0.9 * stable_step(&model, Some(12), ContactLaw::Hertz).unwrap();
    let options = SimulationOptions {
        speed: SpeedProfile::Constant(2.0 * PI * 100.0),
        duration: 0.6,
        step: Some(step),
        method: Method::CentralDifference,
        reduction: Some(12),
        settle: Some(0.3),
        nodes: Some(vec![10]),
        initial: Initial::StaticEquilibrium,
        divergence_bound: 0.01,
        contact: Some(ContactLaw::Hertz),
        record_every: Some(1),
        record_rollers: true,
        progress: None,
    };
    let r = simulate(&model, &options).unwrap();
    assert_eq!(r.status, RunStatus::Completed);
    let weight = 9.81 * (model.shaft_mass() + model.disks[0].mass);
    let start = r.settled_start();
    for record in &r.rollers {
        let lift: f64 = (start..r.time.len())
            .map(|i| {
                record
                    .forces_at(i)
                    .iter()
                    .zip(record.angles_at(i))
                    .map(|(q, a)| -q * a.sin())
                    .sum::<f64>()
            })
            .sum::<f64>()
            / (r.time.len() - start) as f64;
        eprintln!(
            "{}: mean lift {lift:.4} N, half weight {:.4} N, step {step:.3e} s",
            record.name,
            weight / 2.0
        );
        assert!(
            (lift / (weight / 2.0) - 1.0).abs() < 1e-3,
            "{lift} against {}",
            weight / 2.0
        );
    }
}

/// The reference rotor with its roller bearings replaced by linear 1e8 N/m bearings in the
/// damper housings of examples/reference_rotor_sfd.toml, unbalance `eccentricity` on the
/// disk: the dampers are its only nonlinearity.
fn damper_only(eccentricity: &str) -> Model {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../examples/reference_rotor_sfd.toml"),
    )
    .unwrap();
    let roller_fields = [
        "rollers",
        "pitch_diameter",
        "roller_diameter",
        "roller_length",
        "contact_",
        "linear_stiffness",
        "linear_damping",
        "clearance = \"20 um\"",
    ];
    let mut lines = Vec::new();
    for line in text.lines() {
        if roller_fields.iter().any(|f| line.starts_with(f)) {
            continue;
        }
        lines.push(line.replace("[[roller_bearing]]", "[[bearing]]"));
        if line.starts_with("housing = \"damper") {
            lines.extend(["kxx = 1e8".to_string(), "kyy = 1e8".to_string()]);
        }
    }
    let text = lines.join("\n").replace(
        "eccentricity = \"40 um\"",
        &format!("eccentricity = \"{eccentricity}\""),
    );
    Model::from_toml_str(&text, None).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The damper's own jump on harmonic-balance branches: a rotor on linear bearings in pi-film
/// dampers, whose only nonlinearity is the film, has a synchronous branch without a turn at
/// the example's unbalance (40 um), and one that turns back at four times that (160 um):
/// two coexisting motions over a speed range, the bistability known of uncentred and
/// heavily loaded dampers (Vance 1988, ch. 6). Measured: folds at 452.0 and 301.3 Hz.
#[test]
fn the_dampers_own_jump_shows_on_the_harmonic_balance_branch() {
    use whirl::hbm::{sweep, SweepOptions};
    let folds = |eccentricity: &str| {
        let mut options = SweepOptions::new(2.0 * PI, 2.0 * PI * 750.0, 5);
        options.stability = false;
        // As the command line's `hbm --reduce 12` that measured them.
        options.reduction = Some(12);
        let mut model = damper_only(eccentricity);
        assert!(model.roller_bearings.is_empty());
        model.name = eccentricity.into();
        let result = sweep(&model, &options).unwrap();
        assert!(matches!(result.branch.end, whirl::hbm::BranchEnd::Reached));
        let mut hz: Vec<f64> = result
            .branch
            .folds
            .iter()
            .map(|f| f.frequency / (2.0 * PI))
            .collect();
        hz.sort_by(f64::total_cmp);
        hz
    };
    assert_eq!(folds("40 um"), Vec::<f64>::new());
    let turned = folds("160 um");
    assert_eq!(turned.len(), 2, "{turned:?}");
    // The turning points within 1 % of the measured ones (the continuation locates them to
    // its step; the numbers are a record, not a closed form).
    assert!((turned[0] / 301.3 - 1.0).abs() < 0.01, "{turned:?}");
    assert!((turned[1] / 452.0 - 1.0).abs() < 0.01, "{turned:?}");
}
