//! Fuzzing: model files and command lines generated and mutated from the bundled
//! examples, checking that nothing panics or aborts and that every rejection is located.
//!
//! Model files run in this process, on every core: read and validated, and when accepted,
//! assembled and solved for their first modes (as `whirl check` does). A rejected model must
//! name its field or its line and column. Beside them, one thread runs the `whirl` binary
//! without pause, alternately `whirl check` on a mutated model (so the error printer is
//! fuzzed too) and a generated command line: its exit status must be 0, 1 or 2 (never a
//! panic's 101 or a signal), a failure must say why on stderr, and a run still going after
//! [`RUN_LIMIT`] (valid long work, e.g. a cascade) must have said how far it is on stderr by
//! then, unless it had too little CPU time to owe a word ([`STARVED_CPU`]; counted apart).
//!
//! The test suite runs it for a few seconds (`fuzz_briefly`). For hours:
//!
//! ```sh
//! WHIRL_FUZZ_SECONDS=7200 nice -n 19 cargo test -p whirl-cli --test suite fuzz:: -- --ignored --nocapture
//! ```
//!
//! prints the inputs run and the rate every minute; a failing input is written to
//! `$TMPDIR/whirl-fuzz-failures/` to be replayed with `whirl check`. `WHIRL_FUZZ_SEED`
//! picks another sequence of inputs (the default is fixed, so a failure reproduces).

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use whirl::fe::{assemble, Bearings};
use whirl::modal::{check_model, undamped_modes};
use whirl::model::{BeamTheory, Model};

use crate::reference::example_path;

/// How long a generated run may go on before it is stopped, in the long run; by then it must
/// have printed its progress (a line every 5 s), or it counts as a run that went silent.
const RUN_LIMIT: Duration = Duration::from_secs(60);

/// [`RUN_LIMIT`] in the test suite's brief run: long enough for a progress line on a loaded
/// machine, short enough that one valid long command (200 harmonics) does not hold the
/// suite for a minute.
const BRIEF_RUN_LIMIT: Duration = Duration::from_secs(15);

/// Relative rise of the first frequency on twice the elements taken as the solves' own
/// round-off and tolerance: 1e-9 was typical at 120 nodes, +2.2e-7 was seen on an accepted
/// fuzz model, and the round-off of a too fine mesh moved it by 1e-3 to 4e-2.
const RISE_TOLERANCE: f64 = 1e-5;

/// Models larger than this many nodes are validated only: the cost of big models is the
/// business of the scale benchmarks, not of a fuzzer that must run thousands per minute.
const MAX_SOLVED_NODES: usize = 60;

/// xorshift64*: a small, fixed, fast generator, so a seed gives the same inputs everywhere.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// Values that have broken parsers and solvers before: zero, signs, extremes, non-numbers,
/// wrong units, huge counts, long text.
const VALUES: &[&str] = &[
    "0",
    "-1",
    "1",
    "2.5",
    "-0.0",
    "1e308",
    "-1e308",
    "1e-300",
    "1e30",
    "10000000000",
    "9223372036854775807",
    "nan",
    "inf",
    "\"\"",
    "\"1e308 Hz\"",
    "\"-5 mm\"",
    "\"20 furlongs\"",
    "\"5 mm\"",
    "\"0.1 um\"",
    "\"nan m\"",
    "[]",
    "{}",
    "true",
    "\"palmgren\"",
];

/// Speeds, times, counts and lists for command lines, good and bad.
const ARGS: &[&str] = &[
    "1:750Hz:10000000000",
    "1:750Hz:5",
    "0:100Hz:3",
    "100Hz:1Hz:3",
    "1e308Hz",
    "1e308",
    "0:1e300:3",
    "1e308Hz:1e308Hz:2",
    "-5Hz",
    "50Hz",
    "3000rpm",
    "nan",
    "0",
    "-1",
    "1000000000",
    "200",
    "1e-300s",
    "1e30N",
    "abc",
    "",
    "10,0",
    "99999",
];

