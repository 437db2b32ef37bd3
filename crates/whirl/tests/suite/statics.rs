//! Static response under gravity against closed forms of beam theory: a shaft on two
//! supports with a disk at mid-span, an overhung shaft (a cantilever on an elastic root),
//! and the reference rotor hanging in its roller bearings.

use std::f64::consts::PI;

use faer::Mat;
use whirl::bearing::hertz_bearings;
use whirl::fe::{assemble, gravity_force, Bearings};
use whirl::force::Kinematics;
use whirl::model::Model;
use whirl::statics::{static_response, RollerSupport, StaticResult};
use whirl::system::build;
use whirl::time::static_equilibrium;

use crate::common::{example_path, reference_rotor};

const E: f64 = 2.1e11;
const RHO: f64 = 7800.0;
const NU: f64 = 0.3;
const D: f64 = 0.05;
const G: f64 = 9.81;
/// Support stiffness, N/m: stiff, and included in the closed forms exactly.
const K: f64 = 1e10;

fn model(sections: &str, extra: &str, beam: &str) -> Model {
    let text = format!(
        r#"
        gravity = {G}
        [[material]]
        name = "steel"
        young_modulus = {E}
        density = {RHO}
        poisson_ratio = {NU}
        {sections}
        [elements]
        beam = "{beam}"
        {extra}
        "#
    );
    Model::from_toml_str(&text, None).expect("test model is valid")
}

fn section(length: f64, elements: usize) -> String {
    format!(
        "[[shaft]]\nlength = {length}\nouter_diameter = {D}\nmaterial = \"steel\"\nelements = {elements}\n"
    )
}

fn bearing(node: usize) -> String {
    format!("[[bearing]]\nnode = {node}\nkxx = {K}\nkyy = {K}\n")
}

fn disk(node: usize, mass: f64) -> String {
    format!(
        "[[disk]]\nnode = {node}\nmass = {mass}\npolar_inertia = 0.01\ndiametral_inertia = 0.005\n"
    )
}

fn area() -> f64 {
    PI * D * D / 4.0
}

fn ei() -> f64 {
    E * PI * D.powi(4) / 64.0
}

fn uy(r: &StaticResult, node: usize) -> f64 {
    r.displacements[4 * node + 1]
}

/// Weight per length of the shaft, N/m.
fn p() -> f64 {
    RHO * area() * G
}

/// Mid-span deflection (down positive) of a shaft of length `l` on supports of stiffness K
/// at its ends, under its weight and a disk of weight `w` at mid-span, with shear
/// deformation when `kga` is finite:
/// 5 p l^4 / (384 EI) + w l^3 / (48 EI)      (bending)
/// + p l^2 / (8 kGA) + w l / (4 kGA)          (shear: the shear force integrated over l/2)
/// + (p l + w) / (2 K)                        (each support gives half the load).
fn two_supports_mid_deflection(l: f64, w: f64, kga: f64) -> f64 {
    let p = p();
    5.0 * p * l.powi(4) / (384.0 * ei())
        + w * l.powi(3) / (48.0 * ei())
        + p * l * l / (8.0 * kga)
        + w * l / (4.0 * kga)
        + (p * l + w) / (2.0 * K)
}

