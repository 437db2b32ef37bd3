//! What a map reports ([`crate::report`]): per value the first loss of stability and the
//! unstable bands with what opens and closes each, the cost of each sweep, and the design
//! query: which values keep the synchronous orbit stable below a given speed.

use serde::Serialize;

use super::bands::{Edge, Growing, UnstableBand};
use super::check::{CascadeCheck, Confirmation};
use super::lines::{Excitation, ResonanceLine};
use super::request::MapValue;
use super::run::{FirstLoss, Parallelism, ValueRun};
use crate::hbm::SweepOptions;
use crate::report::{Report, Table};
use crate::units::rad_s_to_hz as hz;

/// One value of a map: the value and what its sweep left (its bands, lines and cost).
#[derive(Debug)]
pub struct MapEntry {
    /// The value and its model.
    pub value: MapValue,
    /// What its sweep left, and what it cost.
    pub run: ValueRun,
}

/// A map of the synchronous orbit's stability over speed and one parameter.
#[derive(Debug)]
pub struct MapReport {
    /// The parameter's path in the model file.
    pub parameter: String,
    /// What every sweep solved.
    pub options: SweepOptions,
    /// The values in the order given.
    pub entries: Vec<MapEntry>,
    /// The map against cascades, at the values asked for.
    pub checks: Vec<CascadeCheck>,
    /// The design query's answer tried by a cascade, when asked and a value is clear.
    pub confirmation: Option<Confirmation>,
    /// The design query's speed, rad/s.
    pub clear_below: Option<f64>,
    /// How the sweeps were spread over the threads.
    pub parallelism: Parallelism,
    /// Rayon's threads.
    pub threads: usize,
    /// Processor time of the whole map, s, where the system tells it.
    pub cpu_s: Option<f64>,
    /// Wall-clock time of the whole map, s.
    pub wall_s: f64,
}

/// Whether a value keeps the orbit stable below the query's speed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Clearance {
    /// No unstable band below the speed, and the branch followed all the way to it.
    Clear,
    /// An unstable band below the speed.
    Unstable,
    /// Not known: the sweep failed, stopped below the speed, or jumped over a stretch
    /// below it.
    Undecided,
}

impl MapEntry {
    /// Whether this value keeps the orbit stable below `speed` (rad/s).
    pub fn clearance(&self, speed: f64) -> Clearance {
        let below = hz(speed);
        if self.run.bands.iter().any(|b| b.span_hz[0] < below) {
            return Clearance::Unstable;
        }
        if self.run.failed() {
            return Clearance::Undecided;
        }
        let reached = self.run.reached >= speed;
        let jumped = self.run.jumps.iter().any(|&(from, _)| from < speed);
        if reached && !jumped {
            Clearance::Clear
        } else {
            Clearance::Undecided
        }
    }

    /// The sweep's first loss of stability, the same as `whirl hbm` reports.
    pub fn first_loss(&self) -> Option<&FirstLoss> {
        self.run.first_loss.as_ref()
    }
}

/// The key numbers of a [`MapReport`].
#[derive(Debug, Clone, Serialize)]
pub struct MapSummary {
    /// The parameter's path in the model file.
    pub parameter: String,
    /// First and last speed of every sweep, Hz.
    pub speed_range_hz: [f64; 2],
    /// How the bearings were modelled.
    pub bearings: String,
    /// Harmonics H.
    pub harmonics: usize,
    /// AFT samples per period (`None`: the default for H).
    pub samples_per_period: Option<usize>,
    /// Fixed-interface modes of the stability model.
    pub stability_modes: usize,
    /// How the sweeps were spread over the threads.
    pub parallelism: Parallelism,
    /// Threads.
    pub threads: usize,
    /// Processor time of the whole map, s.
    pub cpu_s: Option<f64>,
    /// Wall-clock time of the whole map, s.
    pub wall_s: f64,
    /// Each value, in the order given.
    pub values: Vec<ValueSummary>,
    /// The design query, when asked.
    pub clear_below: Option<ClearBelow>,
    /// The map against cascades, when asked.
    pub checks: Vec<CheckSummary>,
    /// The design query's answer tried by a cascade, when asked.
    pub confirmation: Option<Confirmation>,
}