/// A command with its flags that take a value (each gets a random [`ARGS`] entry).
const COMMANDS: &[(&str, &[&str])] = &[
    ("check", &[]),
    ("modal", &["--speed", "--modes"]),
    ("campbell", &["--speeds", "--modes"]),
    ("unbalance", &["--speeds", "--nodes"]),
    ("stiffness", &["--load", "--clearances", "--cage-steps"]),
    ("cascade", &["--speeds", "--settle", "--record", "--step"]),
    ("hbm", &["--speeds", "--samples", "--harmonics"]),
    ("fit-forcing", &["--speeds"]),
    ("simulate", &["--speed", "--duration", "--step"]),
    ("convergence", &["--counts", "--modes"]),
    ("static", &[]),
    (
        "frf",
        &["--input", "--output", "--speed", "--frequencies", "--force"],
    ),
    ("ucs", &["--stiffness", "--modes"]),
];

/// The model files mutations start from.
fn seeds() -> Vec<String> {
    [
        "reference_rotor.toml",
        "reference_rotor_soft.toml",
        "reference_rotor_waviness.toml",
    ]
    .iter()
    .map(|f| std::fs::read_to_string(example_path(f)).expect("bundled example"))
    .collect()
}

/// One to three random edits of `text`.
fn mutate(rng: &mut Rng, text: &str) -> String {
    let mut t = text.to_string();
    for _ in 0..=rng.below(3) {
        t = match rng.below(8) {
            0 => replace_value(rng, &t),
            1 => replace_value(rng, &t),
            2 => edit_lines(rng, &t, |lines, i| {
                lines.remove(i);
            }),
            3 => edit_lines(rng, &t, |lines, i| {
                let line = lines[i].clone();
                lines.insert(i, line);
            }),
            4 => {
                // A byte replaced by a character TOML cares about.
                let mut chars: Vec<char> = t.chars().collect();
                if !chars.is_empty() {
                    let i = rng.below(chars.len());
                    chars[i] = *rng.pick(&['"', '=', '[', ']', '\n', '#', '{', ',', '.', 'é']);
                }
                chars.into_iter().collect()
            }
            5 => {
                let cut = rng.below(t.len());
                let cut = (0..=cut)
                    .rev()
                    .find(|&i| t.is_char_boundary(i))
                    .unwrap_or(0);
                t[..cut].to_string()
            }
            6 => {
                // A very long run of text (the printer once panicked past column 65,535).
                let at = t.find('\n').unwrap_or(0);
                format!("{}{}{}", &t[..at], "a".repeat(70_000), &t[at..])
            }
            _ => {
                let from = *rng.pick(&["um", "mm", "Hz", "kg", " m\""]);
                let to = *rng.pick(&["furlongs", "Hz", "m", "um", "rpm", ""]);
                t.replacen(from, to, 1)
            }
        };
    }
    t
}

/// Replaces the value of a random `key = value` line.
fn replace_value(rng: &mut Rng, text: &str) -> String {
    let value = *rng.pick(VALUES);
    edit_lines(rng, text, |lines, i| {
        if let Some((key, _)) = lines[i].split_once('=') {
            lines[i] = format!("{key}= {value}");
        }
    })
}

fn edit_lines(rng: &mut Rng, text: &str, edit: impl FnOnce(&mut Vec<String>, usize)) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    if !lines.is_empty() {
        let i = rng.below(lines.len());
        edit(&mut lines, i);
    }
    lines.join("\n") + "\n"
}

/// What went wrong with one input.
#[derive(Debug)]
struct Failure {
    what: String,
    input: String,
}

/// Counts of what the inputs did, shared by the threads that make them.
#[derive(Debug, Default)]
struct Tally {
    models: AtomicU64,
    accepted: AtomicU64,
    /// Accepted models whose `check` answer the oracles judged ([`wrong_answer`]).
    oracles: AtomicU64,
    /// Of them, those also solved on twice the elements (the mesh convergence oracle).
    refined: AtomicU64,
    processes: AtomicU64,
    /// Runs stopped at the limit without a word that had too little CPU time to have owed
    /// one: a starved run (a loaded machine, `nice`) is no verdict on the program.
    starved: AtomicU64,
    failures: Mutex<Vec<Failure>>,
}

impl Tally {
    fn fail(&self, what: String, input: &str) {
        eprintln!("fuzz failure: {what}");
        if let Ok(mut f) = self.failures.lock() {
            f.push(Failure {
                what,
                input: input.to_string(),
            });
        }
    }

    fn failure_count(&self) -> usize {
        self.failures.lock().map_or(0, |f| f.len())
    }
}

