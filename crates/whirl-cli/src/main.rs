//! `whirl`: rotordynamics of rotors on roller bearings, from the command line.
//!
//! A thin layer over the `whirl` library: parse the arguments, load and validate the model
//! file, call the library, write the results. Every command writes one folder (`--out`,
//! default `out/<command>`) holding `summary.json`, CSV tables and PNG + SVG plots; the
//! folder appears only when everything in it was written (see [`output`]).
//!
//! Errors go to stderr as miette diagnostics that name the file, line and column, the
//! field and the fix, with the offending line of the model file shown; the exit code is 1
//! (2 for a malformed command line, as clap reports it; 130 when stopped by Ctrl-C).
//!
//! One run per output folder at a time: the folder's lock is taken before any work (see
//! [`output::lock`]); Ctrl-C stops cleanly (see [`interrupt`]).

#![forbid(unsafe_code)]

mod commands;
mod error;
mod interrupt;
mod output;
mod progress;

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use commands::Outcome;

/// Rotordynamics of rotors on roller bearings.
///
/// Plain numbers are SI everywhere: lengths in m, speeds and frequencies in rad/s
/// (`--speeds`, `--frequencies`, `--max-frequency` alike). Give a unit to say otherwise:
/// `--speed 3000rpm`, `--speeds 0:800Hz:161`. Every command says on stderr how it read
/// each speed or range, in Hz and rpm.
#[derive(Debug, Parser)]
#[command(name = "whirl", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Validate a model file and summarise it (mesh, masses, supports, first frequencies).
    Check(commands::check::Args),
    /// Undamped modes and shapes, and damped whirl modes at one speed.
    Modal(commands::modal::Args),
    /// Campbell diagram: whirl frequencies over speed, critical speeds.
    Campbell(commands::campbell::Args),
    /// Mesh convergence: natural frequencies versus element count.
    Convergence(commands::convergence::Args),
    /// Static deflection, bending moment, shear force and bearing reactions under gravity.
    Static(commands::statics::Args),
    /// Steady unbalance response over speed: Bode, polar, orbit size, API 617 margins.
    Unbalance(commands::unbalance::Args),
    /// Frequency response functions between two DOFs at a spin speed; harmonic forced response.
    Frf(commands::frf::Args),
    /// Undamped critical-speed map: critical speeds against bearing stiffness (API 684).
    Ucs(commands::ucs::Args),
    /// Craig-Bampton reduction: frequency errors and stable time steps against the full model.
    Reduce(commands::reduce::Args),
    /// Time response at a speed: time histories, orbits, spectrum, settled 1X.
    Simulate(commands::simulate::Args),
    /// Equivalent stiffness of a roller bearing versus clearance; force-deflection surfaces.
    Stiffness(commands::stiffness::Args),
    /// Forcing function of a roller bearing (thesis eq. 3.12) fitted to its Hertz response.
    FitForcing(commands::fit_forcing::Args),
    /// Periodic response by harmonic balance over speed, its stability and bifurcations.
    Hbm(commands::hbm::Args),
    /// NSV map: where the synchronous orbit is unstable over speed and one model parameter,
    /// and by which bifurcation.
    Map(commands::map::Args),
    /// Cascade (waterfall) of non-synchronous vibration over a speed range, classified.
    Cascade(commands::cascade::Args),
    /// Run-up and coast-down through a speed range: time-frequency cascade and hysteresis.
    Runup(commands::runup::Args),
    /// Sensitivity study: sweeps of model parameters, each point a cascade (thesis ch. 5).
    Study(commands::study::Args),
    /// A rotor saved by ROSS (Rotor.save) as a whirl model file, with its first frequencies.
    ImportRoss(commands::import_ross::Args),
}

impl Command {
    /// The folder this run writes.
    fn out_dir(&self) -> PathBuf {
        match self {
            Command::Check(a) => a.common.out_dir("check"),
            Command::Modal(a) => a.common.out_dir("modal"),
            Command::Campbell(a) => a.common.out_dir("campbell"),
            Command::Convergence(a) => a.common.out_dir("convergence"),
            Command::Static(a) => a.common.out_dir("static"),
            Command::Unbalance(a) => a.common.out_dir("unbalance"),
            Command::Frf(a) => a.common.out_dir("frf"),
            Command::Ucs(a) => a.common.out_dir("ucs"),
            Command::Reduce(a) => a.common.out_dir("reduce"),
            Command::Simulate(a) => a.common.out_dir("simulate"),
            Command::Stiffness(a) => a.common.out_dir("stiffness"),
            Command::FitForcing(a) => a.common.out_dir("fit-forcing"),
            Command::Hbm(a) => a.common.out_dir("hbm"),
            Command::Map(a) => a.common.out_dir("map"),
            Command::Cascade(a) => a.common.out_dir("cascade"),
            Command::Runup(a) => a.common.out_dir("runup"),
            Command::Study(a) => a.out_dir(),
            Command::ImportRoss(a) => a.out_dir(),
        }
    }

    fn run(&self) -> miette::Result<Outcome> {
        match self {
            Command::Check(a) => commands::check::run(a),
            Command::Modal(a) => commands::modal::run(a),
            Command::Campbell(a) => commands::campbell::run(a),
            Command::Convergence(a) => commands::convergence::run(a),
            Command::Static(a) => commands::statics::run(a),
            Command::Unbalance(a) => commands::unbalance::run(a),
            Command::Frf(a) => commands::frf::run(a),
            Command::Ucs(a) => commands::ucs::run(a),
            Command::Reduce(a) => commands::reduce::run(a),
            Command::Simulate(a) => commands::simulate::run(a),
            Command::Stiffness(a) => commands::stiffness::run(a),
            Command::FitForcing(a) => commands::fit_forcing::run(a),
            Command::Hbm(a) => commands::hbm::run(a),
            Command::Map(a) => commands::map::run(a),
            Command::Cascade(a) => commands::cascade::run(a),
            Command::Runup(a) => commands::runup::run(a),
            Command::Study(a) => commands::study::run(a),
            Command::ImportRoss(a) => commands::import_ross::run(a),
        }
    }
}

fn main() -> ExitCode {
    // whirl parallelises across speeds with rayon; faer's own threads would only compete.
    faer::set_global_parallelism(faer::Par::Seq);
    error::install_hook();
    interrupt::install();
    let cli = Cli::parse();
    let result = output::lock(&cli.command.out_dir()).and_then(|_lock| cli.command.run());
    match result {
        Ok(outcome) => {
            report(&outcome);
            ExitCode::SUCCESS
        }
        Err(e) => {
            // Writing to a closed stderr must not panic either.
            let _ = writeln!(std::io::stderr(), "{e:?}");
            if interrupt::requested() {
                ExitCode::from(interrupt::EXIT_INTERRUPTED)
            } else {
                ExitCode::FAILURE
            }
        }
    }
}

/// Prints the summary: JSON with `--json`, text otherwise. A closed stdout is not an error.
fn report(outcome: &Outcome) {
    let mut out = std::io::stdout().lock();
    let _ = if outcome.json {
        let text = serde_json::to_string_pretty(&outcome.summary).unwrap_or_default();
        writeln!(out, "{text}")
    } else {
        writeln!(
            out,
            "{}\nwrote {} files to {}",
            outcome.text.trim_end(),
            outcome.files,
            outcome.dir.display()
        )
    };
}
