//! What a harmonic-balance run reports ([`crate::report`]): the branch over speed, its
//! bifurcations, the time-marching comparisons and the harmonic-count study, as `whirl hbm`
//! writes them.

use serde::Serialize;

use super::{
    AtSpeed, Bifurcation, BifurcationKind, BranchEnd, SettledResponse, Sweep, SweepOptions,
    RESOLUTION_TOLERANCE,
};
use crate::fe::{dof, Direction};
use crate::report::{Report, Table};
use crate::units::rad_s_to_hz as hz;

/// A sweep with what was read against it.
#[derive(Debug, Clone)]
pub struct SweepReport {
    /// What was solved.
    pub options: SweepOptions,
    /// The branch over speed.
    pub sweep: Sweep,
    /// Nodes whose harmonics the branch table gives; the first is the one compared and
    /// studied.
    pub nodes: Vec<usize>,
    /// Time-marching runs at some of [`SweepOptions::exact_speeds`].
    pub comparisons: Vec<SettledResponse>,
    /// The same sweep (without stability) for other harmonic counts: (H, sweep).
    pub study: Vec<(usize, Sweep)>,
}

/// The key numbers of a [`SweepReport`].
#[derive(Debug, Clone, Serialize)]
pub struct SweepSummary {
    /// How the bearings were modelled.
    pub bearings: String,
    /// Harmonics H.
    pub harmonics: usize,
    /// Time samples per period of the transform.
    pub samples_per_period: usize,
    /// First and last speed, Hz.
    pub speed_range_hz: [f64; 2],
    /// Branch points.
    pub points: usize,
    /// The lowest and the highest speed of the branch points, Hz: wider than
    /// `speed_range_hz` where the branch turned back out of the range and came back (its
    /// points out there are kept).
    pub branch_span_hz: [f64; 2],
    /// Why the branch stopped.
    pub end: String,
    /// The speed (Hz) the branch was followed up from to reach the first speed, where
    /// Newton from the static equilibrium did not converge at it; `None` when it did.
    pub approached_from_hz: Option<f64>,
    /// Wall-clock time of the sweep, s.
    pub wall_time_s: f64,
    /// Whether the Floquet stability was computed.
    pub stability: bool,
    /// Fixed-interface modes of the stability model.
    pub stability_modes: usize,
    /// The model solved: full or Craig-Bampton.
    pub model: String,
    /// Nodes reported.
    pub nodes: Vec<usize>,
    /// Speeds of the turning points, Hz.
    pub folds_hz: Vec<f64>,
    /// Speeds where the path turned sharply, Hz.
    pub corners_hz: Vec<f64>,
    /// Stalls bridged by a restart: (from, to), Hz.
    pub jumps_hz: Vec<[f64; 2]>,
    /// Folds across which no real multiplier crosses +1, Hz: the stability contradicts
    /// the balance there (too few harmonics, docs/theory.md section 7).
    pub folds_without_crossing_hz: Vec<f64>,
    /// Changes of stability.
    pub bifurcations: Vec<BifurcationSummary>,
    /// AFT samples per period of the bifurcations' resolution check (twice
    /// `samples_per_period`), when they were checked.
    pub resolution_samples: Option<usize>,
    /// Fixed-interface modes of the resolution check's stability model (twice
    /// `stability_modes`), when the bifurcations were checked.
    pub resolution_stability_modes: Option<usize>,
    /// Distance of the resolution check's two orbits from each bifurcation, relative to its
    /// speed.
    pub resolution_tolerance: f64,
    /// Speed of the first loss of stability, Hz.
    pub first_stability_loss_hz: Option<f64>,
    /// The time-marching comparisons.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub compare_time: Vec<ComparisonSummary>,
    /// The harmonic-count study.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub harmonics_study: Vec<StudySummary>,
}

