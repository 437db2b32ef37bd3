//! The NSV map: each value's first loss of stability is the single sweep's, its bands
//! agree with the sweep's bifurcations, and bad requests name what is wrong.

use std::f64::consts::TAU;

use whirl::hbm::{sweep, BifurcationKind, SweepSettings};
use whirl::map::{
    distributed_map, map, map_value, map_with, Clearance, Edge, Growth, MapRequest, Parallelism,
    UnstableBand, ValueRun,
};
use whirl::model::Model;
use whirl::units::rad_s_to_hz as hz;

/// The reference rotor through its first resonance (1-60 Hz), where the 20 and 60 um
/// branches lose stability (near 45 and 40 Hz), on a cheap discretisation: H = 2 on a
/// 12-mode Craig-Bampton model.
fn request(values: &[&str]) -> MapRequest {
    MapRequest {
        model_text: whirl::examples::REFERENCE_ROTOR.to_string(),
        model_file: None,
        parameter: None,
        values: values.iter().map(|v| v.to_string()).collect(),
        from: TAU,
        to: TAU * 60.0,
        settings: SweepSettings {
            harmonics: Some(2),
            reduction: Some(12),
            ..SweepSettings::default()
        },
        clear_below: Some(TAU * 30.0),
        check: Vec::new(),
        check_level_m: None,
        confirm: false,
    }
}

fn reference(clearance: &str) -> Model {
    let text = whirl::examples::REFERENCE_ROTOR.replace(
        "clearance = \"20 um\"",
        &format!("clearance = \"{clearance}\""),
    );
    Model::from_toml_str(&text, None).unwrap()
}

#[test]
fn first_loss_of_stability_is_the_single_sweeps_at_each_value() {
    let request = request(&["20 um", "60um"]);
    let report = map(&request).unwrap();
    for (entry, clearance) in report.entries.iter().zip(["20 um", "60 um"]) {
        let single = sweep(&reference(clearance), &request.sweep_options()).unwrap();
        let expected = single.branch.first_stability_loss().map(|b| b.frequency);
        let got = entry.first_loss().map(|b| b.frequency);
        // The same code path on the same model: a sweep gives the same bits on any number
        // of threads, so equality is exact.
        assert_eq!(got, expected, "{clearance}");
        assert!(
            expected.is_some(),
            "{clearance}: the branch loses stability"
        );
        // The first band opens at the first loss.
        assert_eq!(entry.run.bands.first().map(|b| b.opens_hz), got.map(hz));
        // Each band's edges are the sweep's bifurcations, none re-located.
        let speeds: Vec<f64> = single
            .branch
            .bifurcations
            .iter()
            .map(|b| hz(b.frequency))
            .collect();
        for band in &entry.run.bands {
            assert!(speeds.contains(&band.opens_hz), "{clearance}: {band:?}");
            check_growing(band);
        }
        // Below 30 Hz the orbit is stable at both clearances (first losses near 40-45 Hz).
        assert_eq!(entry.clearance(TAU * 30.0), Clearance::Clear, "{clearance}");
    }
    let query = report.clear_below(TAU * 30.0);
    assert_eq!(query.largest_clear.as_deref(), Some("60um"));
    assert_eq!(query.smallest_clear.as_deref(), Some("20 um"));
}

#[test]
fn both_ways_of_spreading_the_sweeps_give_the_same_map() {
    let request = request(&["60 um"]);
    let a = map_with(&request, Parallelism::Values, None).unwrap();
    let b = map_with(&request, Parallelism::WithinSweeps, None).unwrap();
    assert_eq!(a.entries[0].run.bands, b.entries[0].run.bands);
}

#[test]
fn a_map_whose_values_ran_elsewhere_is_the_local_map() {
    // Each value's run crosses to and from the runner as JSON, as it does to a cluster's
    // worker: the report must be the local one to the bit (serde_json's float_roundtrip
    // reads back every f64 exactly).
    let request = request(&["20 um", "60um"]);
    let local = map(&request).unwrap();
    let runner = |indices: &[usize], done: &mut dyn FnMut(usize, ValueRun) -> whirl::Result<()>| {
        for &j in indices.iter().rev() {
            let json = serde_json::to_string(&map_value(&request, j)?).unwrap();
            done(j, serde_json::from_str(&json).unwrap())?;
        }
        Ok(())
    };
    let remote = distributed_map(&request, None, &runner).unwrap();
    for (a, b) in local.entries.iter().zip(&remote.entries) {
        let cost = |r: &ValueRun| ValueRun {
            cpu_s: None,
            wall_s: 0.0,
            ..r.clone()
        };
        assert_eq!(cost(&a.run), cost(&b.run), "{}", a.value.text);
    }
    // A runner that leaves a value out is an error, not a map with a hole.
    let lazy = |_: &[usize], _: &mut dyn FnMut(usize, ValueRun) -> whirl::Result<()>| Ok(());
    let message = distributed_map(&request, None, &lazy)
        .unwrap_err()
        .to_string();
    assert!(message.contains("left value 0 out"), "{message}");
}