#[test]
fn shaft_on_two_supports_with_a_disk() {
    let (l, m) = (1.0, 5.0);
    let text = section(l, 20);
    let extra = format!("{}{}{}", bearing(0), bearing(20), disk(10, m));
    let r = static_response(
        &model(&text, &extra, "euler-bernoulli"),
        RollerSupport::Linear,
    )
    .unwrap();
    let w = m * G;
    let exact = two_supports_mid_deflection(l, w, f64::INFINITY);
    let got = -uy(&r, 10);
    println!("two supports: mid-span deflection {got:.6e} m, closed form {exact:.6e} m");
    // Hermite elements with consistent loads give exact nodal deflections for a uniform
    // load and point loads at nodes: only round-off (stiff supports, cond ~ 1e6) remains.
    assert!((got / exact - 1.0).abs() < 1e-9, "{got} vs {exact}");
    assert_eq!(r.max_deflection.node, 10);

    // Reactions: each support carries half the weight; their sum is the weight.
    let weight = p() * l + w;
    assert!(
        (r.weight / weight - 1.0).abs() < 1e-12,
        "{} vs {weight}",
        r.weight
    );
    let total = r.total_reaction();
    println!("reactions sum {:.6} N, weight {:.6} N", total[1], r.weight);
    // The equilibrium is solved to 1e-10 of the load (static_equilibrium's tolerance).
    assert!((total[1] / weight - 1.0).abs() < 1e-9);
    assert!(total[0].abs() < 1e-9 * weight);
    for b in &r.reactions {
        assert!((b.force[1] / (weight / 2.0) - 1.0).abs() < 1e-9);
    }

    // Bending moment at mid-span p l^2 / 8 + w l / 4 (sagging, positive), equal on both
    // sides of the disk; shear force R = weight / 2 at the left support, and a jump of the
    // disk's weight across it.
    let mid: Vec<_> = r.stations.iter().filter(|s| s.node == 10).collect();
    assert_eq!(mid.len(), 2);
    let moment = p() * l * l / 8.0 + w * l / 4.0;
    for s in &mid {
        // Element end forces are exact at nodes for these loads: round-off only.
        assert!((s.moment[1] / moment - 1.0).abs() < 1e-8, "{}", s.moment[1]);
    }
    assert!(((mid[0].shear[1] - mid[1].shear[1]) / w - 1.0).abs() < 1e-8);
    let first = &r.stations[0];
    assert!((first.shear[1] / (weight / 2.0) - 1.0).abs() < 1e-8);
    // Pinned ends carry no moment.
    assert!(first.moment[1].abs() < 1e-8 * moment);
}

#[test]
fn timoshenko_adds_the_shear_deflection() {
    let (l, m) = (0.3, 5.0);
    let text = section(l, 10);
    let extra = format!("{}{}{}", bearing(0), bearing(10), disk(5, m));
    let r = static_response(&model(&text, &extra, "timoshenko"), RollerSupport::Linear).unwrap();
    let kappa = whirl::model::circular_shear_factor(D, 0.0, NU);
    let kga = kappa * E / (2.0 * (1.0 + NU)) * area();
    let exact = two_supports_mid_deflection(l, m * G, kga);
    let bending_only = two_supports_mid_deflection(l, m * G, f64::INFINITY);
    let got = -uy(&r, 5);
    println!(
        "Timoshenko, l/d = 6: {got:.6e} m, closed form {exact:.6e} m, without shear {bending_only:.6e} m"
    );
    // The interdependent interpolation solves the static Timoshenko equations exactly, so
    // nodal deflections are exact: round-off only.
    assert!((got / exact - 1.0).abs() < 1e-9, "{got} vs {exact}");
    // The shear part is not negligible at l/d = 6 (a few percent), so the test can tell.
    assert!(exact / bending_only - 1.0 > 0.01);
}

#[test]
fn overhung_shaft_is_a_cantilever_on_an_elastic_root() {
    // Supports at z = 0 (A) and z = a (B), the shaft overhanging by c beyond B with a disk
    // of weight w at its tip. Down positive:
    //   R_B = (p (a + c)^2 / 2 + w (a + c)) / a,  R_A = p (a + c) + w - R_B
    //   tip = p c^4 / (8 EI) + w c^3 / (3 EI)                 (cantilever on B's tangent)
    //       + c (M_B a / (3 EI) - p a^3 / (24 EI))            (rotation of the span at B,
    //                                                          M_B = p c^2 / 2 + w c)
    //       + d_B + (d_B - d_A) c / a,  d = R / K             (the supports' give)
    let (a, c, m) = (0.6, 0.4, 3.0);
    let text = format!("{}{}", section(a, 12), section(c, 8));
    let extra = format!("{}{}{}", bearing(0), bearing(12), disk(20, m));
    let r = static_response(
        &model(&text, &extra, "euler-bernoulli"),
        RollerSupport::Linear,
    )
    .unwrap();
    let (p, w, ei) = (p(), m * G, ei());
    let rb = (p * (a + c).powi(2) / 2.0 + w * (a + c)) / a;
    let ra = p * (a + c) + w - rb;
    let mb = p * c * c / 2.0 + w * c;
    let (da, db) = (ra / K, rb / K);
    let tip = p * c.powi(4) / (8.0 * ei)
        + w * c.powi(3) / (3.0 * ei)
        + c * (mb * a / (3.0 * ei) - p * a.powi(3) / (24.0 * ei))
        + db
        + (db - da) * c / a;
    let got = -uy(&r, 20);
    println!("overhung tip deflection {got:.6e} m, closed form {tip:.6e} m; R_A {ra:.4} N, R_B {rb:.4} N");
    // Nodal exactness as above: round-off only.
    assert!((got / tip - 1.0).abs() < 1e-9, "{got} vs {tip}");
    assert_eq!(r.max_deflection.node, 20);
    // R_A is negative here: the overhang lifts the shaft off A, which must pull it down.
    assert!((r.reactions[0].force[1] / ra - 1.0).abs() < 1e-8);
    assert!((r.reactions[1].force[1] / rb - 1.0).abs() < 1e-8);
    // The hogging moment over B is -M_B; the free end carries neither moment nor shear.
    let over_b: Vec<_> = r.stations.iter().filter(|s| s.node == 12).collect();
    for s in over_b {
        assert!((s.moment[1] / -mb - 1.0).abs() < 1e-8, "{}", s.moment[1]);
    }
    let end = r.stations.last().unwrap();
    // The tip's shear is the disk's weight (the disk hangs at the last node): V = dM/dz
    // with M = -(w x + p x^2 / 2), x measured back from the tip, is +w there.
    assert!((end.shear[1] / w - 1.0).abs() < 1e-8, "{}", end.shear[1]);
    assert!(end.moment[1].abs() < 1e-8 * mb);
}

