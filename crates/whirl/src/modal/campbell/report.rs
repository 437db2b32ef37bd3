//! What a Campbell diagram reports ([`crate::report`]): its branches by label and the
//! critical speeds, as `whirl campbell` writes them.

use serde::Serialize;

use super::CampbellResult;
use crate::modal::{branch_labels, Whirl};
use crate::report::{Report, Table};

/// The key numbers of a [`CampbellResult`].
#[derive(Debug, Clone, Serialize)]
pub struct CampbellSummary {
    /// First and last speed, Hz.
    pub speed_range_hz: [Option<f64>; 2],
    /// Speeds.
    pub speed_count: usize,
    /// Excitation orders.
    pub orders: Vec<f64>,
    /// Modes in the basis (the full system's size without one).
    pub basis_size: usize,
    /// The branches.
    pub branches: Vec<BranchSummary>,
    /// The critical speeds.
    pub critical_speeds: Vec<CriticalSummary>,
}

/// One branch.
#[derive(Debug, Clone, Serialize)]
pub struct BranchSummary {
    /// `1F`, `1B`, ...
    pub label: String,
    /// Whirl direction at the last speed.
    pub whirl: Whirl,
    /// Damped natural frequency at the first speed, Hz.
    pub frequency_at_first_speed_hz: Option<f64>,
    /// The same at the last speed, Hz.
    pub frequency_at_last_speed_hz: Option<f64>,
    /// The smallest logarithmic decrement over speed.
    pub min_log_decrement: f64,
}

/// One critical speed, with its branch by label.
#[derive(Debug, Clone, Serialize)]
pub struct CriticalSummary {
    /// Speed, Hz.
    pub speed_hz: f64,
    /// Speed, rpm.
    pub speed_rpm: f64,
    /// Natural frequency there, Hz.
    pub frequency_hz: f64,
    /// Excitation order.
    pub order: f64,
    /// Branch label.
    pub branch: String,
    /// Whirl direction.
    pub whirl: Whirl,
    /// Damping ratio.
    pub damping_ratio: f64,
}

impl CampbellResult {
    /// The branches' labels by whirl direction and rank: `1F`, `1B`, ...
    pub fn labels(&self) -> Vec<String> {
        branch_labels(&self.branches.iter().map(|b| b.whirl).collect::<Vec<_>>())
    }

    /// The label of branch index `branch` ([`super::ModeBranch::index`]).
    pub fn label_of(&self, branch: usize) -> String {
        self.branches
            .iter()
            .position(|b| b.index == branch)
            .map(|i| self.labels()[i].clone())
            .unwrap_or_else(|| format!("branch {branch}"))
    }
}

impl Report for CampbellResult {
    type Summary = CampbellSummary;

    fn summary(&self) -> CampbellSummary {
        let speeds_hz = &self.speeds_hz;
        CampbellSummary {
            speed_range_hz: [speeds_hz.first().copied(), speeds_hz.last().copied()],
            speed_count: speeds_hz.len(),
            orders: self.orders.clone(),
            basis_size: self.basis_size,
            branches: self
                .branches
                .iter()
                .zip(self.labels())
                .map(|(b, label)| BranchSummary {
                    label,
                    whirl: b.whirl,
                    frequency_at_first_speed_hz: b.frequency_hz.first().copied(),
                    frequency_at_last_speed_hz: b.frequency_hz.last().copied(),
                    min_log_decrement: b
                        .log_decrement
                        .iter()
                        .copied()
                        .filter(|x| x.is_finite())
                        .fold(f64::INFINITY, f64::min),
                })
                .collect(),
            critical_speeds: self
                .critical_speeds
                .iter()
                .map(|c| CriticalSummary {
                    speed_hz: c.speed_hz,
                    speed_rpm: c.speed_rpm,
                    frequency_hz: c.frequency_hz,
                    order: c.order,
                    branch: self.label_of(c.branch),
                    whirl: c.whirl,
                    damping_ratio: c.damping_ratio,
                })
                .collect(),
        }
    }

    /// `campbell` (one row per speed; per branch its damped frequency, damping ratio, log
    /// decrement and whirl direction, empty where the branch is lost) and `critical_speeds`
    /// (crossings of the branches with the excitation orders).
    fn tables(&self) -> Vec<Table> {
        let speeds = &self.speeds_hz;
        let mut campbell = Table::new("campbell");
        campbell
            .numbers("speed_hz", speeds.iter().copied())
            .numbers("speed_rpm", speeds.iter().map(|f| 60.0 * f));
        for (b, l) in self.branches.iter().zip(self.labels()) {
            campbell
                .numbers(format!("{l}_frequency_hz"), b.frequency_hz.iter().copied())
                .numbers(
                    format!("{l}_damping_ratio"),
                    b.damping_ratio.iter().copied(),
                )
                .numbers(
                    format!("{l}_log_decrement"),
                    b.log_decrement.iter().copied(),
                )
                .text(
                    format!("{l}_whirl"),
                    b.frequency_hz.iter().zip(&b.whirl_at).map(|(f, w)| {
                        if f.is_finite() {
                            w.name()
                        } else {
                            ""
                        }
                    }),
                );
        }
        let c = &self.critical_speeds;
        let mut critical = Table::new("critical_speeds");
        critical
            .numbers("speed_hz", c.iter().map(|c| c.speed_hz))
            .numbers("speed_rpm", c.iter().map(|c| c.speed_rpm))
            .numbers("frequency_hz", c.iter().map(|c| c.frequency_hz))
            .numbers("order", c.iter().map(|c| c.order))
            .text("branch", c.iter().map(|c| self.label_of(c.branch)))
            .text("whirl", c.iter().map(|c| c.whirl.name()))
            .numbers("damping_ratio", c.iter().map(|c| c.damping_ratio));
        vec![campbell, critical]
    }
}