/// One change of stability.
#[derive(Debug, Clone, Serialize)]
pub struct BifurcationSummary {
    /// Its name ([`BifurcationKind::name`]).
    pub kind: &'static str,
    /// Speed, Hz.
    pub speed_hz: f64,
    /// Frequency of the crossing exponent, Hz.
    pub exponent_frequency_hz: f64,
    /// Stability lost (true) or regained.
    pub loses_stability: bool,
    /// Located on the branch (false: the locator's trial points failed, along the arclength
    /// and at fixed speed, and the speed is interpolated between the two nearest branch
    /// points it reached).
    pub located: bool,
    /// The same change at twice the samples and stability modes
    /// ([`crate::hbm::resolution`]); `None` when not checked.
    pub resolved: Option<bool>,
    /// What the check found, when it was made.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub resolution_check: Option<CheckSummary>,
}

/// The two orbits of a bifurcation's resolution check ([`crate::hbm::Resolution`]).
#[derive(Debug, Clone, Serialize)]
pub struct CheckSummary {
    /// Their speeds before and after the bifurcation along the path, Hz.
    pub speeds_hz: [f64; 2],
    /// Their stability at twice the samples; `None` where Newton did not converge.
    pub stable: [Option<bool>; 2],
    /// The kind named by the unstable side's largest multiplier, when it is unstable.
    pub kind: Option<&'static str>,
}

/// A time-marching run read against the harmonic-balance solutions at its speed.
#[derive(Debug, Clone, Serialize)]
pub struct ComparisonSummary {
    /// Speed, Hz.
    pub speed_hz: f64,
    /// Node compared.
    pub node: usize,
    /// Every harmonic-balance solution at this speed, in path order.
    pub hb_solutions: Vec<SolutionSummary>,
    /// Stability of the solution compared ([`SweepReport::solutions_at`]).
    pub hb_stable: Option<bool>,
    /// 1X of u_y of the solution compared, m.
    pub hb_1x_uy_m: Option<f64>,
    /// 1X of u_y of the time response, m.
    pub time_1x_uy_m: f64,
    /// (harmonic balance - time) / time, %.
    pub difference_pct: Option<f64>,
    /// The largest non-synchronous peak of the time response.
    pub time_non_synchronous: Option<Peak>,
    /// What an unstable solution compared means.
    pub note: Option<String>,
}

/// One harmonic-balance solution at a compared speed.
#[derive(Debug, Clone, Serialize)]
pub struct SolutionSummary {
    /// The branch point it follows.
    pub after_point: usize,
    /// Floquet stability.
    pub stable: bool,
    /// Largest real part of the Floquet exponents, 1/s.
    pub max_real_exponent_per_s: f64,
    /// 1X of u_x, m.
    pub hb_1x_ux_m: f64,
    /// 1X of u_y, m.
    pub hb_1x_uy_m: f64,
    /// (harmonic balance - time) / time for 1X of u_y, %.
    pub difference_pct: f64,
}

/// A spectral peak.
#[derive(Debug, Clone, Serialize)]
pub struct Peak {
    /// Frequency, Hz.
    pub frequency_hz: f64,
    /// Amplitude, m.
    pub amplitude_m: f64,
}

/// One sweep of the harmonic-count study.
#[derive(Debug, Clone, Serialize)]
pub struct StudySummary {
    /// Harmonics H.
    pub harmonics: usize,
    /// Branch points.
    pub points: usize,
    /// Wall-clock time, s.
    pub wall_time_s: f64,
}

impl BifurcationKind {
    /// The kind's name, e.g. `period doubling`.
    pub fn name(self) -> &'static str {
        match self {
            BifurcationKind::Fold => "fold",
            BifurcationKind::SymmetryBreaking => "symmetry breaking",
            BifurcationKind::PeriodDoubling => "period doubling",
            BifurcationKind::NeimarkSacker => "Neimark-Sacker",
        }
    }
}

impl BranchEnd {
    /// Why the branch stopped, in words.
    pub fn reason(&self) -> String {
        match self {
            BranchEnd::Reached => "reached the last speed".into(),
            BranchEnd::LeftRange => "turned back below the first speed".into(),
            BranchEnd::PointLimit => "stopped at the point limit".into(),
            BranchEnd::EndNotConverged { message } => {
                format!("the last speed itself did not converge: {message}")
            }
            BranchEnd::StepTooSmall { frequency, message } => format!(
                "stopped at {:.3} Hz, the corrector failing at the smallest step: {message}",
                hz(*frequency)
            ),
        }
    }
}

