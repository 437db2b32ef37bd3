//! Running a study's points: resuming from the checkpoint folder, fits and ranking.
//! The cascades are replaced by a closed form of the clearance so that the study machinery
//! is checked on its own, exactly.

use std::cell::Cell;
use std::path::Path;

use whirl::study::results::{analyse, run_points, CascadeMap, NsvSummary, PointResult, Source};
use whirl::study::store::Store;
use whirl::study::{Point, Study};

use crate::common::reference_rotor_path;

/// Table 5.1 of the thesis in SI: delta_nsv(gamma) = P1 g^3 + P2 g^2 + P3 g + P4.
const TABLE_5_1: [f64; 4] = [-3.125e8, 7.162e4, -1.956, 4.296e-5];

fn table_5_1(gamma: f64) -> f64 {
    TABLE_5_1.iter().fold(0.0, |a, c| a * gamma + c)
}

fn study() -> Study {
    let model = reference_rotor_path();
    let text = format!(
        "model = {:?}\n\
         [[sweep]]\nname = \"clearance\"\nparameter = \"roller_bearing[*].clearance\"\n\
         values = [\"20 um\", \"40 um\", \"60 um\", \"80 um\", \"100 um\", \"120 um\"]\n\
         fit = \"cubic\"\n\
         [[sweep]]\nname = \"rollers\"\nparameter = \"roller_bearing[*].rollers\"\n\
         values = [8, 16, 32]\n",
        model.display().to_string()
    );
    Study::from_toml_str(&text, Path::new("study.toml")).unwrap()
}

/// A stand-in for a cascade: the mean NSV over the speed range (the default metric) is
/// table 5.1 at the point's clearance, less one per cent per roller beyond 8; the other
/// statistics are fixed fractions of it, the largest three times it.
fn fake_cascade(point: &Point) -> whirl::Result<PointResult> {
    let b = &point.model.roller_bearings[0];
    let mean = table_5_1(b.clearance.at_speed(0.0)) * (1.0 - 0.01 * (b.rollers - 8) as f64);
    Ok(PointResult {
        key: point.key.clone(),
        nsv: NsvSummary {
            largest: 3.0 * mean,
            median: 0.5 * mean,
            p90: 0.9 * mean,
            mean,
            largest_speed_hz: Some(300.0),
            largest_frequency_hz: Some(50.0),
            largest_class: Some("whip".into()),
            onset_speed_hz: Some(250.0),
            dominant_class: Some("whip".into()),
            largest_synchronous: 1e-4,
        },
        map: CascadeMap {
            speeds_hz: vec![100.0, 200.0],
            frequencies_hz: vec![0.0, 2.0],
            amplitude: vec![vec![Some(0.0), None], vec![Some(mean as f32); 2]],
        },
        wall_time_s: 0.0,
        resumed_speeds: 0,
    })
}

#[test]
fn a_failed_point_is_left_out_and_computed_again_by_the_next_run() {
    let s = study();
    // 6 clearances and 2 more roller counts (8 rollers at 20 um is shared).
    assert_eq!(s.points.len(), 8);
    let dir = std::env::temp_dir().join(format!("whirl-study-run-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let store = Store::open(&dir, &s.fingerprint, Path::new("study.toml"), false).unwrap();
    // The fourth point's cascade fails in the first run.
    let calls = Cell::new(0);
    let failing = |p: &Point| {
        calls.set(calls.get() + 1);
        if calls.get() == 4 {
            Err(whirl::Error::Interrupted("interrupted".into()))
        } else {
            fake_cascade(p)
        }
    };
    let first = run_points(&s, &store, failing, |_, _, _, _| {}).unwrap();
    // The failed point is reported and not saved; the study went on with the others.
    assert_eq!(first[3], Err("interrupted".to_string()));
    assert_eq!(store.finished(), 7);
    let partial = analyse(&s, &first);
    assert_eq!(partial.sweeps[0].largest_nsv[3], None);
    assert_eq!(partial.sweeps[0].metric_nsv[3], None);
    // Five clearances left for a cubic: it is still fitted, from them.
    assert!(partial.sweeps[0].fit.is_some());
    // The second run computes only the failed point, and resumes the seven saved.
    let computed = Cell::new(0);
    let mut resumed = 0;
    let counting = |p: &Point| {
        computed.set(computed.get() + 1);
        fake_cascade(p)
    };
    let results = run_points(&s, &store, counting, |_, _, source, _| {
        resumed += usize::from(source == Source::Resumed)
    })
    .unwrap();
    assert_eq!((computed.get(), resumed), (1, 7));
    // Results saved and read back are the same numbers as computed ones.
    for (p, r) in s.points.iter().zip(&results) {
        assert_eq!(r.as_ref().unwrap(), &fake_cascade(p).unwrap());
    }

    let outcome = analyse(&s, &results);
    // The clearance sweep samples table 5.1 exactly: the cubic fit gives it back (round-off
    // of a problem whose columns span 15 decades, hence 1e-6 relative) with R^2 = 1.
    let fit = outcome.sweeps[0].fit.as_ref().unwrap();
    for (got, want) in fit.coefficients.iter().zip(TABLE_5_1) {
        assert!((got / want - 1.0).abs() < 1e-6, "{got} vs {want}");
    }
    assert!((fit.r_squared - 1.0).abs() < 1e-9);
    // Clearance ranks first: table 5.1 grows about tenfold from 20 to 120 um, while the
    // roller count changes the NSV by 24 % at most.
    assert_eq!(outcome.ranking[0].sweep, "clearance");
    let rollers = &outcome.ranking[1];
    assert!((rollers.relative_change.unwrap() - 0.24 / 0.76).abs() < 1e-12);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_point_whose_every_speed_diverged_is_a_failed_point_with_its_reason() {
    // A 4 mm eccentricity throws the disk into the rings; with the step just under the
    // limit of the contacts at rest, every speed diverges (as the lone cascade does).
    let text = format!(
        "model = {:?}\n\
         [cascade]\nspeeds = \"300:400Hz:2\"\nstep = \"3.6e-5 s\"\nrefine = false\n\
         [[sweep]]\nparameter = \"unbalance[0].eccentricity\"\nvalues = [\"4 mm\", \"8 mm\"]\n",
        reference_rotor_path().display().to_string()
    );
    let s = Study::from_toml_str(&text, Path::new("study.toml")).unwrap();
    let dir = std::env::temp_dir().join(format!("whirl-study-diverged-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let store = Store::open(&dir, &s.fingerprint, Path::new("study.toml"), false).unwrap();
    let results = run_points(
        &s,
        &store,
        |p| whirl::study::point::compute(p, None, None),
        |_, _, _, _| {},
    )
    .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(results.len(), 2);
    for outcome in &results {
        let why = outcome.as_ref().unwrap_err();
        assert!(
            why.contains("diverged at every one of the 2 speeds"),
            "{why}"
        );
    }
    // Nothing is left to fit or rank: no sweep is ranked "first" on diverged points.
    assert!(analyse(&s, &results).ranking.is_empty());
}
