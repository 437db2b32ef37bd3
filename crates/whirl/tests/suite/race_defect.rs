//! A spall on a race shows in the simulated spectrum at its characteristic frequency: an
//! outer-race spall in the load zone at BPFO, an inner-race one at BPFI, each within one bin
//! and well above the healthy bearing's line there.

use std::f64::consts::PI;

use whirl::bearing::{characteristic_frequencies, ContactLaw};
use whirl::model::{Model, RaceDefect, Ring};
use whirl::post::{amplitude_spectrum_with, SpectralPeak, SpectrumOptions, Window};
use whirl::system::SpeedProfile;
use whirl::time::{peak_near, simulate, stable_step, Initial, Method, SimulationOptions};

use crate::common::reference_rotor;

/// Spin speed, Hz: the weight (171 N per bearing) outweighs the unbalance 27 times, so the
/// load zone stays at the bottom. BPFO = 73.0 Hz, BPFI = 87.0 Hz, neither within 3 Hz of a
/// multiple of the spin speed.
const SPEED_HZ: f64 = 20.0;
/// Simulated and settling time, s: the modes near 50 Hz (2 % damping) decay to 2e-3 of
/// their start in the first second; the settled second gives bins of 1 Hz.
const DURATION: f64 = 2.0;
const SETTLE: f64 = 1.0;
/// Fixed-interface modes of the Craig-Bampton model, as in the other roller runs.
const MODES: usize = 12;
/// The spall: 10 um deep over 10 degrees. The bottom roller presses about 1.7 um under the
/// weight, so the spall unloads it as it passes; 10 degrees take about 80 steps at 20 Hz.
const DEPTH: f64 = 10e-6;
const WIDTH_DEG: f64 = 10.0;

/// The vertical spectrum of bearing 0's node in the settled part, and the peak within one
/// bin of `frequency_hz` if there is one (peaks are refined between bins), with the bin.
fn peak(model: &Model, frequency_hz: f64) -> (Option<SpectralPeak>, f64) {
    let step = 0.9 * stable_step(model, Some(MODES), ContactLaw::Hertz).unwrap();
    let node = model.roller_bearings[0].station.node;
    let options = SimulationOptions {
        speed: SpeedProfile::Constant(2.0 * PI * SPEED_HZ),
        duration: DURATION,
        step: Some(step),
        method: Method::CentralDifference,
        reduction: Some(MODES),
        settle: Some(SETTLE),
        nodes: Some(vec![node]),
        initial: Initial::StaticEquilibrium,
        divergence_bound: 0.01,
        contact: Some(ContactLaw::Hertz),
        record_every: Some(1),
        record_rollers: false,
        progress: None,
    };
    let r = simulate(model, &options).unwrap();
    let channel = r
        .channels
        .iter()
        .find(|c| c.name == format!("n{node}.uy"))
        .unwrap();
    let x = &channel.values[r.settled_start()..];
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    let x: Vec<f64> = x.iter().map(|v| v - mean).collect();
    let spectrum = amplitude_spectrum_with(
        &x,
        1.0 / r.sample_interval(),
        SpectrumOptions::window(Window::FlatTop),
    )
    .unwrap();
    let found = peak_near(&spectrum, frequency_hz, 1.0, SPEED_HZ);
    (found, spectrum.resolution_hz)
}

fn with_spall(ring: Ring) -> Model {
    let mut model = reference_rotor();
    model.roller_bearings[0].defects.push(RaceDefect {
        ring,
        // The bottom, where the weight loads the rollers (the inner ring carries it there
        // once per turn).
        angle: -PI / 2.0,
        width: WIDTH_DEG.to_radians(),
        depth: DEPTH,
    });
    model
}

/// The spall's line within one bin of `frequency_hz`, and its ratio to the healthy
/// bearing's line there (infinite where the healthy spectrum has no peak there).
fn check(ring: Ring, frequency_hz: f64) -> f64 {
    let healthy = peak(&reference_rotor(), frequency_hz)
        .0
        .map_or(0.0, |p| p.amplitude);
    let (spalled, bin) = peak(&with_spall(ring), frequency_hz);
    let spalled = spalled.expect("no line within one bin");
    let ratio = spalled.amplitude / healthy;
    eprintln!(
        "{ring:?}: predicted {frequency_hz:.3} Hz, peak {:.3} Hz (bin {bin:.3} Hz), {:.3e} m \
         against {:.3e} m healthy ({ratio:.1}x)",
        spalled.frequency_hz, spalled.amplitude, healthy
    );
    assert!((spalled.frequency_hz - frequency_hz).abs() <= bin);
    ratio
}

#[test]
fn an_outer_race_spall_shows_at_bpfo_and_an_inner_race_one_at_bpfi() {
    let bearing = &reference_rotor().roller_bearings[0];
    let f = characteristic_frequencies(bearing, SPEED_HZ);
    // BPFO is also the healthy bearing's varying compliance, so the spall must raise it
    // clearly; twice is far beyond the run-to-run change of a deterministic simulation.
    let outer = check(Ring::Outer, f.bpfo);
    let inner = check(Ring::Inner, f.bpfi);
    assert!(outer > 2.0 && inner > 2.0);
}

#[test]
fn a_bad_defect_or_waviness_form_is_refused_with_the_field_named() {
    // Appended to the file, the tables belong to its last roller bearing.
    for (table, field) in [
        (
            "[[roller_bearing.defect]]\nring = \"outer\"\nwidth = 0\ndepth = \"5 um\"\n",
            "roller_bearing[1].defect[0].width",
        ),
        (
            "[[roller_bearing.defect]]\nring = \"outer\"\nwidth = 360\ndepth = \"5 um\"\n",
            "roller_bearing[1].defect[0].width",
        ),
        (
            "[[roller_bearing.defect]]\nring = \"outer\"\nwidth = 4\ndepth = \"-5 um\"\n",
            "roller_bearing[1].defect[0].depth",
        ),
        (
            "[[roller_bearing.defect]]\nring = \"cage\"\nwidth = 4\ndepth = \"5 um\"\n",
            "roller_bearing[1].defect[0].ring",
        ),
        (
            "[[roller_bearing.waviness]]\nring = \"outer\"\norder = 5\namplitude = \"1 um\"\n\
             form = \"fixed\"\n",
            "roller_bearing[1].waviness[0].form",
        ),
    ] {
        let text = format!("{}\n{table}", whirl::examples::REFERENCE_ROTOR);
        let message = Model::from_toml_str(&text, None).unwrap_err().to_string();
        assert!(message.contains(field), "{table}: {message}");
    }
    let good = "[[roller_bearing.defect]]\nring = \"inner\"\nangle = 270\nwidth = 4\n\
                depth = \"5 um\"\n";
    let model = Model::from_toml_str(
        &format!("{}\n{good}", whirl::examples::REFERENCE_ROTOR),
        None,
    )
    .unwrap();
    let d = &model.roller_bearings[1].defects[0];
    assert_eq!((d.ring, d.depth), (Ring::Inner, 5e-6));
}
