//! Bearing housings (pedestals): a rotor on bearings mounted in housings with mass, each
//! housing on its own spring, against closed forms; the same through every path that
//! assembles the system (Craig-Bampton, the static solve with Hertz contacts in housings,
//! ROSS's point masses with linked bearings); and bad housings refused with the field named.

use std::f64::consts::PI;

use whirl::fe::{assemble, Bearings};
use whirl::modal::undamped_modes;
use whirl::model::ross::from_ross_toml;
use whirl::model::{Housing, LinearBearing, Model};
use whirl::reduce::{boundary_dofs, CraigBampton};
use whirl::statics::{static_response, RollerSupport};
use whirl::Error;

const LENGTH: f64 = 0.5;
const DIAMETER: f64 = 0.05;
const DENSITY: f64 = 7800.0;
/// A shaft 1e4 times steel's stiffness: its first bending mode (about 6 kHz) is far above
/// the supports' (below 15 Hz), so the rotor moves as a rigid body to k / k_shaft ~ 1e-7.
const YOUNG: f64 = 1e15;
/// Bearing stiffness (shaft to housing), N/m.
const BEARING: f64 = 1e4;
/// Housing mounting stiffness (housing to ground), N/m.
const MOUNTING: f64 = 2.5e4;
/// Housing mass, kg.
const HOUSING: f64 = 1.5;
/// Shaft elements: few, as the rigid shaft's element stiffness (12 E I / l^3) against the
/// supports' sets the eigen-solver's round-off.
const ELEMENTS: usize = 2;

/// A uniform shaft on two bearings at its ends, each in a housing of `HOUSING` kg on
/// `MOUNTING` N/m; `bearing` is the bearing table's kind (`bearing`, `roller_bearing`).
fn rotor(bearing: &str) -> String {
    let fields = match bearing {
        "bearing" => format!("kxx = {BEARING}\nkyy = {BEARING}"),
        _ => format!(
            "rollers = 8\npitch_diameter = 0.0696\nroller_diameter = 0.0061\n\
             roller_length = 0.007\nclearance = \"20 um\"\ncontact_stiffness = 4.52e8\n\
             linear_stiffness = {BEARING}"
        ),
    };
    format!(
        r#"
gravity = 9.81
[[material]]
name = "stiff"
young_modulus = {YOUNG:e}
density = {DENSITY}
[[shaft]]
length = {LENGTH}
outer_diameter = {DIAMETER}
material = "stiff"
elements = {ELEMENTS}
[elements]
gyroscopic = false
[[housing]]
name = "pedestal A"
mass = {HOUSING}
kxx = {MOUNTING}
kyy = {MOUNTING}
[[housing]]
name = "pedestal B"
mass = {HOUSING}
kxx = {MOUNTING}
kyy = {MOUNTING}
[[{bearing}]]
{fields}
node = 0
housing = "pedestal A"
[[{bearing}]]
{fields}
node = {ELEMENTS}
housing = "pedestal B"
"#
    )
}

/// The two roots w^2 of a rigid body of mass `m` (per support: the rotor's mass or
/// 4 J / L^2 for the tilt) on two supports, each a bearing `BEARING` to a housing of
/// `HOUSING` on `MOUNTING`: M = diag(m, 2 m_h), K = [[2 k_b, -2 k_b], [-2 k_b, 2 (k_b +
/// k_s)]], det(K - w^2 M) = 0.
fn two_mass_roots(m: f64) -> [f64; 2] {
    let (m1, m2) = (m, 2.0 * HOUSING);
    let (k11, k12, k22) = (2.0 * BEARING, -2.0 * BEARING, 2.0 * (BEARING + MOUNTING));
    let a = m1 * m2;
    let b = -(k11 * m2 + k22 * m1);
    let c = k11 * k22 - k12 * k12;
    let root = (b * b - 4.0 * a * c).sqrt();
    [(-b - root) / (2.0 * a), (-b + root) / (2.0 * a)]
}