/// The map against one cascade, in numbers.
#[derive(Debug, Clone, Serialize)]
pub struct CheckSummary {
    /// The comparison, speed by speed where they disagree.
    #[serde(flatten)]
    pub check: CascadeCheck,
    /// Share of the speeds with NSV at or above the level that the map explains.
    pub explained_fraction: f64,
    /// Share of the speeds predicted quiet that are below the level.
    pub quiet_fraction: f64,
}

/// One value of a map.
#[derive(Debug, Clone, Serialize)]
pub struct ValueSummary {
    /// The value as given.
    pub value: String,
    /// In SI, when it is a number or a quantity.
    pub si: Option<f64>,
    /// Speed of the first loss of stability, Hz.
    pub first_stability_loss_hz: Option<f64>,
    /// The bifurcation there.
    pub first_loss_kind: Option<&'static str>,
    /// The unstable bands, in path order.
    pub bands: Vec<BandSummary>,
    /// Resonance lines, and those on a stable orbit (where NSV can appear without a loss
    /// of stability).
    pub lines: usize,
    /// Of them on a stable orbit.
    pub lines_on_stable_orbit: usize,
    /// Points of the branch: what a sweep's cost grows with (0 when it failed).
    pub points: usize,
    /// Why the branch ended, or why the sweep failed.
    pub end: String,
    /// Stretches the path jumped over (not followed), Hz.
    pub jumps_hz: Vec<[f64; 2]>,
    /// Processor time of the sweep, s.
    pub cpu_s: Option<f64>,
    /// Wall-clock time of the sweep, s.
    pub wall_s: f64,
    /// The sweep failed.
    pub failed: bool,
}

/// One unstable band.
#[derive(Debug, Clone, Serialize)]
pub struct BandSummary {
    /// Speed where it opens, Hz.
    pub opens_hz: f64,
    /// What opens it (a bifurcation's name, `branch start` or `jump`).
    pub opens: &'static str,
    /// The frequency that emerges where it opens, Hz (at a bifurcation).
    pub emerging_hz: Option<f64>,
    /// Whether the opening bifurcation holds at twice the samples and modes.
    pub opens_resolved: Option<bool>,
    /// Speed where it closes, Hz.
    pub closes_hz: f64,
    /// What closes it (a bifurcation's name, `branch end` or `jump`).
    pub closes: &'static str,
    /// The lowest and highest speed it covers, Hz.
    pub span_hz: [f64; 2],
    /// Speeds within it where a stable synchronous orbit coexists, Hz.
    pub coexisting_stable_hz: Vec<[f64; 2]>,
    /// What grows inside it, stretch by stretch.
    pub growing: Vec<Growing>,
    /// The largest real part of its points' Floquet exponents, 1/s (none for a window
    /// between two points).
    pub largest_growth_per_s: Option<f64>,
}

/// The answer to "which values keep the orbit free of unstable bands below this speed".
#[derive(Debug, Clone, Serialize)]
pub struct ClearBelow {
    /// The speed, Hz.
    pub speed_hz: f64,
    /// The values that do, as given.
    pub clear: Vec<String>,
    /// The values that do not.
    pub unstable: Vec<String>,
    /// The values not decided (a failed sweep, a branch that stops or jumps below).
    pub undecided: Vec<String>,
    /// The largest numeric value that does.
    pub largest_clear: Option<String>,
    /// The smallest numeric value that does.
    pub smallest_clear: Option<String>,
}

impl MapReport {
    /// The design query at `speed` (rad/s).
    pub fn clear_below(&self, speed: f64) -> ClearBelow {
        let with = |c: Clearance| -> Vec<&MapEntry> {
            self.entries
                .iter()
                .filter(|e| e.clearance(speed) == c)
                .collect()
        };
        let names = |v: &[&MapEntry]| v.iter().map(|e| e.value.text.clone()).collect();
        let clear = with(Clearance::Clear);
        let numeric = || clear.iter().filter_map(|e| Some((e.value.si?, e)));
        let text = |e: Option<(f64, &&MapEntry)>| e.map(|(_, e)| e.value.text.clone());
        ClearBelow {
            speed_hz: hz(speed),
            largest_clear: text(numeric().max_by(|a, b| a.0.total_cmp(&b.0))),
            smallest_clear: text(numeric().min_by(|a, b| a.0.total_cmp(&b.0))),
            clear: names(&clear),
            unstable: names(&with(Clearance::Unstable)),
            undecided: names(&with(Clearance::Undecided)),
        }
    }

