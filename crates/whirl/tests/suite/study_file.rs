//! Study files: parameter edits by path, sweep expansion and validation messages.

use whirl::model::{Clearance, Model};
use whirl::study::Study;
use whirl::units::{parse_range, Dimension};

use crate::common::{example_path, reference_rotor_path};

/// A study of the reference rotor whose body (after `model = ...`) is `body`.
fn study(body: &str) -> whirl::Result<Study> {
    let text = format!(
        "model = {:?}\n{body}",
        reference_rotor_path().display().to_string()
    );
    Study::from_toml_str(&text, std::path::Path::new("study.toml"))
}

fn base() -> Model {
    Model::from_file(&reference_rotor_path()).unwrap()
}

fn error(body: &str) -> String {
    study(body).unwrap_err().to_string()
}

#[test]
fn a_clearance_sweep_changes_exactly_the_clearances() {
    let s = study(
        "[[sweep]]\nparameter = \"roller_bearing[*].clearance\"\n\
         values = [\"20 um\", \"60 um\", 1.2e-4, \"90 um\"]\nfit = \"cubic\"\n\
         [[sweep]]\nparameter = \"roller_bearing[*].clearance\"\nvalues = [\"60 um\", \"80 um\"]\n",
    )
    .unwrap();
    // 20, 60, 120, 90 and 80 um: the 60 um point of both sweeps is one point.
    assert_eq!(s.points.len(), 5);
    assert_eq!(s.sweeps[0].points, [0, 1, 2, 3]);
    assert_eq!(s.sweeps[1].points, [1, 4]);
    let si: Vec<f64> = s.sweeps[0].values.iter().map(|v| v.si.unwrap()).collect();
    assert_eq!(si, [2e-5, 6e-5, 1.2e-4, 9e-5]);
    assert_eq!(s.sweeps[0].fit_degree, Some(3));
    for (k, want) in [(1, 6e-5), (2, 1.2e-4)] {
        let mut expected = base();
        for b in &mut expected.roller_bearings {
            b.clearance = Clearance::Constant(want);
        }
        // Everything else is the base model, bit for bit.
        assert_eq!(s.points[k].model, expected);
    }
    // The reference rotor's own clearance is 20 um: that point is the base model.
    assert_eq!(s.points[0].model, base());
}

#[test]
fn selectors_pick_one_bearing_by_number_or_name() {
    let s = study(
        "[[sweep]]\nparameter = 'roller_bearing[\"bearing B\"].rollers'\nvalues = [16]\n\
         [[sweep]]\nparameter = \"roller_bearing[0].rollers\"\nvalues = [32]\n",
    )
    .unwrap();
    let rollers = |p: usize| -> Vec<usize> {
        s.points[p]
            .model
            .roller_bearings
            .iter()
            .map(|b| b.rollers)
            .collect()
    };
    assert_eq!(rollers(0), [8, 16]);
    assert_eq!(rollers(1), [32, 8]);
}

#[test]
fn set_fixes_other_parameters_and_cascade_settings_can_be_swept() {
    let s = study(
        "[cascade]\nspeeds = \"1:750Hz:150\"\ncontact = \"hertz\"\nstep = \"5 us\"\n\
         [[sweep]]\nparameter = \"cascade.contact\"\nvalues = [\"hertz\", \"lagrange\"]\n\
         set = { \"unbalance[0].eccentricity\" = \"10 um\" }\n",
    )
    .unwrap();
    assert_eq!(s.points.len(), 2);
    for p in &s.points {
        // 10 um on the 10 kg disk.
        assert!((p.model.unbalances[0].mass_radius - 1e-4).abs() < 1e-15);
        assert_eq!(p.cascade.speeds.as_ref().map(Vec::len), Some(150));
        assert_eq!(p.cascade.step, Some(5e-6));
    }
    assert_eq!(
        s.points[1].cascade.contact,
        Some(whirl::bearing::ContactLaw::Lagrange)
    );
    assert_eq!(s.sweeps[0].values[1].si, None);
    assert_eq!(
        s.points[1].label(),
        "eccentricity = 10 um; contact = lagrange"
    );
}