/// The rigid rotor's closed-form frequencies (Hz), ascending, each once: bounce (the
/// rotor's mass) and tilt (4 J / L^2, J = m L^2 / 12 + m d^2 / 16 about the middle with
/// the cross-sections' rotary inertia, which the elements carry).
fn closed_form_hz() -> Vec<f64> {
    let mass = DENSITY * PI / 4.0 * DIAMETER * DIAMETER * LENGTH;
    let tilt = mass * LENGTH * LENGTH / 12.0 + mass * DIAMETER * DIAMETER / 16.0;
    let mut hz: Vec<f64> = two_mass_roots(mass)
        .into_iter()
        .chain(two_mass_roots(4.0 * tilt / (LENGTH * LENGTH)))
        .map(|w2| w2.sqrt() / (2.0 * PI))
        .collect();
    hz.sort_by(f64::total_cmp);
    hz
}

/// Each frequency twice (x and y alike), ascending.
fn doubled(hz: &[f64]) -> Vec<f64> {
    hz.iter().flat_map(|&f| [f, f]).collect()
}

/// The rigid-rotor closed form holds to the shaft's flexibility, k_b / k_shaft ~ 1e-7, and
/// the solver's round-off on the stiffness spread (the shaft's 3e11 N/m against 1e4):
/// measured 1.4e-7 (full model) and 2.4e-7 (reduced); 1e-6 is the issue's bar.
const RIGID: f64 = 1e-6;

fn assert_close(whirl: &[f64], expected: &[f64], tolerance: f64) {
    let worst = whirl
        .iter()
        .zip(expected)
        .map(|(w, e)| (w / e - 1.0).abs())
        .fold(0.0, f64::max);
    eprintln!("worst relative difference {worst:.2e}");
    assert!(worst < tolerance, "{whirl:?}\nagainst {expected:?}");
}

#[test]
fn a_rigid_rotor_on_two_housings_has_the_two_mass_frequencies() {
    let expected = doubled(&closed_form_hz());
    for kind in ["bearing", "roller_bearing"] {
        let model = Model::from_toml_str(&rotor(kind), None).unwrap();
        assert_eq!(model.dof_count(), 4 * (ELEMENTS + 1) + 2 * 2);
        let modes = undamped_modes(&assemble(&model, Bearings::Linearised), 8).unwrap();
        assert_close(&modes.frequencies_hz, &expected, RIGID);
        // The next mode is the shaft's bending, far above.
        let ninth = undamped_modes(&assemble(&model, Bearings::Linearised), 9).unwrap();
        assert!(
            ninth.frequencies_hz[8] > 1000.0,
            "{:?}",
            ninth.frequencies_hz
        );
    }
}

/// Craig-Bampton keeps the housings' DOFs on the boundary: its boundary is the bearing
/// nodes' 8 DOFs and the housings' 4, and with 2 fixed-interface modes its lowest
/// frequencies are the full model's (the supports' modes live on the boundary DOFs; the
/// interior of a near-rigid shaft adds ~k / k_shaft): 1e-6.
#[test]
fn a_reduction_keeps_the_housings_on_its_boundary() {
    let model = Model::from_toml_str(&rotor("bearing"), None).unwrap();
    let boundary = boundary_dofs(&model, &[]);
    assert_eq!(boundary.len(), 8 + 4);
    let first = 4 * (ELEMENTS + 1);
    assert_eq!(&boundary[8..], &[first, first + 1, first + 2, first + 3]);
    let full = assemble(&model, Bearings::Linearised);
    let cb = CraigBampton::new(&full, &boundary, 2).unwrap();
    let reduced = undamped_modes(&cb.reduced, 8).unwrap();
    assert_close(&reduced.frequencies_hz, &doubled(&closed_form_hz()), RIGID);
}

