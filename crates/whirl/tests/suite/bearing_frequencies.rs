//! The characteristic frequencies of the reference bearing against values worked by hand.

use whirl::bearing::{characteristic_frequencies, RollerGeometry};

use crate::common::reference_bearing;

// Worked by hand for N_b = 8, d = 6.1 mm, D_p = 69.6 mm: c = (1 - 6.1/69.6)/2 = 0.456178161,
// BPFO = 8c, BPFI = 8(1 - c), BSF = D_p/(2d) (1 - (d/D_p)^2) (the textbook form, which
// the library reaches through the cage ratio instead). The values are printed to 12
// digits and the library's arithmetic is a few operations deep, so 1e-11 relative
// separates a wrong formula from round-off.
const FTF: f64 = 0.456_178_160_920;
const BPFO: f64 = 3.649_425_287_356;
const BPFI: f64 = 4.350_574_712_644;
const BSF: f64 = 5.661_096_193_706;
const RELATIVE: f64 = 1e-11;

fn close(got: f64, want: f64) -> bool {
    (got - want).abs() <= RELATIVE * want.abs()
}

#[test]
fn the_reference_bearing_frequencies_match_the_hand_values() {
    let f = characteristic_frequencies(&reference_bearing(), 1.0);
    assert!(close(f.ftf, FTF), "FTF {}", f.ftf);
    assert!(close(f.bpfo, BPFO), "BPFO {}", f.bpfo);
    assert!(close(f.bpfi, BPFI), "BPFI {}", f.bpfi);
    assert!(close(f.bsf, BSF), "BSF {}", f.bsf);
    assert!(close(f.varying_compliance, BPFO));
}

#[test]
fn the_frequencies_scale_with_speed_and_agree_with_the_cage_kinematics() {
    let bearing = reference_bearing();
    let geometry = RollerGeometry::new(&bearing);
    let speed = 2.0 * std::f64::consts::PI * 50.0;
    let f = characteristic_frequencies(&bearing, speed);
    assert!(close(f.ftf, geometry.cage_speed(speed)));
    assert!(close(f.bpfo, geometry.varying_compliance_frequency(speed)));
    // Outer and inner passes add up to N_b times the spin: the rollers pass the inner race
    // at the spin speed less the cage's.
    assert!(close(f.bpfo + f.bpfi, 8.0 * speed));
}

#[test]
fn a_measured_cage_ratio_moves_every_line() {
    let mut bearing = reference_bearing();
    bearing.cage_speed_ratio = 0.44;
    let f = characteristic_frequencies(&bearing, 1.0);
    assert!(close(f.ftf, 0.44));
    assert!(close(f.bpfo, 8.0 * 0.44));
    assert!(close(f.bpfi, 8.0 * 0.56));
    // Rolling without slip on the outer raceway (diameter D_p + d) at the cage's speed.
    assert!(close(f.bsf, 0.44 * (0.0696 + 0.0061) / 0.0061));
}
