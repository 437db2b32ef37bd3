//! Campbell diagrams: whirl direction, tracking through crossings, truncated basis error.

use std::f64::consts::PI;

use whirl::fe::{assemble, assemble_banded, Bearings, SystemMatrices};
use whirl::modal::{campbell, solves_dense, CampbellOptions, CampbellResult, Whirl};
use whirl::model::Model;

use crate::common::reference_rotor;

fn system(text: &str) -> SystemMatrices {
    assemble(
        &Model::from_toml_str(text, None).unwrap(),
        Bearings::Linearised,
    )
}

fn speeds(max_hz: f64, count: usize) -> Vec<f64> {
    (0..count)
        .map(|i| 2.0 * PI * max_hz * i as f64 / (count - 1) as f64)
        .collect()
}

fn run(sys: &SystemMatrices, max_hz: f64, count: usize, basis: Option<usize>) -> CampbellResult {
    let mut o = CampbellOptions::new(speeds(max_hz, count));
    o.basis_size = basis;
    campbell(sys, &o, None).unwrap()
}

#[test]
fn forward_branches_rise_and_backward_branches_fall() {
    for text in [
        whirl::examples::REFERENCE_ROTOR,
        whirl::examples::REFERENCE_ROTOR_SOFT,
    ] {
        let c = run(&system(text), 800.0, 81, Some(24));
        assert_eq!(c.branches.len(), 8);
        for b in &c.branches {
            let (first, last) = (b.frequency_hz[0], b.frequency_hz[80]);
            match b.whirl {
                Whirl::Forward => assert!(last > first, "branch {} {first} -> {last}", b.index),
                Whirl::Backward => assert!(last < first, "branch {} {first} -> {last}", b.index),
                Whirl::Mixed => panic!("branch {} is mixed", b.index),
            }
        }
        // Forward and backward alternate in each pair split by the gyroscopic effect.
        let kinds: Vec<Whirl> = c.branches.iter().map(|b| b.whirl).collect();
        for pair in kinds.chunks(2) {
            assert_eq!(pair, [Whirl::Backward, Whirl::Forward]);
        }
    }
}

#[test]
fn branches_are_followed_through_a_crossing() {
    // Up to 4000 Hz the falling backward branch 6 of the reference rotor crosses the rising
    // forward branch 5; sorting by frequency would swap them there.
    let c = run(
        &system(whirl::examples::REFERENCE_ROTOR),
        4000.0,
        401,
        Some(24),
    );
    let (b5, b6) = (&c.branches[5], &c.branches[6]);
    let gap: Vec<f64> = b6
        .frequency_hz
        .iter()
        .zip(&b5.frequency_hz)
        .map(|(a, b)| a - b)
        .collect();
    assert!(
        gap[0] > 0.0 && gap[400] < 0.0,
        "no crossing: {} {}",
        gap[0],
        gap[400]
    );
    for b in [b5, b6] {
        // Smooth: no step larger than the branch's own slope allows (at most about 2 Hz per
        // 10 Hz of speed here), and one whirl direction throughout.
        let jump = b
            .frequency_hz
            .windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .fold(0.0, f64::max);
        assert!(jump < 2.0, "branch {} jumps {jump} Hz", b.index);
        assert!(b.whirl_at.iter().all(|w| *w == b.whirl));
    }
    assert_eq!(b5.whirl, Whirl::Forward);
    assert_eq!(b6.whirl, Whirl::Backward);
}

#[test]
fn the_banded_basis_of_a_large_model_matches_the_full_solve() {
    // 100 elements (404 DOFs): past the dense limit, so the basis comes from subspace
    // iteration and is projected on the bands; the full solve takes every mode, dense.
    let model = reference_rotor().remeshed(&[100]).unwrap();
    let banded = assemble_banded(&model, Bearings::Linearised);
    assert!(!solves_dense(
        banded.dofs(),
        CampbellOptions::default_basis(8)
    ));
    let speeds = speeds(800.0, 5);
    let mut options = CampbellOptions::new(speeds.clone());
    let fast = campbell(&banded, &options, None).unwrap();
    options.basis_size = None;
    let full = campbell(&banded, &options, None).unwrap();
    assert_eq!(full.basis_size, 404);
    for (a, b) in fast.branches.iter().zip(&full.branches) {
        assert_eq!(a.whirl, b.whirl);
        for (x, y) in a.frequency_hz.iter().zip(&b.frequency_hz) {
            // The default basis' truncation error, as on the 20-element rotors below
            // (measured there: at most 9e-5).
            assert!((x - y).abs() / y < 2e-4, "branch {}: {x} vs {y}", a.index);
        }
    }
}