/// Under gravity each housing sinks by its own weight and half the rotor's over its
/// mounting, whatever carries the rotor to it (here Hertz contacts through the clearance):
/// (m_h + m / 2) g / k_s, exact for a symmetric rotor. The solve's round-off is the
/// stiffness spread (the rigid shaft's 3e10 N/m against the mounting's 2.5e4) times 1e-16:
/// 1e-10; measured 1.2e-8 (the Hertz contacts' 1e8 N/m tangent against the mounting add
/// to the spread); 1e-7.
#[test]
fn housings_carry_the_rotor_weight_through_hertz_contacts() {
    let model = Model::from_toml_str(&rotor("roller_bearing"), None).unwrap();
    let result = static_response(&model, RollerSupport::Hertz).unwrap();
    let mass = DENSITY * PI / 4.0 * DIAMETER * DIAMETER * LENGTH;
    let sag = -(HOUSING + mass / 2.0) * 9.81 / MOUNTING;
    for h in 0..2 {
        let [x, y] = model.housing_dofs(h);
        let u = &result.displacements;
        assert!((u[y] / sag - 1.0).abs() < 1e-7, "{} against {sag}", u[y]);
        assert!(u[x].abs() < 1e-12, "{}", u[x]);
    }
    // The bearings' reactions hold the rotor: their sum is its weight.
    let held = result.reactions.iter().map(|r| r.force[1]).sum::<f64>();
    assert!((held / (mass * 9.81) - 1.0).abs() < 1e-7, "{held}");
}

/// A ROSS rotor whose bearings are linked to point masses on support nodes (`n_link`),
/// each support node on a bearing to the ground: the reader makes housings of them, and
/// the frequencies are those of the same model written directly, to round-off.
#[test]
fn ross_point_masses_with_linked_bearings_become_housings() {
    let mut ross = String::from("ross_version = \"2.3.0\"\n");
    for n in 0..ELEMENTS {
        ross.push_str(&format!(
            "[\"ShaftElement_{n}\"]\nL = {}\nidl = 0.0\nodl = {DIAMETER}\nidr = 0.0\n\
             odr = {DIAMETER}\nn = {n}\nshear_effects = false\nrotary_inertia = true\n\
             gyroscopic = false\naxial_force = 0\ntorque = 0\nalpha = 0\nbeta = 0\n\
             [\"ShaftElement_{n}\".material]\nname = \"stiff\"\nrho = {DENSITY}\n\
             E = {YOUNG}\nG_s = {}\n",
            LENGTH / ELEMENTS as f64,
            YOUNG / 2.6
        ));
    }
    for (tag, shaft, support) in [("A", 0, ELEMENTS + 1), ("B", ELEMENTS, ELEMENTS + 2)] {
        ross.push_str(&format!(
            "[\"PointMass_pedestal {tag}\"]\nn = {support}\nmx = {HOUSING}\nmy = {HOUSING}\n\
             [\"BearingElement_bearing {tag}\"]\nn = {shaft}\nn_link = {support}\n\
             kxx = [{BEARING}]\nkyy = [{BEARING}]\n\
             [\"BearingElement_mount {tag}\"]\nn = {support}\nkxx = [{MOUNTING}]\n\
             kyy = [{MOUNTING}]\n"
        ));
    }
    let import = from_ross_toml(&ross, "linked").unwrap();
    let model = Model::from_toml_str(&import.toml, None).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(model.housings.len(), 2, "{}", import.toml);
    let direct = Model::from_toml_str(&rotor("bearing"), None).unwrap();
    let hz = |m: &Model| {
        undamped_modes(&assemble(m, Bearings::Linearised), 8)
            .unwrap()
            .frequencies_hz
    };
    // The same matrices but for the material's Poisson ratio, which Euler-Bernoulli
    // elements do not use: equal to round-off.
    assert_close(&hz(&model), &hz(&direct), 1e-12);
}

