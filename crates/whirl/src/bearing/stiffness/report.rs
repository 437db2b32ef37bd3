//! What a stiffness study reports ([`crate::report`]): the three stiffnesses per clearance,
//! the passage samples and the force-deflection surfaces, as `whirl stiffness` writes them.

use serde::Serialize;

use super::{ClearanceStiffness, ForceSurface, Stiffness2, StiffnessStudy};
use crate::model::RollerBearing;
use crate::report::{index_list, Report, Table};

/// A stiffness study of one bearing with its force-deflection surfaces.
#[derive(Debug, Clone)]
pub struct StiffnessReport {
    /// The bearing studied.
    pub bearing: RollerBearing,
    /// Its stiffness versus clearance.
    pub study: StiffnessStudy,
    /// Where the load came from, in words.
    pub load_source: String,
    /// Force-deflection surfaces, one per clearance.
    pub surfaces: Vec<ForceSurface>,
}

/// What each kind of stiffness is.
#[derive(Debug, Clone, Serialize)]
pub struct Kinds {
    /// The frozen-cage equilibrium tangent.
    pub frozen: &'static str,
    /// The passage average.
    pub averaged: &'static str,
    /// The tangent at one displacement.
    pub fixed: &'static str,
}

/// The descriptions of the three stiffnesses.
pub const KINDS: Kinds = Kinds {
    frozen: "tangent at the static equilibrium under the load, cage frozen; with one roller on \
             the load line it does not depend on the clearance (statically determinate)",
    averaged: "mean of the equilibrium tangents over one roller passage (cage turned through \
               2 pi / N_b, equilibrium solved again at each position); it too does not depend \
               on the clearance while no more than two rollers carry the load \
               (most_rollers <= 2)",
    fixed: "tangent at the same journal displacement for every clearance: the frozen \
            equilibrium of the largest clearance; it falls as the clearance grows",
};

/// The key numbers of a [`StiffnessReport`].
#[derive(Debug, Clone, Serialize)]
pub struct StiffnessSummary {
    /// The bearing.
    pub bearing: BearingSummary,
    /// Load vector, N.
    pub load_n: [f64; 2],
    /// Its magnitude, N.
    pub load_magnitude_n: f64,
    /// Where it came from.
    pub load_source: String,
    /// Angle of roller 0 of the frozen cage, degrees.
    pub cage_angle_deg: f64,
    /// Cage positions of the passage average.
    pub cage_steps: usize,
    /// The displacement of the `fixed` stiffness, µm.
    pub fixed_displacement_um: [f64; 2],
    /// What each stiffness is.
    pub kinds: Kinds,
    /// Clearances at which no more than two rollers carry the load at any cage position, µm.
    pub statically_determinate_clearances_um: Vec<f64>,
    /// The stiffnesses at each clearance.
    pub clearances: Vec<ClearanceSummary>,
    /// The force-deflection surfaces.
    pub surfaces: Vec<SurfaceSummary>,
}

/// The bearing of a stiffness study.
#[derive(Debug, Clone, Serialize)]
pub struct BearingSummary {
    /// Name.
    pub name: String,
    /// Node.
    pub node: usize,
    /// Rollers.
    pub rollers: usize,
    /// Hertz contact stiffness, N/m^n.
    pub contact_stiffness: f64,
    /// Hertz exponent n.
    pub contact_exponent: f64,
    /// The model's clearance at rest, µm.
    pub model_clearance_at_rest_um: f64,
}

/// The three stiffnesses at one clearance.
#[derive(Debug, Clone, Serialize)]
pub struct ClearanceSummary {
    /// Clearance, µm.
    pub clearance_um: f64,
    /// At the frozen-cage equilibrium.
    pub frozen: FrozenSummary,
    /// Over one roller passage.
    pub averaged: AveragedSummary,
    /// At the fixed displacement.
    pub fixed: FixedSummary,
}

/// The frozen-cage equilibrium.
#[derive(Debug, Clone, Serialize)]
pub struct FrozenSummary {
    /// Journal displacement, µm.
    pub displacement_um: [f64; 2],
    /// The loaded rollers.
    pub rollers: Vec<RollerSummary>,
    /// Tangent stiffness.
    pub stiffness_n_per_m: Stiffness2,
    /// Newton iterations.
    pub newton_iterations: usize,
    /// Relative residual of the equilibrium.
    pub relative_residual: f64,
}

/// One loaded roller.
#[derive(Debug, Clone, Serialize)]
pub struct RollerSummary {
    /// Roller index.
    pub index: usize,
    /// Angle, degrees.
    pub angle_deg: f64,
    /// Approach, µm.
    pub approach_um: f64,
    /// Contact force, N.
    pub force_n: f64,
}