#[test]
fn reference_rotor_hangs_in_its_roller_bearings() {
    let model = reference_rotor();
    let r = static_response(&model, RollerSupport::Hertz).unwrap();
    let total = r.total_reaction();
    println!(
        "reference rotor on Hertz rollers: weight {:.4} N, reactions {:?}",
        r.weight, total
    );
    // static_equilibrium converges to 1e-10 of the load.
    assert!((total[1] / r.weight - 1.0).abs() < 1e-8);
    for b in &r.reactions {
        // Each bearing drops through its 20 um clearance onto the bottom roller.
        assert!(b.displacement[1] < -20e-6, "{:?}", b.displacement);
        assert_eq!(b.rollers.len(), 8);
        // The rollers' loads add up to the bearing's force (vertical components).
        let lifted: f64 = b
            .rollers
            .iter()
            .map(|q| -q.force * q.angle_deg.to_radians().sin())
            .sum();
        assert!((lifted / b.force[1] - 1.0).abs() < 1e-9);
        let bottom = b
            .rollers
            .iter()
            .max_by(|x, y| x.force.total_cmp(&y.force))
            .unwrap();
        assert!((bottom.angle_deg - 270.0).abs() < 1e-6, "{bottom:?}");
    }
    // With linear springs of 1e8 N/m the journal sits at -R / k instead.
    let lin = static_response(&model, RollerSupport::Linear).unwrap();
    for b in &lin.reactions {
        assert!((b.displacement[1] + b.force[1] / 1e8).abs() < 1e-9 * b.displacement[1].abs());
    }
}

#[test]
fn the_full_model_hangs_in_its_rollers_at_any_mesh() {
    // The static start of the full (unreduced) model once failed from 80 elements on; the
    // disk stays at mid-span and the bearings at the ends on every mesh.
    let reference = reference_rotor();
    let bearing = &reference.roller_bearings[0];
    for elements in [80, 640] {
        let model = reference.remeshed(&[elements]).unwrap();
        let r = static_response(&model, RollerSupport::Hertz).unwrap();
        // The solve converges to 1e-10 of the load, but its round-off grows with the
        // condition of the stiffness, as the fourth power of the element count (an
        // element's bending stiffness goes as 1/l^3, the bearings' stays): the drop's
        // relative error went 2e-14, 2e-12 (80), 3e-8 (640) before the solves were refined
        // against the elements' own products, 2e-14, 6e-14, 3e-11 since; the total
        // reaction's is about 14 times that (the roller's force goes as the 10/9 power of
        // the 1.66 um beyond the clearance, 1/13 of the drop). The bounds allow at least 3
        // times what was measured before.
        let growth = (elements as f64 / 20.0).powi(4);
        let total = r.total_reaction();
        assert!(
            (total[1] / r.weight - 1.0).abs() < 1e-12 * growth,
            "{elements}: {total:?} against {}",
            r.weight
        );
        assert!(total[0].abs() < 1e-12 * r.weight, "{elements}: {total:?}");
        // Symmetric rotor: each bearing carries half the weight on its bottom roller alone
        // (the two next to it, 45 degrees away, stay clear: 0.71 of the drop is below the
        // clearance), so the journal drops by c + (W / 2 k)^(1 / n), Hertz's closed form.
        let k = bearing.contact_stiffness;
        let n = bearing.contact_exponent;
        let drop = bearing.clearance.at_speed(0.0) + (0.5 * r.weight / k).powf(1.0 / n);
        for b in &r.reactions {
            assert!(
                (-b.displacement[1] / drop - 1.0).abs() < 1e-13 * growth,
                "{elements}: {} against {drop}",
                b.displacement[1]
            );
        }
    }
}