impl SweepReport {
    /// The harmonic-balance solutions at exactly `speed`, in path order, and the one
    /// compared with time marching: the first stable one (time marching settles on a
    /// stable orbit), or the first when none is.
    pub fn solutions_at(&self, speed: f64) -> (Vec<&AtSpeed>, Option<&AtSpeed>) {
        let all: Vec<&AtSpeed> = self
            .sweep
            .at_speeds
            .iter()
            .filter(|a| a.speed == speed)
            .collect();
        let compared = all
            .iter()
            .find(|a| a.stability.stable)
            .or(all.first())
            .copied();
        (all, compared)
    }

    /// 1X of u_y at the comparison's node of solution `a`, m.
    pub fn hb_1x_uy(&self, a: &AtSpeed, c: &SettledResponse) -> f64 {
        self.sweep
            .amplitude_of(&a.coefficients, dof(c.node, Direction::Uy), 1)
    }

    fn comparison(&self, c: &SettledResponse) -> ComparisonSummary {
        let (all, compared) = self.solutions_at(c.speed);
        let hb_solutions = all
            .iter()
            .map(|a| {
                let hb = self.hb_1x_uy(a, c);
                SolutionSummary {
                    after_point: a.after,
                    stable: a.stability.stable,
                    max_real_exponent_per_s: a.stability.max_real,
                    hb_1x_ux_m: self.sweep.amplitude_of(
                        &a.coefficients,
                        dof(c.node, Direction::Ux),
                        1,
                    ),
                    hb_1x_uy_m: hb,
                    difference_pct: percent(hb, c.uy[0]),
                }
            })
            .collect();
        let hb = compared.map(|a| self.hb_1x_uy(a, c));
        ComparisonSummary {
            speed_hz: hz(c.speed),
            node: c.node,
            hb_solutions,
            hb_stable: compared.map(|a| a.stability.stable),
            hb_1x_uy_m: hb,
            time_1x_uy_m: c.uy[0],
            difference_pct: hb.map(|h| percent(h, c.uy[0])),
            time_non_synchronous: c.non_synchronous.map(|(frequency_hz, amplitude_m)| Peak {
                frequency_hz,
                amplitude_m,
            }),
            note: compared.and_then(|a| unstable_note(a, c)),
        }
    }
}

/// (a - b) / b in %.
fn percent(a: f64, b: f64) -> f64 {
    100.0 * (a - b) / b
}

/// What the comparison means when the harmonic-balance solution `a` is unstable: time
/// marching leaves it, and the difference is the non-synchronous vibration it settles
/// into.
pub fn unstable_note(a: &AtSpeed, c: &SettledResponse) -> Option<String> {
    if a.stability.stable {
        return None;
    }
    let nsv = c.non_synchronous.map_or_else(
        || "no non-synchronous peak was found in the time response".to_string(),
        |(f, amp)| {
            format!(
                "time marching shows a non-synchronous component of {:.3} um at {f:.2} Hz",
                1e6 * amp
            )
        },
    );
    Some(format!(
        "the harmonic-balance solution is unstable (largest Floquet exponent {:.3e} 1/s): \
         time marching leaves it, and the difference is the non-synchronous vibration; {nsv}",
        a.stability.max_real
    ))
}

/// What the summary says of one bifurcation, with its check at more samples when made.
fn bifurcation_summary(b: &Bifurcation) -> BifurcationSummary {
    BifurcationSummary {
        kind: b.kind.name(),
        speed_hz: hz(b.frequency),
        exponent_frequency_hz: hz(b.exponent_frequency),
        loses_stability: b.loses_stability,
        located: b.located,
        resolved: b.resolution.map(|r| r.resolved),
        resolution_check: b.resolution.map(|r| CheckSummary {
            speeds_hz: r.speeds.map(hz),
            stable: r.stable,
            kind: r.kind.map(BifurcationKind::name),
        }),
    }
}