/// The passage average.
#[derive(Debug, Clone, Serialize)]
pub struct AveragedSummary {
    /// Mean journal displacement, µm.
    pub mean_displacement_um: [f64; 2],
    /// Most rollers loaded at once.
    pub most_rollers: usize,
    /// Mean tangent stiffness.
    pub stiffness_n_per_m: Stiffness2,
    /// Smallest entries over the passage.
    pub min_n_per_m: Stiffness2,
    /// Largest entries over the passage.
    pub max_n_per_m: Stiffness2,
}

/// The tangent at the fixed displacement.
#[derive(Debug, Clone, Serialize)]
pub struct FixedSummary {
    /// Loaded rollers.
    pub rollers: Vec<usize>,
    /// Bearing force, N.
    pub force_n: [f64; 2],
    /// Tangent stiffness.
    pub stiffness_n_per_m: Stiffness2,
}

/// One force-deflection surface.
#[derive(Debug, Clone, Serialize)]
pub struct SurfaceSummary {
    /// Clearance, µm.
    pub clearance_um: f64,
    /// Its table's file.
    pub file: String,
    /// Half-width of the grid, µm.
    pub extent_um: Option<f64>,
    /// Points per side of the grid.
    pub grid: usize,
    /// Largest radial force on the grid, N.
    pub largest_radial_force_n: f64,
}

/// "20um", "12.5um": a clearance for table names and labels.
pub fn clearance_label(c: f64) -> String {
    let text = format!("{:.3}", c * 1e6);
    format!("{}um", text.trim_end_matches('0').trim_end_matches('.'))
}

/// The name of the table of a surface at clearance `c`.
fn surface_table(c: f64) -> String {
    format!("surfaces_{}", clearance_label(c))
}

/// µm from m.
fn um(x: f64) -> f64 {
    x * 1e6
}

/// The four entries in table order.
fn entries(k: &Stiffness2) -> [f64; 4] {
    [k.kxx, k.kxy, k.kyx, k.kyy]
}

fn clearance_summary(c: &ClearanceStiffness) -> ClearanceSummary {
    let f = &c.frozen.tangent;
    ClearanceSummary {
        clearance_um: um(c.clearance),
        frozen: FrozenSummary {
            displacement_um: f.displacement.map(um),
            rollers: f
                .rollers
                .iter()
                .map(|r| RollerSummary {
                    index: r.index,
                    angle_deg: r.angle.to_degrees(),
                    approach_um: um(r.approach),
                    force_n: r.force,
                })
                .collect(),
            stiffness_n_per_m: f.stiffness,
            newton_iterations: c.frozen.iterations,
            relative_residual: c.frozen.relative_residual,
        },
        averaged: AveragedSummary {
            mean_displacement_um: c.averaged.mean_displacement.map(um),
            most_rollers: c.averaged.most_rollers,
            stiffness_n_per_m: c.averaged.mean,
            min_n_per_m: c.averaged.min,
            max_n_per_m: c.averaged.max,
        },
        fixed: FixedSummary {
            rollers: c.fixed.rollers.iter().map(|r| r.index).collect(),
            force_n: c.fixed.force,
            stiffness_n_per_m: c.fixed.stiffness,
        },
    }
}

impl StiffnessStudy {
    /// Clearances at which the equilibrium is statically determinate at every cage
    /// position (no more than two rollers carry the load), m.
    pub fn determinate_clearances(&self) -> Vec<f64> {
        self.clearances
            .iter()
            .filter(|c| c.averaged.most_rollers <= 2)
            .map(|c| c.clearance)
            .collect()
    }
}

impl Report for StiffnessReport {
    type Summary = StiffnessSummary;

    fn summary(&self) -> StiffnessSummary {
        let (b, study) = (&self.bearing, &self.study);
        StiffnessSummary {
            bearing: BearingSummary {
                name: b.name.clone(),
                node: b.station.node,
                rollers: b.rollers,
                contact_stiffness: b.contact_stiffness,
                contact_exponent: b.contact_exponent,
                model_clearance_at_rest_um: um(b.clearance.at_speed(0.0)),
            },
            load_n: study.load,
            load_magnitude_n: study.load[0].hypot(study.load[1]),
            load_source: self.load_source.clone(),
            cage_angle_deg: study.cage_angle.to_degrees(),
            cage_steps: study.cage_steps,
            fixed_displacement_um: study.fixed_displacement.map(um),
            kinds: KINDS,
            statically_determinate_clearances_um: study
                .determinate_clearances()
                .into_iter()
                .map(um)
                .collect(),
            clearances: study.clearances.iter().map(clearance_summary).collect(),
            surfaces: self
                .surfaces
                .iter()
                .map(|f| SurfaceSummary {
                    clearance_um: um(f.clearance),
                    file: format!("{}.csv", surface_table(f.clearance)),
                    extent_um: f.ux.last().copied().map(um),
                    grid: f.ux.len(),
                    largest_radial_force_n: f.fr.iter().flatten().copied().fold(0.0, f64::max),
                })
                .collect(),
        }
    }