#[test]
fn an_unknown_parameter_names_itself() {
    let mut r = request(&["20 um"]);
    r.parameter = Some("roller_bearing[*].clearence".into());
    let message = map(&r).unwrap_err().to_string();
    assert!(message.contains("clearence"), "{message}");
    r.parameter = Some("roller_bearings[*].clearance".into());
    let message = map(&r).unwrap_err().to_string();
    assert!(message.contains("roller_bearings"), "{message}");
}

#[test]
fn no_values_and_refused_values_are_named() {
    let message = map(&request(&[])).unwrap_err().to_string();
    assert!(message.contains("1 to"), "{message}");
    let err = map(&request(&["20 um", "-5 um"])).unwrap_err();
    let whirl::Error::Input(input) = &err else {
        panic!("{err}")
    };
    assert_eq!(input.field.as_deref(), Some("values[1]"));
    assert!(input.message.contains("-5 um"), "{}", input.message);
}

#[test]
fn the_varying_compliance_resonance_is_a_line_that_explains_the_cascade_below_the_first_loss() {
    // Below 30 Hz the 20 um orbit is stable, yet the cascade shows its largest NSV of the
    // low speeds (about 20 um at 49.8 Hz near 13.6 Hz running speed): N_b w_c meeting the
    // first mode, which the averaged linearisation of the orbit puts near 50 Hz. The map
    // must draw that line and the check must count the speed as explained.
    let mut request = request(&["20 um"]);
    request.to = TAU * 30.0;
    request.clear_below = None;
    request.check = vec!["20 um".into()];
    let report = map(&request).unwrap();
    let entry = &report.entries[0];
    assert!(entry.run.bands.is_empty(), "{:?}", entry.run.bands);
    let line = entry
        .run
        .lines
        .iter()
        .find(|l| l.excitation.name() == "1x varying compliance" && l.on_stable_orbit)
        .expect("a varying-compliance line");
    // The first mode on the orbit: 45-55 Hz (49.5 Hz on linear bearings), met where
    // N_b w_c (about 3.66 w: 8 rollers, the cage at 0.46 of the speed) equals it: 12.5-15.3 Hz.
    assert!((45.0..55.0).contains(&line.response_hz), "{line:?}");
    assert!((12.5..15.3).contains(&line.speed_hz), "{line:?}");
    let check = &report.checks[0];
    assert!(check.nsv_speeds >= 1, "{check:?}");
    // Every NSV of 10 um here is the resonance on the line: all explained, and the speeds
    // the map calls quiet are quiet but for at most a tenth.
    assert_eq!(check.explained, check.nsv_speeds, "{check:?}");
    assert!(check.quiet_fraction() >= 0.9, "{check:?}");
}

#[test]
fn the_design_querys_answer_is_tried_by_a_cascade() {
    // Below 30 Hz both clearances keep the orbit stable; the larger, 60 um, is the answer,
    // and its cascade up to 30 Hz passes through the varying-compliance resonance (about 63
    // um at 13.6 Hz in the default 60 um cascade): stable is not quiet, and the
    // confirmation says so at 10 um.
    let mut request = request(&["20 um", "60um"]);
    request.to = TAU * 30.0;
    request.confirm = true;
    let report = map(&request).unwrap();
    let c = report.confirmation.as_ref().expect("a value is clear");
    assert_eq!(c.value, "60um");
    assert!(c.speeds >= 100, "{c:?}");
    let at = c.largest_at_hz.unwrap();
    assert!((11.0..16.0).contains(&at), "{c:?}");
    assert!(c.largest_nsv_m > 1e-5 && !c.confirmed, "{c:?}");
    // Without a query there is nothing to confirm: refused, naming the field.
    request.clear_below = None;
    let e = map(&request).unwrap_err().to_string();
    assert!(e.contains("confirm"), "{e}");
}

/// What grows inside `band` lies within it; a real negative multiplier's component is at
/// half the speed (its angle is pi), and a band opened by period doubling has one.
fn check_growing(band: &UnstableBand) {
    let [lo, hi] = band.span_hz;
    let within = |x: f64, a: f64, b: f64| a - 1e-9 * b <= x && x <= b + 1e-9 * b;
    for g in &band.growing {
        for s in g.speeds_hz {
            assert!(within(s, lo, hi), "{band:?}");
        }
        if g.growth == Growth::HalfSpeed {
            for f in g.frequency_hz {
                assert!(within(f, 0.5 * lo, 0.5 * hi), "{band:?}");
            }
        }
    }
    let opens_by_doubling = matches!(
        band.opens,
        Edge::Bifurcation {
            bifurcation: BifurcationKind::PeriodDoubling,
            ..
        }
    );
    if opens_by_doubling {
        assert!(
            band.growing.iter().any(|g| g.growth == Growth::HalfSpeed),
            "{band:?}"
        );
    }
}