/// Reads, validates and (when small) solves one model text in this process, as the command
/// line does; a panic or an unlocated rejection is a failure.
fn run_model(text: &str, tally: &Tally) {
    tally.models.fetch_add(1, Relaxed);
    let outcome = catch_unwind(AssertUnwindSafe(|| -> Result<bool, String> {
        let model = match Model::from_toml_str(text, Some(PathBuf::from("fuzz.toml"))) {
            Ok(m) => m,
            Err(whirl::Error::Input(e)) if e.line_column.is_some() || e.field.is_some() => {
                return Ok(false)
            }
            Err(e) => return Err(format!("rejected without a place: {e}")),
        };
        let _ = model.warnings();
        if model.check_supports().is_err() || model.node_count() > MAX_SOLVED_NODES {
            return Ok(true);
        }
        let _ = undamped_modes(&assemble(&model, Bearings::Linearised), 4);
        wrong_answer(&model, tally)?;
        Ok(true)
    }));
    match outcome {
        Ok(Ok(accepted)) => {
            tally.accepted.fetch_add(u64::from(accepted), Relaxed);
        }
        Ok(Err(what)) => tally.fail(what, text),
        Err(_) => tally.fail("panic".into(), text),
    }
}

/// How far round-off may move the first eigenvalue of `model` meshed with `elements` per
/// section, relative: the machine epsilon times w_max^2 / w_1^2, w_max^2 bounded by the
/// stiffest element's highest eigenvalue, 8400 E I / (rho A l^4) for a cubic beam element
/// of length l with its consistent mass (free-free). A shaft far stiffer than its supports
/// on short elements sets it: 2.5 m across, 1.3 m long, on 1e6 N/m (a fuzz model, first
/// frequency 0.9 Hz) puts it near 0.5, and the first frequency rose by 1.8e-5 on 40
/// elements against 20; the reference rotor's is 9e-8.
fn round_off_bound(model: &Model, elements: &[usize], first_hz: f64) -> f64 {
    let stiffest = model
        .sections
        .iter()
        .zip(elements)
        .map(|(s, &n)| {
            let l = s.length / n as f64;
            // I / A of a hollow circle.
            let radius_of_gyration2 = (s.outer_diameter.powi(2) + s.inner_diameter.powi(2)) / 16.0;
            8400.0 * s.material.young_modulus * radius_of_gyration2
                / (s.material.density * l.powi(4))
        })
        .fold(0.0, f64::max);
    f64::EPSILON * stiffest / (std::f64::consts::TAU * first_hz).powi(2)
}

/// The oracles for answers that are wrong though nothing failed, on a model `whirl check`
/// would solve:
/// - finite outputs: the frequencies `check` reports are finite, non-negative, ascending;
/// - rigid body: an accepted first mode is no rigid-body motion (at least 0.1 Hz; a rotor
///   its supports leave free must be refused, not answered with 0 Hz);
/// - mesh convergence: on twice the elements (Euler-Bernoulli: the cubic shape functions of
///   the halved elements contain the coarse ones), the first frequency is a Rayleigh-Ritz
///   bound of the coarse one, so it may not rise beyond [`RISE_TOLERANCE`] or the solve's
///   round-off ([`round_off_bound`]), whichever is larger.
fn wrong_answer(model: &Model, tally: &Tally) -> Result<(), String> {
    let Ok(coarse) = check_model(model) else {
        return Ok(());
    };
    let f = &coarse.frequencies_hz;
    if f.iter().any(|x| !x.is_finite() || *x < 0.0) || f.windows(2).any(|w| w[1] < w[0]) {
        return Err(format!(
            "check's frequencies are not finite and ascending: {f:?}"
        ));
    }
    tally.oracles.fetch_add(1, Relaxed);
    let first = f.first().copied().unwrap_or(f64::NAN);
    if first < 0.1 {
        return Err(format!(
            "accepted a rigid-body mode as the first frequency: {first} Hz"
        ));
    }
    let euler = model
        .sections
        .iter()
        .all(|s| s.beam == BeamTheory::EulerBernoulli);
    let doubled: Vec<usize> = model.sections.iter().map(|s| 2 * s.elements).collect();
    let Some(fine) = euler
        .then(|| model.remeshed(&doubled).ok())
        .flatten()
        .and_then(|m| check_model(&m).ok())
    else {
        return Ok(());
    };
    tally.refined.fetch_add(1, Relaxed);
    let refined = fine.frequencies_hz.first().copied().unwrap_or(f64::NAN);
    let tolerance = RISE_TOLERANCE.max(round_off_bound(model, &doubled, first));
    if refined.is_nan() || refined > first * (1.0 + tolerance) {
        return Err(format!(
            "the first frequency rose from {first} Hz to {refined} Hz on twice the elements \
             (a finer mesh can only lower it)"
        ));
    }
    Ok(())
}