    fn value_summary(e: &MapEntry) -> ValueSummary {
        let first = e.first_loss();
        ValueSummary {
            value: e.value.text.clone(),
            si: e.value.si,
            first_stability_loss_hz: first.map(|b| hz(b.frequency)),
            first_loss_kind: first.map(|b| b.kind.name()),
            bands: e.run.bands.iter().map(band_summary).collect(),
            lines: e.run.lines.len(),
            lines_on_stable_orbit: e.run.lines.iter().filter(|l| l.on_stable_orbit).count(),
            points: e.run.points,
            end: e.run.end.clone(),
            jumps_hz: e.run.jumps_hz(),
            cpu_s: e.run.cpu_s,
            wall_s: e.run.wall_s,
            failed: e.run.failed(),
        }
    }
}

fn band_summary(b: &UnstableBand) -> BandSummary {
    let resolved = match b.opens {
        Edge::Bifurcation { resolved, .. } => resolved,
        _ => None,
    };
    BandSummary {
        opens_hz: b.opens_hz,
        opens: b.opens.name(),
        emerging_hz: b.opens.emerging_hz(),
        opens_resolved: resolved,
        closes_hz: b.closes_hz,
        closes: b.closes.name(),
        span_hz: b.span_hz,
        coexisting_stable_hz: b.coexisting_stable_hz.clone(),
        growing: b.growing.clone(),
        largest_growth_per_s: b.largest_growth_per_s,
    }
}