/// A flexible rotor (the reference rotor's shaft and disk) on bearings `k_b` in housings
/// `m_h` on mountings `k_s`: at each of its natural frequencies w, a housing behind its
/// bearing is, exactly, a bearing to the ground of dynamic stiffness
/// k_eq(w) = k_b (k_s - m_h w^2) / (k_b + k_s - m_h w^2), so the rotor on grounded bearings
/// of that stiffness has w among its natural frequencies. Both solves are of well-scaled
/// symmetric problems (round-off ~1e-13); 1e-9 would show any coupling term wrong.
#[test]
fn a_flexible_rotor_in_housings_has_the_frequencies_of_its_equivalent_supports() {
    const K_B: f64 = 1e8;
    const K_S: f64 = 2e8;
    const M_H: f64 = 3.0;
    let base = Model::from_toml_str(whirl::examples::REFERENCE_ROTOR, None).unwrap();
    let supported = |k: f64, in_housings: bool| {
        let mut m = base.clone();
        let rollers = std::mem::take(&mut m.roller_bearings);
        m.bearings = rollers
            .iter()
            .enumerate()
            .map(|(i, b)| LinearBearing {
                name: b.name.clone(),
                station: b.station,
                stiffness: [[k, 0.0], [0.0, k]],
                damping: [[0.0; 2]; 2],
                housing: in_housings.then_some(i),
            })
            .collect();
        if in_housings {
            m.housings = (0..rollers.len())
                .map(|i| Housing {
                    name: format!("housing {i}"),
                    mass: M_H,
                    on: None,
                    stiffness: [[K_S, 0.0], [0.0, K_S]],
                    damping: [[0.0; 2]; 2],
                    squeeze_film: None,
                })
                .collect();
        }
        m
    };
    let hz = |m: &Model, count: usize| {
        undamped_modes(&assemble(m, Bearings::Linearised), count)
            .unwrap()
            .frequencies_hz
    };
    let housed = hz(&supported(K_B, true), 6);
    let mut worst = 0.0f64;
    for &f in housed.iter().step_by(2) {
        let w = 2.0 * PI * f;
        let behind = K_S - M_H * w * w;
        assert!(behind > 0.0, "{f} Hz is above the housings' own resonance");
        let k_eq = K_B * behind / (K_B + behind);
        let grounded = hz(&supported(k_eq, false), 12);
        let nearest = grounded
            .iter()
            .map(|g| (g / f - 1.0).abs())
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(nearest);
    }
    eprintln!("housed {housed:?}: worst {worst:.1e}");
    assert!(worst < 1e-9, "{worst}");
}

fn refusal(text: &str) -> (String, String) {
    match Model::from_toml_str(text, None) {
        Err(Error::Input(e)) => (e.field.clone().unwrap_or_default(), e.to_string()),
        other => panic!("expected a refusal, got {:?}", other.map(|m| m.housings)),
    }
}

#[test]
fn bad_housings_are_refused_with_the_field_named() {
    let good = rotor("bearing");
    let cases = [
        (
            good.replacen(&format!("mass = {HOUSING}"), "mass = 0", 1),
            "housing[0].mass",
        ),
        (
            good.replacen(&format!("kyy = {MOUNTING}"), "", 1),
            "housing[0].kyy",
        ),
        (
            good.replacen(
                "name = \"pedestal A\"",
                "name = \"pedestal A\"\non = \"pedestal A\"",
                1,
            ),
            "housing[0].on",
        ),
        (
            good.replacen(
                "name = \"pedestal A\"",
                "name = \"pedestal A\"\non = \"pedestal B\"",
                1,
            )
            .replacen(
                "name = \"pedestal B\"",
                "name = \"pedestal B\"\non = \"pedestal A\"",
                1,
            ),
            "housing[0].on",
        ),
        (
            good.replacen("housing = \"pedestal B\"", "housing = \"pedestal C\"", 1),
            "bearing[1].housing",
        ),
        (
            good.replacen("name = \"pedestal B\"", "name = \"pedestal A\"", 1),
            "housing[1].name",
        ),
    ];
    for (text, field) in cases {
        let (named, message) = refusal(&text);
        assert_eq!(named, field, "{message}");
    }
    // A housing without a mass: the file's parser names the missing field.
    let (_, message) = refusal(&good.replacen(&format!("mass = {HOUSING}"), "", 1));
    assert!(message.contains("mass"), "{message}");
}