#[test]
fn truncated_basis_matches_the_full_solve() {
    for text in [
        whirl::examples::REFERENCE_ROTOR,
        whirl::examples::REFERENCE_ROTOR_SOFT,
    ] {
        let sys = system(text);
        let fast = run(&sys, 800.0, 41, Some(CampbellOptions::default_basis(8)));
        let full = run(&sys, 800.0, 41, None);
        assert_eq!(full.basis_size, 84);
        for (a, b) in fast.branches.iter().zip(&full.branches) {
            assert_eq!(a.whirl, b.whirl);
            for (x, y) in a.frequency_hz.iter().zip(&b.frequency_hz) {
                // Measured: at most 9e-5 on the reference rotors (the highest branch).
                assert!((x - y).abs() / y < 2e-4, "branch {}: {x} vs {y}", a.index);
            }
        }
    }
}

#[test]
fn first_critical_speeds_of_the_reference_rotor() {
    let c = run(
        &system(whirl::examples::REFERENCE_ROTOR),
        800.0,
        161,
        Some(24),
    );
    let forward: Vec<f64> = c
        .critical_speeds
        .iter()
        .filter(|s| s.whirl == Whirl::Forward && s.order == 1.0)
        .map(|s| s.speed_hz)
        .collect();
    // The 1X line crosses the first forward branch just above its 49.82 Hz rest value.
    assert!((forward[0] - 49.85).abs() < 0.02, "{forward:?}");
    // The second forward branch rises from 254 Hz; it meets 1X below 300 Hz.
    assert!(forward[1] > 254.0 && forward[1] < 300.0, "{forward:?}");
    // The excitation line's frequency equals the crossing speed.
    for s in &c.critical_speeds {
        assert!((s.frequency_hz - s.speed_hz * s.order).abs() < 1e-9);
    }
}

#[test]
fn damping_ratio_of_the_first_modes_is_the_rayleigh_value() {
    // alpha = 10.5, beta = 2.1e-5 give about 2 % at the first mode; the bearings, which carry
    // no Rayleigh damping, lower the modal value a little.
    let c = run(&system(whirl::examples::REFERENCE_ROTOR), 10.0, 2, Some(24));
    let zeta = c.branches[0].damping_ratio[0];
    assert!(zeta > 0.015 && zeta < 0.021, "{zeta}");
}

#[test]
fn damping_scale_multiplies_every_modal_damping_ratio() {
    // C = s (alpha M + beta K): each mode's ratio is, to first order in C, phi^T C phi /
    // (2 w) and so s times the unscaled one. Rayleigh damping on the shaft only (the
    // bearings carry none) makes C slightly non-proportional, and the damped modes deviate
    // from linear in s by O(zeta^2), below 1e-3 relative at 5 %.
    let base = whirl::examples::REFERENCE_ROTOR;
    let scaled = base.replace("beta = 2.1e-5", "beta = 2.1e-5\nscale = 2.5");
    assert_ne!(base, scaled);
    let (c1, c2) = (
        run(&system(base), 10.0, 2, Some(24)),
        run(&system(&scaled), 10.0, 2, Some(24)),
    );
    for (b1, b2) in c1.branches.iter().zip(&c2.branches).take(4) {
        let ratio = b2.damping_ratio[0] / b1.damping_ratio[0];
        assert!((ratio - 2.5).abs() < 2.5e-3, "{ratio}");
    }
    let refused = base.replace("beta = 2.1e-5", "beta = 2.1e-5\nscale = 0");
    let message = Model::from_toml_str(&refused, None)
        .unwrap_err()
        .to_string();
    assert!(message.contains("damping.scale"), "{message}");
}