#[test]
fn the_banded_solve_is_the_dense_solve() {
    // The static response holds the stiffness on its bands and condenses the balance onto
    // the contacts' coordinates; here it is checked against the balance written dense, on
    // the reference rotor and a 40-element mesh of it.
    for elements in [20, 40] {
        let model = reference_rotor().remeshed(&[elements]).unwrap();
        // Linear rollers: K q = F_g, solved by a dense LU with partial pivoting.
        let m = assemble(&model, Bearings::Linearised);
        let f = gravity_force(&model, &m);
        let n = f.len();
        let mut dense = Mat::<f64>::from_fn(n, 1, |i, _| f[i]);
        faer::linalg::solvers::Solve::solve_in_place(&m.stiffness.partial_piv_lu(), dense.as_mut());
        let linear = static_response(&model, RollerSupport::Linear).unwrap();
        let largest = linear
            .displacements
            .iter()
            .fold(0.0f64, |a, x| a.max(x.abs()));
        let apart = linear
            .displacements
            .iter()
            .enumerate()
            .fold(0.0f64, |a, (i, q)| a.max((q - dense[(i, 0)]).abs()));
        println!(
            "{elements} elements: linear {:.2e} of the largest displacement apart",
            apart / largest
        );
        // Two factorisations (a band LU without row swaps, a dense one with them) of a
        // matrix whose condition (K's largest entries against the bearings' 1e8 N/m)
        // grows as the cube of the element count: measured 1.8e-12 at 20 elements and
        // 2.4e-11 at 40.
        assert!(apart < 1e-10 * largest, "{elements}: {apart} m");
        // Hertz rollers: the whole balance K q - F_g - F_c(q), dense, vanishes, and the
        // displacements are those of the solver of the time-marching start (the dense
        // system of `build`).
        let hertz = static_response(&model, RollerSupport::Hertz).unwrap();
        let mut system = build(&model, None, Bearings::NonlinearApart, &hertz_bearings)
            .unwrap()
            .system;
        let q = &hertz.displacements;
        let mut balance = vec![0.0; n];
        let rest = Kinematics {
            time: 0.0,
            speed: 0.0,
            angle: 0.0,
        };
        let mut scratch = system.scratch();
        system.add_nonlinear(&rest, q, &vec![0.0; n], &mut balance, &mut scratch);
        let residual: f64 = (0..n)
            .map(|i| {
                let kq: f64 = (0..n)
                    .map(|j| system.matrices.stiffness[(i, j)] * q[j])
                    .sum();
                (kq - system.constant_force[i] - balance[i]).powi(2)
            })
            .sum::<f64>()
            .sqrt();
        let load = system
            .constant_force
            .iter()
            .map(|x| x * x)
            .sum::<f64>()
            .sqrt();
        // Converged to 1e-10 of the load on the contacts' coordinates; the rest is solved
        // exactly up to the rounding of K q (entries to 4e10 N/m times 1e-4 m): measured
        // 3.3e-12 of the load at 20 elements and 3.7e-11 at 40.
        assert!(
            residual < 1e-9 * load,
            "{elements}: {residual} N against {load} N"
        );
        println!(
            "{elements} elements: Hertz balance {:.2e} of the load",
            residual / load
        );
        // The time-marching start condenses the same way, with K x from the band where the
        // static response takes it from the elements: the vertical plane (uy, tx) agrees to
        // round-off. The horizontal position on one bottom roller is set by round-off alone
        // (neither stiffness nor load: the rotor may roll sideways in its clearance).
        let marched = static_equilibrium(&mut system, &vec![0.0; n], 0.0).unwrap();
        let apart = |plane: [usize; 2]| {
            q.iter()
                .zip(&marched)
                .enumerate()
                .filter(|(i, _)| plane.contains(&(i % 4)))
                .fold(0.0f64, |a, (_, (x, y))| a.max((x - y).abs()))
                / largest
        };
        let (vertical, horizontal) = (apart([1, 2]), apart([0, 3]));
        println!("{elements} elements: vertical {vertical:.1e}, horizontal {horizontal:.1e} apart");
        assert!(vertical < 1e-11, "{elements}: {vertical}");
        assert!(horizontal < 1e-5, "{elements}: {horizontal}");
    }
}

