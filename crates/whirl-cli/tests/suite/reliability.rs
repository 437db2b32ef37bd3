//! Runs that meet each other, get interrupted or fail part-way: one run per
//! output folder, Ctrl-C keeps the checkpoint and leaves no temporary folder, the next run
//! cleans what a killed one left, and the exit status says whether anything was computed.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::reference::{reference_rotor_path, reference_rotor_text_meshed};

fn whirl() -> Command {
    Command::new(env!("CARGO_BIN_EXE_whirl"))
}

/// A cascade of 40 speeds: long enough (a few seconds) to be met or interrupted.
fn cascade(out: &Path) -> Command {
    let mut c = whirl();
    c.arg("cascade")
        .arg(reference_rotor_path())
        .args(["--speeds", "1:750Hz:40", "--out"])
        .arg(out);
    c
}

/// Waits until the cascade's checkpoint under `dir` (`cascade.partial/<key>/`) holds `name`.
fn wait_for_checkpoint(dir: &Path, name: &str) {
    let root = dir.join("cascade.partial");
    let start = Instant::now();
    let found = || {
        std::fs::read_dir(&root)
            .map(|entries| entries.flatten().any(|e| e.path().join(name).exists()))
            .unwrap_or(false)
    };
    while !found() {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "{name} never appeared under {root:?}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Names in `dir` that start with a dot (temporary folders, locks).
fn hidden(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().to_string())
        .filter(|n| n.starts_with('.'))
        .collect()
}

/// Sends Ctrl-C (SIGINT) to `run` and waits for it: it must stop with exit status 130.
/// Returns what it wrote on stderr.
fn ctrl_c(run: std::process::Child) -> String {
    let sent = Command::new("kill")
        .args(["-INT", &run.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let stopped = run.wait_with_output().unwrap();
    let message = text(&stopped);
    assert_eq!(stopped.status.code(), Some(130), "{message}");
    message
}

fn text(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).to_string()
}

#[test]
fn a_second_run_on_the_same_folder_is_refused_and_the_first_is_unharmed() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("cascade");
    let first = cascade(&out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The checkpoint's manifest is written once the first run holds the folder.
    wait_for_checkpoint(tmp.path(), "manifest.json");
    let second = cascade(&out).output().unwrap();
    let refused = text(&second);
    assert_eq!(second.status.code(), Some(1), "{refused}");
    assert!(
        refused.contains(&format!("another whirl run (process {})", first.id())),
        "{refused}"
    );
    assert!(refused.contains("is writing"), "{refused}");
    let first = first.wait_with_output().unwrap();
    assert!(first.status.success(), "{}", text(&first));
    // The first run's result is whole, and nothing is left beside it.
    same_as_uninterrupted(&out, tmp.path());
}

/// Checks that the cascade in `out` is an uninterrupted run's, bit for bit, and that
/// nothing hidden is left in `dir`.
fn same_as_uninterrupted(out: &Path, dir: &Path) {
    let reference = dir.join("uninterrupted");
    let ok = cascade(&reference).output().unwrap();
    assert!(ok.status.success(), "{}", text(&ok));
    for file in ["cascade.csv", "nsv.csv"] {
        assert_eq!(
            std::fs::read(out.join(file)).unwrap(),
            std::fs::read(reference.join(file)).unwrap(),
            "{file}"
        );
    }
    assert_eq!(hidden(dir), Vec::<String>::new(), "hidden files left");
}

#[test]
fn ctrl_c_keeps_the_checkpoint_and_a_rerun_ends_with_the_same_bytes() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("cascade");
    let run = cascade(&out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Interrupt once a few speeds are saved.
    wait_for_checkpoint(tmp.path(), "point-00002.json");
    let message = ctrl_c(run);
    assert!(
        message.contains("the cascade was stopped after"),
        "{message}"
    );
    assert!(!out.exists(), "an interrupted run writes no result");
    assert_eq!(
        hidden(tmp.path()),
        Vec::<String>::new(),
        "temporary folders left"
    );
    // The rerun computes the rest; the result is the uninterrupted run's, bit for bit.
    let resumed = cascade(&out).output().unwrap();
    assert!(resumed.status.success(), "{}", text(&resumed));
    same_as_uninterrupted(&out, tmp.path());
}

#[test]
fn leftovers_of_a_killed_run_are_removed_by_the_next() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("modal");
    // What `kill -9` leaves: a temporary folder, a set-aside old result, an unlocked lock.
    for leftover in [".modal.whirl-tmp-999999", ".modal.whirl-old-999999"] {
        std::fs::create_dir(tmp.path().join(leftover)).unwrap();
        std::fs::write(tmp.path().join(leftover).join("summary.json"), "{}").unwrap();
    }
    std::fs::write(tmp.path().join(".modal.whirl-lock"), "999999\n").unwrap();
    // A folder of another name is none of this run's business.
    std::fs::create_dir(tmp.path().join(".other.whirl-tmp-1")).unwrap();
    let run = whirl()
        .arg("modal")
        .arg(reference_rotor_path())
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", text(&run));
    assert_eq!(hidden(tmp.path()), [".other.whirl-tmp-1"]);
}

#[test]
fn a_cascade_that_diverged_at_every_speed_exits_nonzero() {
    let tmp = tempfile::tempdir().unwrap();
    // A 4 mm eccentricity throws the disk into the rings; with the step just under the
    // limit of the contacts at rest, every speed diverges.
    let model = std::fs::read_to_string(reference_rotor_path())
        .unwrap()
        .replace("eccentricity = \"40 um\"", "eccentricity = \"4 mm\"");
    let file = tmp.path().join("thrown.toml");
    std::fs::write(&file, model).unwrap();
    let out = tmp.path().join("cascade");
    let run = whirl()
        .arg("cascade")
        .arg(&file)
        .args(["--speeds", "300:400Hz:2", "--step", "3.6e-5s", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let message = text(&run);
    assert_eq!(run.status.code(), Some(1), "{message}");
    assert!(
        message.contains("diverged at every one of the 2 speeds"),
        "{message}"
    );
    assert!(!out.exists());
}

#[test]
fn a_bearing_name_of_300_characters_does_not_fail_at_write_time() {
    let tmp = tempfile::tempdir().unwrap();
    let name = "b".repeat(300);
    let model = std::fs::read_to_string(reference_rotor_path())
        .unwrap()
        .replace("name = \"bearing A\"", &format!("name = \"{name}\""));
    let file = tmp.path().join("long_name.toml");
    std::fs::write(&file, model).unwrap();
    let run = whirl()
        .arg("simulate")
        .arg(&file)
        .args([
            "--speed",
            "50Hz",
            "--duration",
            "0.05s",
            "--reduce",
            "12",
            "--out",
        ])
        .arg(tmp.path().join("simulate"))
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", text(&run));
}

#[test]
fn an_absurdly_long_cascade_warns_before_it_starts() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("cascade");
    // 0.5 s settling and the 4 records averaged at least (overlapping by half: 1.25 s) at
    // 2e-8 s: 8.75e7 steps per speed, 40 speeds: 38 min at least on 2 cores (the estimate
    // counts 1.3 us per step), while a speed's longest run (4 s + 8 records of 0.5 s
    // overlapping by half) stays within the 5e8 steps a run may take. The warning comes first; Ctrl-C stops it.
    let mut run = cascade(&out)
        .args(["--step", "2e-8s", "--max-records", "8"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_for_checkpoint(tmp.path(), "manifest.json");
    let _ = Command::new("kill")
        .args(["-INT", &run.id().to_string()])
        .status();
    // The speeds running finish before it stops: a second Ctrl-C quits at once.
    std::thread::sleep(Duration::from_millis(500));
    let _ = Command::new("kill")
        .args(["-INT", &run.id().to_string()])
        .status();
    let status = run.wait().unwrap();
    let mut message = String::new();
    use std::io::Read;
    run.stderr
        .take()
        .unwrap()
        .read_to_string(&mut message)
        .unwrap();
    assert_eq!(status.code(), Some(130), "{message}");
    assert!(
        message.contains("warning: --step 2e-8 s makes 8.750e7 time steps per speed, 40 speeds"),
        "{message}"
    );
    assert!(message.contains("of computing on"), "{message}");
    assert_eq!(hidden(tmp.path()), Vec::<String>::new());
}

#[test]
fn an_absurdly_long_study_warns_before_it_starts() {
    // Three points of 4 speeds at a 1e-9 s step: 5e8 steps per speed (0.1 s settling and
    // at least 4 records of 0.1 s), about an hour on 2 cores.
    let tmp = tempfile::tempdir().unwrap();
    let file = quick_study(tmp.path());
    let text = std::fs::read_to_string(&file).unwrap();
    std::fs::write(
        &file,
        text.replace("refine = false", "refine = false\nstep = \"1e-9 s\""),
    )
    .unwrap();
    let mut run = study(&file, &tmp.path().join("study"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut pipe = std::io::BufReader::new(run.stderr.take().unwrap());
    let mut line = String::new();
    use std::io::BufRead;
    let read = pipe.read_line(&mut line);
    let _ = run.kill();
    let _ = run.wait();
    assert!(read.is_ok_and(|n| n > 0), "nothing on stderr");
    assert!(
        line.starts_with("warning: the [cascade] step makes the 3 points at least"),
        "{line}"
    );
}

#[test]
fn long_work_says_how_far_it_is_also_into_a_pipe() {
    // 50 harmonics (the most) take seconds a point: stderr (a pipe here, not a terminal)
    // gets a line every few seconds.
    let tmp = tempfile::tempdir().unwrap();
    let mut run = whirl()
        .arg("hbm")
        .arg(reference_rotor_path())
        .args(["--harmonics", "50", "--out"])
        .arg(tmp.path().join("hbm"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut pipe = std::io::BufReader::new(run.stderr.take().unwrap());
    let mut line = String::new();
    use std::io::BufRead;
    // The first lines say how the default speeds were read and warn that each point is
    // slow; progress follows.
    let mut read = pipe.read_line(&mut line);
    while line.starts_with("speeds (default)") || line.starts_with("warning: H = 50") {
        line.clear();
        read = pipe.read_line(&mut line);
    }
    let _ = run.kill();
    let _ = run.wait();
    assert!(read.is_ok_and(|n| n > 0), "no progress line");
    assert!(line.starts_with("hbm (H = 50): "), "{line}");
    assert!(line.contains("Hz of 900.0 Hz"), "{line}");
}

#[test]
fn the_linear_analyses_of_a_large_model_say_how_far_they_are_into_a_pipe() {
    // 2,000 elements (8,004 DOFs): each command's work takes at least three times
    // progress::LOG_INTERVAL (5 s) of wall time on two cores (campbell 17 s, unbalance and
    // frf 21 s on a quick machine; 800 speeds or 1001 frequencies took under 7 s
    // there and ended before a line was due), so stderr (a pipe) gets a progress line; the
    // run is stopped once it has.
    let tmp = tempfile::tempdir().unwrap();
    let model = tmp.path().join("rotor_2000.toml");
    std::fs::write(&model, reference_rotor_text_meshed(2000)).unwrap();
    // The unbalance response adds speeds round each peak once its first pass is done, so
    // the line may count more than were asked for.
    for (command, args, (asked, unit)) in [
        (
            "campbell",
            &["--speeds", "0:800Hz:4000"][..],
            (4000, "speeds"),
        ),
        (
            "unbalance",
            &["--speeds", "1:800Hz:4000"][..],
            (4000, "speeds"),
        ),
        (
            "frf",
            &["--input", "1000:ux", "--frequencies", "0:800Hz:5001"][..],
            (5001, "frequencies"),
        ),
    ] {
        let mut run = whirl()
            .arg(command)
            .arg(&model)
            .args(args)
            .arg("--out")
            .arg(tmp.path().join(command))
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut pipe = std::io::BufReader::new(run.stderr.take().unwrap());
        use std::io::BufRead;
        let label = format!("{command}: ");
        let mut line = String::new();
        // Warnings may come first; the progress line follows (or the pipe ends, a failure).
        while pipe.read_line(&mut line).is_ok_and(|n| n > 0) && !line.starts_with(&label) {
            line.clear();
        }
        let _ = run.kill();
        let _ = run.wait();
        assert!(line.starts_with(&label), "{command}: no progress line");
        let total = progress_total(&line, unit);
        assert!(total.is_some_and(|n| n >= asked), "{line}");
        assert!(line.contains("left"), "{line}");
    }
}

/// The total of a progress line "<command>: done/total <unit>, ...".
fn progress_total(line: &str, unit: &str) -> Option<usize> {
    let (_, after) = line.split_once('/')?;
    let (total, rest) = after.split_once(' ')?;
    rest.starts_with(unit).then(|| total.parse().ok())?
}

/// A study of three quick cascades (4 speeds of 0.1 s each), written into `dir`.
fn quick_study(dir: &Path) -> PathBuf {
    let path = dir.join("study.toml");
    let text = format!(
        "title = \"quick\"\nmodel = {:?}\n\n[cascade]\nspeeds = \"40Hz:400Hz:4\"\n\
         settle = \"0.1 s\"\nsettle_max = \"0.1 s\"\nrecord = \"0.1 s\"\nrefine = false\n\n\
         [[sweep]]\nname = \"unbalance\"\nparameter = \"unbalance[0].eccentricity\"\n\
         values = [\"10 um\", \"20 um\", \"40 um\"]\n",
        reference_rotor_path().display().to_string()
    );
    std::fs::write(&path, text).unwrap();
    path
}

fn study(file: &Path, out: &Path) -> Command {
    let mut c = whirl();
    c.arg("study").arg(file).arg("--out").arg(out);
    c
}

/// Ctrl-C during a study keeps its finished points, and the rerun computes the rest and
/// writes what an uninterrupted study writes, with no temporary folder left.
#[test]
fn ctrl_c_during_a_study_keeps_its_points_and_a_rerun_ends_with_the_same_bytes() {
    let tmp = tempfile::tempdir().unwrap();
    let file = quick_study(tmp.path());
    let out = tmp.path().join("study");
    let run = study(&file, &out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let points = tmp.path().join("study.points").join("points");
    let start = Instant::now();
    while std::fs::read_dir(&points).map_or(0, |d| d.count()) == 0 {
        assert!(start.elapsed() < Duration::from_secs(120), "no point saved");
        std::thread::sleep(Duration::from_millis(20));
    }
    let message = ctrl_c(run);
    assert!(message.contains("the study was stopped"), "{message}");
    assert!(!out.exists(), "an interrupted study writes no result");
    let kept = std::fs::read_dir(&points).unwrap().count();
    assert!((1..3).contains(&kept), "{kept} points kept");

    let resumed = study(&file, &out).output().unwrap();
    assert!(resumed.status.success(), "{}", text(&resumed));
    let reference = tmp.path().join("uninterrupted");
    let whole = study(&file, &reference).output().unwrap();
    assert!(whole.status.success(), "{}", text(&whole));
    for entry in std::fs::read_dir(&reference).unwrap().flatten() {
        let name = entry.file_name();
        if name.to_string_lossy().ends_with(".csv") {
            assert_eq!(
                untimed(&out.join(&name)),
                untimed(&entry.path()),
                "{name:?}"
            );
        }
    }
    assert_eq!(
        hidden(tmp.path()),
        Vec::<String>::new(),
        "hidden files left"
    );
}

/// A CSV's cells without its `wall_time_s` column (the one thing two runs may differ in).
fn untimed(path: &Path) -> Vec<Vec<String>> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_path(path)
        .unwrap();
    let rows: Vec<Vec<String>> = reader
        .records()
        .map(|r| r.unwrap().iter().map(String::from).collect())
        .collect();
    let timed = rows
        .first()
        .and_then(|header| header.iter().position(|h| h == "wall_time_s"));
    rows.into_iter()
        .map(|mut row| {
            if let Some(i) = timed {
                row.remove(i);
            }
            row
        })
        .collect()
}

#[test]
fn an_absurdly_long_map_warns_before_it_starts() {
    // Two values at H = 40: at least 400 points a sweep at about 10 s each (the H = 5 point
    // cost grown as (2H + 1)^3): over an hour on 2 cores. The warning comes before the
    // sweeps start; Ctrl-C stops them and nothing is written.
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("map");
    let mut run = whirl()
        .arg("map")
        .arg(reference_rotor_path())
        .args(["--values", "20um,60um", "--harmonics", "40", "--out"])
        .arg(&out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    for _ in 0..2 {
        let _ = Command::new("kill")
            .args(["-INT", &run.id().to_string()])
            .status();
        std::thread::sleep(Duration::from_millis(300));
    }
    let status = run.wait().unwrap();
    let mut message = String::new();
    use std::io::Read;
    run.stderr
        .take()
        .unwrap()
        .read_to_string(&mut message)
        .unwrap();
    assert!(
        message.contains("warning: 2 values at H = 40 make 2 sweeps of at least"),
        "{message}"
    );
    assert_eq!(status.code(), Some(130), "{message}");
    assert!(!out.exists(), "{message}");
}