impl Report for SweepReport {
    type Summary = SweepSummary;

    fn summary(&self) -> SweepSummary {
        let (options, branch) = (&self.options, &self.sweep.branch);
        let checked = branch.bifurcations.iter().find_map(|b| b.resolution);
        SweepSummary {
            bearings: self.sweep.bearings.clone(),
            harmonics: options.harmonics,
            samples_per_period: branch.options.samples,
            speed_range_hz: [hz(options.from), hz(options.to)],
            points: branch.points.len(),
            branch_span_hz: {
                let (lo, hi) = branch.speed_span();
                [hz(lo), hz(hi)]
            },
            end: branch.end.reason(),
            approached_from_hz: self.sweep.approached_from.map(hz),
            wall_time_s: self.sweep.wall_time_s,
            stability: options.stability,
            stability_modes: options.stability_modes,
            model: match options.reduction {
                Some(m) => format!("Craig-Bampton, {m} fixed-interface modes"),
                None => "full finite-element model".into(),
            },
            nodes: self.nodes.clone(),
            folds_hz: branch.folds.iter().map(|f| hz(f.frequency)).collect(),
            corners_hz: branch.corners.iter().map(|c| hz(*c)).collect(),
            jumps_hz: branch.jumps.iter().map(|(a, b)| [hz(*a), hz(*b)]).collect(),
            folds_without_crossing_hz: branch
                .folds_without_crossing
                .iter()
                .map(|w| hz(*w))
                .collect(),
            bifurcations: branch
                .bifurcations
                .iter()
                .map(bifurcation_summary)
                .collect(),
            resolution_samples: checked.map(|r| r.samples),
            resolution_stability_modes: checked.map(|_| 2 * options.stability_modes),
            resolution_tolerance: RESOLUTION_TOLERANCE,
            first_stability_loss_hz: branch.first_stability_loss().map(|b| hz(b.frequency)),
            compare_time: self
                .comparisons
                .iter()
                .map(|c| self.comparison(c))
                .collect(),
            harmonics_study: self
                .study
                .iter()
                .map(|(h, r)| StudySummary {
                    harmonics: *h,
                    points: r.branch.points.len(),
                    wall_time_s: r.wall_time_s,
                })
                .collect(),
        }
    }

    /// `branch`, `bifurcations`, and `compare_time` and `harmonics_study` when there are
    /// comparisons and a study.
    fn tables(&self) -> Vec<Table> {
        let mut tables = vec![self.branch_table(), self.bifurcation_table()];
        if !self.comparisons.is_empty() {
            tables.push(self.comparison_table());
        }
        if let (false, Some(&node)) = (self.study.is_empty(), self.nodes.first()) {
            tables.push(self.study_table(node));
        }
        tables
    }
}

impl SweepReport {
    /// One row per branch point in path order: speed, stability, largest real part of the
    /// Floquet exponents, Newton iterations, and per node the amplitude of the constant
    /// term and of each harmonic of u_x and u_y.
    fn branch_table(&self) -> Table {
        let (sweep, points) = (&self.sweep, &self.sweep.branch.points);
        let mut t = Table::new("branch");
        t.counts("point", 0..points.len())
            .numbers("speed_hz", points.iter().map(|p| hz(p.solution.frequency)))
            .flags(
                "stable",
                points
                    .iter()
                    .map(|p| p.stability.as_ref().map(|s| s.stable)),
            )
            .optional(
                "max_real_exponent_per_s",
                points
                    .iter()
                    .map(|p| p.stability.as_ref().map(|s| s.max_real)),
            )
            .counts("iterations", points.iter().map(|p| p.solution.iterations));
        for &n in &self.nodes {
            for (axis, d) in [("ux", Direction::Ux), ("uy", Direction::Uy)] {
                for r in 0..=sweep.harmonics() {
                    let name = match r {
                        0 => format!("n{n}_{axis}_mean_m"),
                        r => format!("n{n}_{axis}_{r}x_m"),
                    };
                    t.numbers(
                        name,
                        (0..points.len()).map(|i| sweep.amplitude(i, dof(n, d), r)),
                    );
                }
            }
        }
        t
    }