/// Runs `whirl` with `args` (model file `model`), checking how it ends.
fn run_process(dir: &Path, model: &str, args: &[String], limit: Duration, tally: &Tally) {
    let n = tally.processes.fetch_add(1, Relaxed) + 1;
    let file = dir.join("fuzz.toml");
    if std::fs::write(&file, model).is_err() {
        return;
    }
    let out = dir.join(format!("out{n}"));
    let mut child = match Command::new(env!("CARGO_BIN_EXE_whirl"))
        .args(&args[..1])
        .arg(&file)
        .args(&args[1..])
        .arg("--out")
        .arg(&out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
    {
        Ok(c) => c,
        Err(_) => return,
    };
    let start = Instant::now();
    let mut stopped = false;
    let mut starved = false;
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Some(status),
            Ok(None) if start.elapsed() > limit => {
                starved = cpu_seconds(child.id()).is_some_and(|cpu| cpu < STARVED_CPU);
                let _ = child.kill();
                let _ = child.wait();
                stopped = true;
                break None;
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(2)),
            Err(_) => break None,
        }
    };
    let mut stderr = String::new();
    if let Some(mut pipe) = child.stderr.take() {
        use std::io::Read;
        let _ = pipe.read_to_string(&mut stderr);
    }
    let _ = std::fs::remove_dir_all(&out);
    let what = match status.and_then(|s| s.code()) {
        None if stopped && !stderr.trim().is_empty() => None,
        None if stopped && starved => {
            tally.starved.fetch_add(1, Relaxed);
            None
        }
        None if stopped => Some(format!("silent for {} s", limit.as_secs())),
        None => Some("killed by a signal".to_string()),
        Some(0) => None,
        Some(1 | 2) if !stderr.trim().is_empty() => None,
        Some(1 | 2) => Some("failed without a word".to_string()),
        Some(code) => Some(format!("exit status {code}: {}", tail(&stderr))),
    };
    if let Some(what) = what {
        tally.fail(format!("whirl {}: {what}", args.join(" ")), model);
    }
}

/// A run that had less CPU time than this by the limit was starved, not silent: it owed a
/// progress line only after 5 s of its own work.
const STARVED_CPU: f64 = 10.0;

/// The CPU time (user + system) process `pid` has had, s, where the system tells it
/// (Linux's /proc).
fn cpu_seconds(pid: u32) -> Option<f64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // Fields after the command name (which may hold spaces) in parentheses; utime and
    // stime are the 14th and 15th fields, in clock ticks of 1/100 s on Linux.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

fn tail(text: &str) -> String {
    let start = text.len().saturating_sub(2000);
    let start = (start..text.len())
        .find(|&i| text.is_char_boundary(i))
        .unwrap_or(0);
    text[start..].to_string()
}

/// A random command line: a command and some of its flags with random values.
fn command_line(rng: &mut Rng) -> Vec<String> {
    let (command, flags) = *rng.pick(COMMANDS);
    let mut args = vec![command.to_string()];
    for flag in flags.iter() {
        if rng.below(2) == 0 {
            args.push(flag.to_string());
            args.push(rng.pick(ARGS).to_string());
        }
    }
    args
}