#[test]
fn a_bad_value_gets_the_model_files_own_message_at_the_study_value() {
    let e = error("[[sweep]]\nparameter = \"roller_bearing[*].rollers\"\nvalues = [8, 0]\n");
    assert!(
        e.starts_with("study.toml:4:14: `sweep[0].values[1]`"),
        "{e}"
    );
    assert!(e.contains("makes an invalid model"), "{e}");
    // The model's validation names its field and its range.
    assert!(e.contains("`roller_bearing[0].rollers`"), "{e}");
    assert!(e.contains("got 0"), "{e}");
}

#[test]
fn a_bad_path_or_field_is_named_with_the_fix() {
    let e = error("[[sweep]]\nparameter = \"roller_bearing.clearance\"\nvalues = [1e-5]\n");
    assert!(e.contains("`roller_bearing[*]`"), "{e}");
    let e = error("[[sweep]]\nparameter = \"bearings.clearance\"\nvalues = [1e-5]\n");
    assert!(e.contains("the file has no `bearings`"), "{e}");
    assert!(e.contains("roller_bearing"), "{e}");
    let e = error("[[sweep]]\nparameter = \"roller_bearing[*].clearence\"\nvalues = [1e-5]\n");
    assert!(e.contains("unknown field `clearence`"), "{e}");
    let e = error("[[sweep]]\nparameter = \"cascade.contact\"\nvalues = [\"coulomb\"]\n");
    assert!(e.contains("hertz, lagrange, forcing, linear"), "{e}");
    let e = error("[[sweep]]\nparamter = \"x\"\n");
    assert!(e.contains("docs/study-file.md"), "{e}");
    let e = error("[[sweep]]\nparameter = \"cascade.contact\"\nvalues = [\"hertz\", \"lagrange\"]\nfit = \"linear\"\n");
    assert!(e.contains("not a number"), "{e}");
    assert!(error("").contains("no sweep"));
    let e = error(
        "[cascade]\nsettle = \"-1 s\"\n[[sweep]]\nparameter = \"damping.alpha\"\nvalues = [1]\n",
    );
    assert!(e.contains("`cascade.settle`"), "{e}");
}

#[test]
fn the_shipped_thesis_study_is_valid_and_shares_its_base_points() {
    let path = example_path("thesis_chapter5_study.toml");
    let s = Study::from_file(&path).unwrap();
    assert_eq!(s.sweeps.len(), 11);
    // Figs. 5.1-5.6 share their points down to 14 distinct Hertz cascades (figs. 5.2 and
    // 5.5 start from rest, another cascade setting: 5.5's 16 rollers is 5.2's 20 um, its 8
    // and 32 are new), figs. 5.7-5.9 share theirs down to 7 Lagrange ones, fig. 5.10 adds
    // the 9 clearances not already there, and the onset sweep 12 more (another NSV
    // threshold is another cascade setting).
    assert_eq!(s.points.len(), 42);
}

#[test]
fn a_value_written_in_other_units_is_the_same_point() {
    let s = study(
        "[[sweep]]\nparameter = \"roller_bearing[*].clearance\"\nvalues = [\"60 um\", 6e-5, \"6e-5 m\"]\n",
    )
    .unwrap();
    assert_eq!(s.points.len(), 1);
}

#[test]
fn a_study_without_speeds_takes_the_command_lines_default_speeds() {
    // One definition (whirl::nsv::default_speeds) serves the study, the command line and
    // Python: a point without speeds gets exactly that list ...
    let s = study("[[sweep]]\nparameter = \"roller_bearing[*].clearance\"\nvalues = [\"20 um\"]\n")
        .unwrap();
    let point = &s.points[0];
    assert_eq!(point.cascade.speeds, None);
    let study_speeds = whirl::study::point::cascade_options(point).unwrap().speeds;
    let default = whirl::nsv::default_speeds(&point.model).unwrap();
    assert_eq!(study_speeds, default);
    // ... which is the command line's range over [operating] (1 to 750 Hz), the one the
    // main-job numbers of docs/results.md rest on, to the bit.
    let range = parse_range("1Hz:750Hz:150", Dimension::AngularSpeed).unwrap();
    assert_eq!(default, range);
}