    /// Kind, speed and frequency of the crossing exponent of each bifurcation, whether it
    /// was located on the branch, and whether it is resolved at twice the samples (empty
    /// when not checked).
    fn bifurcation_table(&self) -> Table {
        let b = &self.sweep.branch.bifurcations;
        let mut t = Table::new("bifurcations");
        t.text("kind", b.iter().map(|b| b.kind.name()))
            .numbers("speed_hz", b.iter().map(|b| hz(b.frequency)))
            .numbers("speed_rpm", b.iter().map(|b| 60.0 * hz(b.frequency)))
            .numbers(
                "exponent_frequency_hz",
                b.iter().map(|b| hz(b.exponent_frequency)),
            )
            .text(
                "stability",
                b.iter().map(|b| {
                    if b.loses_stability {
                        "lost"
                    } else {
                        "regained"
                    }
                }),
            )
            .flags("located", b.iter().map(|b| Some(b.located)))
            .flags(
                "resolved",
                b.iter().map(|b| b.resolution.map(|r| r.resolved)),
            );
        t
    }

    /// One row per harmonic-balance solution at each compared speed.
    fn comparison_table(&self) -> Table {
        let rows: Vec<(&SettledResponse, &AtSpeed)> = self
            .comparisons
            .iter()
            .flat_map(|c| {
                self.solutions_at(c.speed)
                    .0
                    .into_iter()
                    .map(move |a| (c, a))
            })
            .collect();
        let one_x = |(c, a): &(&SettledResponse, &AtSpeed), d| {
            self.sweep.amplitude_of(&a.coefficients, dof(c.node, d), 1)
        };
        let mut t = Table::new("compare_time");
        t.numbers("speed_hz", rows.iter().map(|(c, _)| hz(c.speed)))
            .counts("node", rows.iter().map(|(c, _)| c.node))
            .counts("hb_after_point", rows.iter().map(|(_, a)| a.after))
            .flags(
                "hb_stable",
                rows.iter().map(|(_, a)| Some(a.stability.stable)),
            )
            .numbers("hb_1x_ux_m", rows.iter().map(|r| one_x(r, Direction::Ux)))
            .numbers("time_1x_ux_m", rows.iter().map(|(c, _)| c.ux[0]))
            .numbers("hb_1x_uy_m", rows.iter().map(|r| one_x(r, Direction::Uy)))
            .numbers("time_1x_uy_m", rows.iter().map(|(c, _)| c.uy[0]))
            .numbers(
                "uy_difference_pct",
                rows.iter()
                    .map(|r| percent(one_x(r, Direction::Uy), r.0.uy[0])),
            )
            .optional(
                "time_nsv_hz",
                rows.iter().map(|(c, _)| c.non_synchronous.map(|p| p.0)),
            )
            .optional(
                "time_nsv_m",
                rows.iter().map(|(c, _)| c.non_synchronous.map(|p| p.1)),
            );
        t
    }

    /// 1X of u_y at `node` over speed for each harmonic count of the study.
    fn study_table(&self, node: usize) -> Table {
        let uy = dof(node, Direction::Uy);
        let rows: Vec<(usize, &Sweep, usize)> = self
            .study
            .iter()
            .flat_map(|(h, r)| (0..r.branch.points.len()).map(move |i| (*h, r, i)))
            .collect();
        let mut t = Table::new("harmonics_study");
        t.counts("harmonics", rows.iter().map(|r| r.0))
            .numbers(
                "speed_hz",
                rows.iter()
                    .map(|(_, r, i)| hz(r.branch.points[*i].solution.frequency)),
            )
            .numbers(
                format!("n{node}_uy_1x_m"),
                rows.iter().map(|(_, r, i)| r.amplitude(*i, uy, 1)),
            );
        t
    }
}