    /// `stiffness` (one row per clearance), `passage` (one row per clearance and cage
    /// position) and `surfaces_<clearance>` (one per surface).
    fn tables(&self) -> Vec<Table> {
        let mut tables = vec![self.stiffness_table(), self.passage_table()];
        tables.extend(self.surfaces.iter().map(surface_table_of));
        tables
    }
}

/// The four stiffness columns `<prefix>k.._n_per_m` of `values`.
fn stiffness_columns<'a>(
    t: &mut Table,
    prefix: &str,
    values: impl Iterator<Item = &'a Stiffness2> + Clone,
) {
    for (e, name) in ["kxx", "kxy", "kyx", "kyy"].iter().enumerate() {
        t.numbers(
            format!("{prefix}{name}_n_per_m"),
            values.clone().map(|k| entries(k)[e]),
        );
    }
}

impl StiffnessReport {
    fn stiffness_table(&self) -> Table {
        let c = &self.study.clearances;
        let mut t = Table::new("stiffness");
        t.numbers("clearance_um", c.iter().map(|c| um(c.clearance)));
        for (i, axis) in ["ux", "uy"].iter().enumerate() {
            t.numbers(
                format!("frozen_{axis}_um"),
                c.iter().map(|c| um(c.frozen.tangent.displacement[i])),
            );
        }
        t.text(
            "frozen_rollers",
            c.iter()
                .map(|c| index_list(c.frozen.tangent.rollers.iter().map(|r| r.index))),
        );
        stiffness_columns(
            &mut t,
            "frozen_",
            c.iter().map(|c| &c.frozen.tangent.stiffness),
        );
        for (i, axis) in ["ux", "uy"].iter().enumerate() {
            t.numbers(
                format!("averaged_{axis}_um"),
                c.iter().map(|c| um(c.averaged.mean_displacement[i])),
            );
        }
        t.counts(
            "averaged_most_rollers",
            c.iter().map(|c| c.averaged.most_rollers),
        );
        stiffness_columns(&mut t, "averaged_", c.iter().map(|c| &c.averaged.mean));
        t.numbers(
            "averaged_kxx_min_n_per_m",
            c.iter().map(|c| c.averaged.min.kxx),
        )
        .numbers(
            "averaged_kxx_max_n_per_m",
            c.iter().map(|c| c.averaged.max.kxx),
        )
        .numbers(
            "averaged_kyy_min_n_per_m",
            c.iter().map(|c| c.averaged.min.kyy),
        )
        .numbers(
            "averaged_kyy_max_n_per_m",
            c.iter().map(|c| c.averaged.max.kyy),
        )
        .text(
            "fixed_rollers",
            c.iter()
                .map(|c| index_list(c.fixed.rollers.iter().map(|r| r.index))),
        )
        .numbers("fixed_fx_n", c.iter().map(|c| c.fixed.force[0]))
        .numbers("fixed_fy_n", c.iter().map(|c| c.fixed.force[1]));
        stiffness_columns(&mut t, "fixed_", c.iter().map(|c| &c.fixed.stiffness));
        t
    }

    fn passage_table(&self) -> Table {
        let rows: Vec<(f64, &super::PassageSample)> = self
            .study
            .clearances
            .iter()
            .flat_map(|c| c.averaged.samples.iter().map(move |s| (c.clearance, s)))
            .collect();
        let mut t = Table::new("passage");
        t.numbers("clearance_um", rows.iter().map(|(c, _)| um(*c)))
            .numbers(
                "cage_angle_deg",
                rows.iter().map(|(_, s)| s.cage_angle.to_degrees()),
            )
            .numbers("ux_um", rows.iter().map(|(_, s)| um(s.displacement[0])))
            .numbers("uy_um", rows.iter().map(|(_, s)| um(s.displacement[1])))
            .text(
                "rollers",
                rows.iter()
                    .map(|(_, s)| index_list(s.rollers.iter().copied())),
            );
        stiffness_columns(&mut t, "", rows.iter().map(|(_, s)| &s.stiffness));
        t
    }
}

/// The surface on its grid, row by row of u_y.
fn surface_table_of(surface: &ForceSurface) -> Table {
    let cells: Vec<(usize, usize)> = (0..surface.uy.len())
        .flat_map(|j| (0..surface.ux.len()).map(move |i| (j, i)))
        .collect();
    let mut t = Table::new(surface_table(surface.clearance));
    t.numbers("ux_um", cells.iter().map(|&(_, i)| um(surface.ux[i])))
        .numbers("uy_um", cells.iter().map(|&(j, _)| um(surface.uy[j])))
        .numbers("fx_n", cells.iter().map(|&(j, i)| surface.fx[j][i]))
        .numbers("fy_n", cells.iter().map(|&(j, i)| surface.fy[j][i]))
        .numbers("fr_n", cells.iter().map(|&(j, i)| surface.fr[j][i]))
        .counts(
            "rollers_in_contact",
            cells.iter().map(|&(j, i)| surface.contacts[j][i]),
        );
    t
}