#[test]
fn static_solves_meshes_too_large_for_dense_matrices_to_the_nodally_exact_answer() {
    // 2,000 and 10,000 elements: 8,004 and 40,004 DOFs, which `static` refused (it held the
    // stiffness and the contact tangents dense, 512 MB each at 8,004 DOFs). Cubic beam
    // elements are exact at the nodes under point loads and the shaft's uniform weight, so
    // each node of the 20-element mesh has the same deflection on every finer one, and the
    // bearings the same loads: what differs is round-off. Solved on the bands alone, the
    // 10,000-element mesh's bearing loads were 6e-4 off and its sag 2.5e-4; with the
    // products from the elements' deformation, measured 2.6e-6 on the loads and 5.8e-8 of
    // the sag on the deflections (8.8e-9 and 9.8e-11 at 2,000 elements).
    let reference = reference_rotor();
    let coarse = static_response(&reference, RollerSupport::Hertz).unwrap();
    let sag = uy(&coarse, 10).abs();
    for elements in [2000, 10_000] {
        let model = reference.remeshed(&[elements]).unwrap();
        assert_eq!(model.dof_count(), 4 * (elements + 1));
        let fine = static_response(&model, RollerSupport::Hertz).unwrap();
        let every = elements / 20;
        let deflection = (0..=20)
            .map(|node| (uy(&coarse, node) - uy(&fine, every * node)).abs() / sag)
            .fold(0.0f64, f64::max);
        let loads = coarse
            .reactions
            .iter()
            .zip(&fine.reactions)
            .map(|(a, b)| (b.force[1] / a.force[1] - 1.0).abs())
            .fold(0.0f64, f64::max);
        println!("{elements} elements: deflections {deflection:.1e} of the sag, loads {loads:.1e}");
        assert!(deflection < 5e-7, "{elements}: {deflection}");
        assert!(loads < 1e-5, "{elements}: {loads}");
    }
}

#[test]
fn bands_widened_past_memory_by_a_housing_are_refused_before_allocation() {
    // A bearing in a housing couples the shaft's node with the housing's DOFs, numbered
    // after all the shaft's, so the bands reach across the whole model: at 2,000 elements
    // with the rollers' linear stiffness (shaft to housing) they would take about 12 GB.
    // With Hertz rollers the contacts between shaft and housing are condensed apart and
    // the bands stay narrow.
    let model = Model::from_file(&example_path("reference_rotor_sfd.toml"))
        .unwrap()
        .remeshed(&[2000])
        .unwrap();
    match static_response(&model, RollerSupport::Linear) {
        Err(whirl::Error::Unsupported(m)) => {
            assert!(m.contains("8008 DOFs") && m.contains("housing"), "{m}");
            assert!(
                m.contains("Use fewer elements") && !m.contains("--reduce"),
                "{m}"
            );
        }
        other => panic!("expected a refusal, got {:?}", other.map(|_| ())),
    }
    let hertz = static_response(&model, RollerSupport::Hertz).unwrap();
    let total = hertz.total_reaction();
    // The rollers carry the rotor (the housings hang on their centring springs), to the
    // solver's tolerance and the fine mesh's round-off.
    assert!(
        (total[1] / hertz.weight - 1.0).abs() < 1e-7,
        "{total:?} against {}",
        hertz.weight
    );
}

#[test]
fn the_analyses_that_solve_dense_matrices_refuse_a_model_too_large_for_them() {
    // 2,000 elements: 8,004 DOFs, whose four dense matrices would take 2 GB. The bearing's
    // gravity load solves dense matrices, and the critical-speed map does when a quarter of
    // its plane's 4,002 DOFs or more are asked for as modes (it computes a few on the bands,
    // `tests/suite/frf.rs`); each must refuse before allocating, naming the size and what to
    // do instead.
    let model = reference_rotor().remeshed(&[2000]).unwrap();
    let refusals = [
        whirl::modal::critical_speed_map(&model, &[1e8], 1001, true, None).err(),
        whirl::bearing::stiffness::gravity_load(&model, 0).err(),
    ];
    for refusal in refusals {
        match refusal {
            Some(whirl::Error::Unsupported(m)) => {
                assert!(
                    m.contains("8004 DOFs") && m.contains("limited to 4000"),
                    "{m}"
                );
            }
            other => panic!("expected a refusal, got {other:?}"),
        }
    }
}