/// Fuzzes for `seconds` on every core: model files in this process on one thread per core,
/// and beside them `whirl` runs one after another (a run may take its whole `limit`, and
/// the model files should not wait for it). Each thread's inputs are a fixed sequence of
/// `seed`, so a failure reproduces. Returns the tally.
fn fuzz(seconds: f64, seed: u64, limit: Duration) -> Tally {
    let seeds = seeds();
    let tally = Tally::default();
    let start = Instant::now();
    let deadline = start + Duration::from_secs_f64(seconds);
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    std::thread::scope(|s| {
        let workers: Vec<_> = (0..threads)
            .map(|k| {
                let (seeds, tally) = (&seeds, &tally);
                s.spawn(move || fuzz_models(seeds, stream(seed, k), deadline, tally))
            })
            .chain(std::iter::once({
                let (seeds, tally) = (&seeds, &tally);
                s.spawn(move || fuzz_runs(seeds, stream(seed, threads), deadline, limit, tally))
            }))
            .collect();
        let mut last_report = Instant::now();
        while !workers.iter().all(|w| w.is_finished()) {
            std::thread::sleep(Duration::from_millis(100));
            if last_report.elapsed() > Duration::from_secs(60) {
                last_report = Instant::now();
                report(&tally, start.elapsed());
            }
        }
    });
    report(&tally, start.elapsed());
    tally
}

/// The generator of thread `k` of the run seeded `seed`.
fn stream(seed: u64, k: usize) -> Rng {
    Rng((seed ^ (k as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15)).max(1))
}

fn fuzz_models(seeds: &[String], mut rng: Rng, deadline: Instant, tally: &Tally) {
    while Instant::now() < deadline {
        let base = rng.pick(seeds).clone();
        run_model(&mutate(&mut rng, &base), tally);
    }
}

/// Alternately a mutated model through `whirl check` (the error printer) and a random
/// command line on the unmutated reference (the options are fuzzed).
fn fuzz_runs(seeds: &[String], mut rng: Rng, deadline: Instant, limit: Duration, tally: &Tally) {
    let Ok(dir) = tempfile::tempdir() else {
        return tally.fail("no temporary folder".into(), "");
    };
    let mut check = true;
    while Instant::now() < deadline {
        if check {
            let base = rng.pick(seeds).clone();
            let text = mutate(&mut rng, &base);
            run_process(dir.path(), &text, &["check".to_string()], limit, tally);
        } else {
            let args = command_line(&mut rng);
            run_process(dir.path(), &seeds[0], &args, limit, tally);
        }
        check = !check;
    }
}

fn report(tally: &Tally, elapsed: Duration) {
    let s = elapsed.as_secs_f64();
    let (models, processes) = (tally.models.load(Relaxed), tally.processes.load(Relaxed));
    eprintln!(
        "fuzz: {:.0} s: {} model files ({} accepted, {} judged by the oracles, {} on a refined \
         mesh), {} whirl runs ({} starved), {:.0} inputs/s, {} failures",
        s,
        models,
        tally.accepted.load(Relaxed),
        tally.oracles.load(Relaxed),
        tally.refined.load(Relaxed),
        processes,
        tally.starved.load(Relaxed),
        (models + processes) as f64 / s.max(1e-9),
        tally.failure_count()
    );
}

/// Writes the failing inputs where they can be replayed, and fails with the first few.
fn assert_clean(tally: &Tally) {
    let Ok(failures) = tally.failures.lock() else {
        panic!("a fuzzing thread panicked while recording a failure");
    };
    if failures.is_empty() {
        return;
    }
    let dir = std::env::temp_dir().join("whirl-fuzz-failures");
    let _ = std::fs::create_dir_all(&dir);
    for (i, f) in failures.iter().enumerate() {
        let _ = std::fs::write(dir.join(format!("failure-{i}.toml")), &f.input);
    }
    let first: Vec<&str> = failures.iter().take(5).map(|f| f.what.as_str()).collect();
    panic!(
        "{} failures (inputs in {}); first: {first:#?}",
        failures.len(),
        dir.display()
    );
}

fn env_number(name: &str, default: f64) -> f64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

#[test]
fn fuzz_briefly() {
    // A few seconds in the suite (and the whirl run under way when they are up): some
    // thousands of model files and a few tens of whirl runs.
    let tally = fuzz(4.0, 0x5eed, BRIEF_RUN_LIMIT);
    assert!(tally.models.load(Relaxed) > 100, "{tally:?}");
    assert_clean(&tally);
}

#[test]
#[ignore = "hours; run with WHIRL_FUZZ_SECONDS (see the module doc)"]
fn fuzz_long() {
    let seconds = env_number("WHIRL_FUZZ_SECONDS", 3600.0);
    let seed = env_number("WHIRL_FUZZ_SEED", 7.0) as u64;
    let tally = fuzz(seconds, seed, RUN_LIMIT);
    assert_clean(&tally);
}