#[test]
fn default_speeds_start_above_rest_and_need_an_operating_range() {
    let mut m = base();
    let top = 2.0 * std::f64::consts::PI * 750.0;
    // A range from rest starts at top / 150: a cascade needs a running speed everywhere.
    m.operating = Some((0.0, top));
    let w = whirl::nsv::default_speeds(&m).unwrap();
    assert_eq!(w.len(), whirl::nsv::DEFAULT_SPEED_COUNT);
    assert_eq!(w[0], top / 150.0);
    assert!((w[149] - top).abs() <= 1e-12 * top);
    m.operating = None;
    let e = whirl::nsv::default_speeds(&m).unwrap_err().to_string();
    assert!(e.contains("`speeds`") && e.contains("[operating]"), "{e}");
    let s = study("[[sweep]]\nparameter = \"roller_bearing[*].clearance\"\nvalues = [\"20 um\"]\n")
        .unwrap();
    let mut point = s.points[0].clone();
    point.model.operating = None;
    let e = whirl::study::point::cascade_options(&point)
        .unwrap_err()
        .to_string();
    assert!(e.contains("`cascade.speeds`"), "{e}");
}

#[test]
fn the_studys_own_set_reaches_every_point_and_a_sweeps_set_overrides_it() {
    // The whole study at 2.5 times the reference rotor's damping; the second sweep also
    // scales it itself, and its own value wins (it is applied after the study's).
    let s = study(
        "set = { \"damping.scale\" = 2.5 }\n\
         [[sweep]]\nparameter = \"roller_bearing[*].clearance\"\nvalues = [\"20 um\", \"60 um\"]\n\
         [[sweep]]\nparameter = \"unbalance[0].eccentricity\"\nvalues = [\"10 um\"]\n\
         set = { \"damping.scale\" = 5 }\n",
    )
    .unwrap();
    let d = base().damping;
    for (k, scale) in [(0, 2.5), (1, 2.5), (2, 5.0)] {
        let got = s.points[k].model.damping;
        assert_eq!(
            (got.alpha, got.beta),
            (scale * d.alpha, scale * d.beta),
            "{k}"
        );
    }
    let e = error(
        "set = { \"damping.scael\" = 2 }\n[[sweep]]\nparameter = \"gravity\"\nvalues = [9]\n",
    );
    // The model's validation refuses the misspelt key and lists the right one, at `set`
    // (not at the sweep's first value, which it would otherwise meet first).
    assert!(
        e.contains("unknown field `scael`") && e.contains("`scale`"),
        "{e}"
    );
    assert!(e.contains(": `set`: ") && !e.contains("values[0]"), "{e}");
}

#[test]
fn the_cascade_table_reads_every_cascade_option_as_the_command_line_does() {
    // One reader for the study file and the Python keywords (CascadeRequest::set): an
    // option the table never listed before is read with its unit, into the same options
    // the command line's flags give.
    let s = study(
        "[cascade]\nrefine_budget = 5\nrefine_spacing = \"2 Hz\"\nwindow = \"flat-top\"\n\
         [[sweep]]\nparameter = \"roller_bearing[*].clearance\"\nvalues = [\"20 um\"]\n",
    )
    .unwrap();
    let o = whirl::study::point::cascade_options(&s.points[0]).unwrap();
    assert_eq!(o.refine.max_added, 5);
    assert_eq!(o.refine.min_spacing_hz, 2.0);
    assert_eq!(o.window, whirl::post::Window::FlatTop);
    // A name the cascade does not have is refused at its field, listing the options.
    let e = error(
        "[cascade]\nrefine_budgte = 5\n\
         [[sweep]]\nparameter = \"roller_bearing[*].clearance\"\nvalues = [\"20 um\"]\n",
    );
    assert!(e.contains("`cascade.refine_budgte`"), "{e}");
    assert!(e.contains("refine_budget"), "{e}");
}
