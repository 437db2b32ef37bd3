//! What a static response reports ([`crate::report`]): the largest deflection, moment and
//! shear, the reactions against the weight, and the station, reaction and roller tables, as
//! `whirl static` writes them.

use serde::Serialize;

use super::{RollerSupport, StaticResult, Station};
use crate::bearing::BearingLife;
use crate::report::{Report, Table};

/// The key numbers of a [`StaticResult`].
#[derive(Debug, Clone, Serialize)]
pub struct StaticSummary {
    /// Gravity, m/s^2.
    pub gravity_m_s2: f64,
    /// How roller bearings carried the load.
    pub roller_support: RollerSupport,
    /// Weight of the rotor, N.
    pub weight_n: f64,
    /// The largest deflection.
    pub max_deflection: Largest,
    /// The largest bending moment.
    pub max_bending_moment: Largest,
    /// The largest shear force.
    pub max_shear_force: Largest,
    /// Each bearing's reaction.
    pub reactions: Vec<ReactionSummary>,
    /// Sum of the reactions, [x, y], N.
    pub reaction_sum_n: [f64; 2],
    /// Its y part over the weight (1 in equilibrium).
    pub reaction_sum_over_weight: f64,
}

/// The largest value of a quantity along the shaft and where it is.
#[derive(Debug, Clone, Serialize)]
pub struct Largest {
    /// The value, named by its quantity and unit.
    #[serde(flatten)]
    pub value: Named,
    /// Node.
    pub node: usize,
    /// Axial position, m.
    pub z_m: f64,
}

/// A value under the name of its quantity.
#[derive(Debug, Clone, Serialize)]
pub enum Named {
    /// Deflection, m.
    #[serde(rename = "deflection_m")]
    Deflection(f64),
    /// Bending moment, N m.
    #[serde(rename = "moment_nm")]
    Moment(f64),
    /// Shear force, N.
    #[serde(rename = "shear_n")]
    Shear(f64),
}

/// One bearing's reaction.
#[derive(Debug, Clone, Serialize)]
pub struct ReactionSummary {
    /// Bearing name.
    pub bearing: String,
    /// Node.
    pub node: usize,
    /// Axial position, m.
    pub z_m: f64,
    /// Kind of bearing.
    pub kind: &'static str,
    /// Journal displacement, m.
    pub displacement_m: [f64; 2],
    /// Force on the shaft, N.
    pub force_n: [f64; 2],
    /// Rollers carrying load.
    pub rollers_loaded: usize,
    /// The largest roller load, N (roller bearings with Hertz contacts).
    pub max_roller_load_n: Option<f64>,
    /// Fatigue life under this load (roller and ball bearings with Hertz contacts).
    pub life: Option<BearingLife>,
}

impl StaticResult {
    /// Index of the station with the largest `f`, and that value.
    pub fn largest(&self, f: impl Fn(&Station) -> f64) -> (usize, f64) {
        self.stations
            .iter()
            .map(f)
            .enumerate()
            .fold(
                (0, f64::NEG_INFINITY),
                |a, (i, v)| if v > a.1 { (i, v) } else { a },
            )
    }

    /// The station with the largest bending moment (magnitude) and that moment, N m.
    pub fn largest_moment(&self) -> (usize, f64) {
        self.largest(|st| st.moment[1].hypot(st.moment[0]))
    }

    /// The station with the largest shear force (magnitude) and that force, N.
    pub fn largest_shear(&self) -> (usize, f64) {
        self.largest(|st| st.shear[1].hypot(st.shear[0]))
    }

    fn at_station(&self, (i, value): (usize, f64), named: fn(f64) -> Named) -> Largest {
        Largest {
            value: named(value),
            node: self.stations[i].node,
            z_m: self.stations[i].z,
        }
    }

    /// True when some roller bearing reports its roller loads.
    pub fn has_rollers(&self) -> bool {
        self.reactions.iter().any(|r| !r.rollers.is_empty())
    }
}

impl Report for StaticResult {
    type Summary = StaticSummary;

    fn summary(&self) -> StaticSummary {
        let total = self.total_reaction();
        StaticSummary {
            gravity_m_s2: self.gravity,
            roller_support: self.roller_support,
            weight_n: self.weight,
            max_deflection: Largest {
                value: Named::Deflection(self.max_deflection.value),
                node: self.max_deflection.node,
                z_m: self.max_deflection.z,
            },
            max_bending_moment: self.at_station(self.largest_moment(), Named::Moment),
            max_shear_force: self.at_station(self.largest_shear(), Named::Shear),
            reactions: self
                .reactions
                .iter()
                .map(|r| ReactionSummary {
                    bearing: r.name.clone(),
                    node: r.node,
                    z_m: r.z,
                    kind: r.kind,
                    displacement_m: r.displacement,
                    force_n: r.force,
                    rollers_loaded: r.rollers.iter().filter(|q| q.force > 0.0).count(),
                    max_roller_load_n: r.rollers.iter().map(|q| q.force).reduce(f64::max),
                    life: r.life.clone(),
                })
                .collect(),
            reaction_sum_n: total,
            reaction_sum_over_weight: total[1] / self.weight,
        }
    }

    /// `stations` (deflection, slope, moment and shear at both ends of every element),
    /// `reactions` (each bearing's displacement and force on the shaft) and, when some
    /// roller bearing has Hertz contacts, `rollers` (each roller's angle, approach, load).
    fn tables(&self) -> Vec<Table> {
        let s = &self.stations;
        let mut stations = Table::new("stations");
        stations
            .numbers("z_m", s.iter().map(|s| s.z))
            .counts("node", s.iter().map(|s| s.node))
            .counts("element", s.iter().map(|s| s.element));
        let pairs = [
            ("u{}_m", s.iter().map(|s| s.deflection).collect::<Vec<_>>()),
            ("slope_{}_rad", s.iter().map(|s| s.slope).collect()),
            ("moment_{}_nm", s.iter().map(|s| s.moment).collect()),
            ("shear_{}_n", s.iter().map(|s| s.shear).collect()),
        ];
        for (pattern, values) in pairs {
            for (i, axis) in ["x", "y"].iter().enumerate() {
                stations.numbers(pattern.replace("{}", axis), values.iter().map(|v| v[i]));
            }
        }
        let r = &self.reactions;
        let mut reactions = Table::new("reactions");
        reactions
            .text("bearing", r.iter().map(|r| r.name.as_str()))
            .counts("node", r.iter().map(|r| r.node))
            .numbers("z_m", r.iter().map(|r| r.z))
            .text("kind", r.iter().map(|r| r.kind))
            .numbers("ux_m", r.iter().map(|r| r.displacement[0]))
            .numbers("uy_m", r.iter().map(|r| r.displacement[1]))
            .numbers("fx_n", r.iter().map(|r| r.force[0]))
            .numbers("fy_n", r.iter().map(|r| r.force[1]));
        let mut tables = vec![stations, reactions];
        if self.has_rollers() {
            let loads: Vec<_> = r
                .iter()
                .flat_map(|r| r.rollers.iter().enumerate().map(move |(j, q)| (r, j, q)))
                .collect();
            let mut rollers = Table::new("rollers");
            rollers
                .text("bearing", loads.iter().map(|(r, _, _)| r.name.as_str()))
                .counts("roller", loads.iter().map(|(_, j, _)| *j))
                .numbers("angle_deg", loads.iter().map(|(_, _, q)| q.angle_deg))
                .numbers("approach_m", loads.iter().map(|(_, _, q)| q.approach))
                .numbers("force_n", loads.iter().map(|(_, _, q)| q.force));
            tables.push(rollers);
        }
        tables
    }
}