/// What grows inside a band, as one line: `w/2 528.6-541.0 Hz at 264.3-270.5 Hz; complex
/// 541.6-627.4 Hz at 45.1-52.3 Hz`.
pub fn growing_text(growing: &[Growing]) -> String {
    growing
        .iter()
        .map(|g| {
            format!(
                "{} {:.1}-{:.1} Hz at {:.1}-{:.1} Hz",
                g.growth.name(),
                g.speeds_hz[0],
                g.speeds_hz[1],
                g.frequency_hz[0],
                g.frequency_hz[1]
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
}

impl Report for MapReport {
    type Summary = MapSummary;

    fn summary(&self) -> MapSummary {
        MapSummary {
            parameter: self.parameter.clone(),
            speed_range_hz: [hz(self.options.from), hz(self.options.to)],
            bearings: self.options.describe_bearings(),
            harmonics: self.options.harmonics,
            samples_per_period: self.options.samples,
            stability_modes: self.options.stability_modes,
            parallelism: self.parallelism,
            threads: self.threads,
            cpu_s: self.cpu_s,
            wall_s: self.wall_s,
            values: self.entries.iter().map(MapReport::value_summary).collect(),
            clear_below: self.clear_below.map(|w| self.clear_below(w)),
            checks: self
                .checks
                .iter()
                .map(|c| CheckSummary {
                    explained_fraction: c.explained_fraction(),
                    quiet_fraction: c.quiet_fraction(),
                    check: c.clone(),
                })
                .collect(),
            confirmation: self.confirmation.clone(),
        }
    }

    fn tables(&self) -> Vec<Table> {
        vec![
            self.bands_table(),
            self.lines_table(),
            self.values_table(),
            self.checks_table(),
        ]
    }
}

impl MapReport {
    /// `bands`: one row per unstable band of every value.
    fn bands_table(&self) -> Table {
        let rows: Vec<(&MapEntry, &UnstableBand)> = self
            .entries
            .iter()
            .flat_map(|e| e.run.bands.iter().map(move |b| (e, b)))
            .collect();
        let mut t = Table::new("bands");
        t.text("value", rows.iter().map(|(e, _)| e.value.text.clone()))
            .optional("value_si", rows.iter().map(|(e, _)| e.value.si))
            .numbers("opens_hz", rows.iter().map(|(_, b)| b.opens_hz))
            .numbers("closes_hz", rows.iter().map(|(_, b)| b.closes_hz))
            .numbers("span_low_hz", rows.iter().map(|(_, b)| b.span_hz[0]))
            .numbers("span_high_hz", rows.iter().map(|(_, b)| b.span_hz[1]))
            .text("opens", rows.iter().map(|(_, b)| b.opens.name()))
            .optional(
                "emerging_hz",
                rows.iter().map(|(_, b)| b.opens.emerging_hz()),
            )
            .text("closes", rows.iter().map(|(_, b)| b.closes.name()))
            .optional(
                "closing_emerging_hz",
                rows.iter().map(|(_, b)| b.closes.emerging_hz()),
            )
            .numbers(
                "coexisting_stable_fraction",
                rows.iter().map(|(_, b)| b.coexisting_fraction()),
            )
            .text(
                "growing",
                rows.iter().map(|(_, b)| growing_text(&b.growing)),
            )
            .optional(
                "largest_growth_per_s",
                rows.iter().map(|(_, b)| b.largest_growth_per_s),
            );
        t
    }

    /// `checks`: one row per value checked against its cascade.
    fn checks_table(&self) -> Table {
        let c = &self.checks;
        let mut t = Table::new("checks");
        t.text("value", c.iter().map(|x| x.value.clone()))
            .numbers("level_m", c.iter().map(|x| x.level_m))
            .counts("speeds", c.iter().map(|x| x.speeds))
            .counts("not_followed", c.iter().map(|x| x.not_followed))
            .counts("nsv_speeds", c.iter().map(|x| x.nsv_speeds))
            .counts("explained", c.iter().map(|x| x.explained))
            .numbers(
                "explained_fraction",
                c.iter().map(|x| x.explained_fraction()),
            )
            .counts("predicted_quiet", c.iter().map(|x| x.predicted_quiet))
            .counts("quiet_confirmed", c.iter().map(|x| x.quiet_confirmed))
            .numbers("quiet_fraction", c.iter().map(|x| x.quiet_fraction()))
            .optional(
                "cascade_sustained_hz",
                c.iter().map(|x| x.cascade_sustained_hz),
            )
            .optional("map_sustained_hz", c.iter().map(|x| x.map_sustained_hz))
            .counts("disagreements", c.iter().map(|x| x.disagreements.len()));
        t
    }

    /// `lines`: one row per resonance line of every value.
    fn lines_table(&self) -> Table {
        let rows: Vec<(&MapEntry, &ResonanceLine)> = self
            .entries
            .iter()
            .flat_map(|e| e.run.lines.iter().map(move |l| (e, l)))
            .collect();
        let other = |l: &ResonanceLine| match l.excitation {
            Excitation::Sum { other_hz, .. } | Excitation::Difference { other_hz } => {
                Some(other_hz)
            }
            _ => None,
        };
        let mut t = Table::new("lines");
        t.text("value", rows.iter().map(|(e, _)| e.value.text.clone()))
            .optional("value_si", rows.iter().map(|(e, _)| e.value.si))
            .numbers("speed_hz", rows.iter().map(|(_, l)| l.speed_hz))
            .text("excitation", rows.iter().map(|(_, l)| l.excitation.name()))
            .numbers("response_hz", rows.iter().map(|(_, l)| l.response_hz))
            .numbers("mode_hz", rows.iter().map(|(_, l)| l.mode_hz))
            .optional("other_mode_hz", rows.iter().map(|(_, l)| other(l)))
            .numbers("damping_ratio", rows.iter().map(|(_, l)| l.damping_ratio))
            .bits(
                "on_stable_orbit",
                rows.iter().map(|(_, l)| l.on_stable_orbit),
            );
        t
    }

    /// `values`: one row per value, its first loss of stability and cost.
    fn values_table(&self) -> Table {
        let e = &self.entries;
        let first = |x: &MapEntry| x.first_loss().map(|b| hz(b.frequency));
        let lowest = |x: &MapEntry| {
            x.run
                .bands
                .iter()
                .map(|b| b.span_hz[0])
                .min_by(f64::total_cmp)
        };
        let mut t = Table::new("values");
        t.text("value", e.iter().map(|x| x.value.text.clone()))
            .optional("value_si", e.iter().map(|x| x.value.si))
            .optional("first_stability_loss_hz", e.iter().map(first))
            .text(
                "first_loss_kind",
                e.iter()
                    .map(|x| x.first_loss().map_or("", |b| b.kind.name())),
            )
            .counts("bands", e.iter().map(|x| x.run.bands.len()))
            .optional("lowest_unstable_hz", e.iter().map(lowest))
            .optional("cpu_s", e.iter().map(|x| x.run.cpu_s))
            .numbers("wall_s", e.iter().map(|x| x.run.wall_s))
            .bits("failed", e.iter().map(|x| x.run.failed()));
        t
    }
}
