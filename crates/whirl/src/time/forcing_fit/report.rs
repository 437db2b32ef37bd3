//! What a forcing-function fit reports ([`crate::report`]): the law's coefficients with
//! their units, the fit quality per speed, and every sample with its fitted force, as
//! `whirl fit-forcing` writes them.

use serde::Serialize;

use super::ForcingFit;
use crate::bearing::valid_up_to;
use crate::model::{ForcingFunction, Model};
use crate::report::{Report, Table};
use crate::units::rad_s_to_hz as hz;

/// A fit of bearing `index`'s forcing function, with where the law stops giving force.
#[derive(Debug, Clone)]
pub struct ForcingFitReport {
    /// The roller bearing's index in file order.
    pub index: usize,
    /// The fit.
    pub fit: ForcingFit,
    /// The lowest speed at which the law gives no force, rad/s ([`valid_up_to`]).
    pub valid_up_to: Option<f64>,
    /// Why the law should not be used over the whole operating range, if it should not.
    pub warning: Option<String>,
}

/// The key numbers of a [`ForcingFitReport`].
#[derive(Debug, Clone, Serialize)]
pub struct ForcingFitSummary {
    /// The bearing fitted.
    pub bearing: BearingRef,
    /// The law, in words.
    pub law: &'static str,
    /// Its coefficients.
    pub coefficients: Coefficients,
    /// What was fitted.
    pub samples: &'static str,
    /// Coefficient of determination of the fit over every sample (log-log).
    pub r_squared: f64,
    /// Rms relative force error.
    pub rms_relative_error: f64,
    /// Samples.
    pub points: usize,
    /// Gauss-Newton iterations.
    pub iterations: usize,
    /// Time step of the simulations, s.
    pub time_step_s: f64,
    /// The fit at each speed.
    pub speeds: Vec<SpeedSummary>,
    /// The lowest speed at which the law gives no force, Hz.
    pub valid_up_to_hz: Option<f64>,
    /// Why the law should not be used over the whole operating range.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub warning: Option<String>,
}

/// A roller bearing by index and name.
#[derive(Debug, Clone, Serialize)]
pub struct BearingRef {
    /// Index in file order.
    pub index: usize,
    /// Name.
    pub name: String,
}

/// A coefficient with its SI unit.
#[derive(Debug, Clone, Serialize)]
pub struct Coefficient {
    /// Value.
    pub value: f64,
    /// Unit (W in rad/s).
    pub unit: &'static str,
}

/// The four coefficients of the law.
#[derive(Debug, Clone, Serialize)]
pub struct Coefficients {
    /// a0, N/m^b.
    pub a0: Coefficient,
    /// a1, N/m^b per rad/s.
    pub a1: Coefficient,
    /// b0.
    pub b0: Coefficient,
    /// b1, per rad/s.
    pub b1: Coefficient,
}

/// The fit at one speed.
#[derive(Debug, Clone, Serialize)]
pub struct SpeedSummary {
    /// Speed, Hz.
    pub speed_hz: f64,
    /// Speed, rad/s.
    pub speed_rad_s: f64,
    /// Samples in contact.
    pub points: usize,
    /// Samples out of contact.
    pub excluded: usize,
    /// Coefficient of determination of the common law at this speed.
    pub r_squared: f64,
    /// Its rms relative force error.
    pub rms_relative_error: f64,
    /// Coefficient of a power law fitted at this speed alone.
    pub own_coefficient: f64,
    /// Its exponent.
    pub own_exponent: f64,
    /// Wall-clock time of this speed's simulation, s.
    pub wall_time_s: f64,
}

impl ForcingFitReport {
    /// The report of `fit` of `model`'s bearing `index`: warns when the law gives no force
    /// below the model's top operating speed.
    pub fn new(model: &Model, index: usize, fit: ForcingFit) -> ForcingFitReport {
        let valid_up_to = valid_up_to(&fit.law);
        let warning = valid_up_to
            .zip(model.operating.map(|o| o.1))
            .filter(|(limit, top)| limit < top)
            .map(|(limit, top)| {
                format!(
                    "the law's coefficient or exponent reaches zero at {:.1} Hz, below the \
                     top operating speed {:.1} Hz: above it the bearing would carry nothing; \
                     fit over speeds that reach the top of the range",
                    hz(limit),
                    hz(top)
                )
            });
        ForcingFitReport {
            index,
            fit,
            valid_up_to,
            warning,
        }
    }
}

fn coefficients(law: &ForcingFunction) -> Coefficients {
    let c = |value, unit| Coefficient { value, unit };
    Coefficients {
        a0: c(law.a0, "N/m^b"),
        a1: c(law.a1, "N/m^b per rad/s"),
        b0: c(law.b0, "1"),
        b1: c(law.b1, "1 per rad/s"),
    }
}

impl Report for ForcingFitReport {
    type Summary = ForcingFitSummary;

    fn summary(&self) -> ForcingFitSummary {
        let fit = &self.fit;
        ForcingFitSummary {
            bearing: BearingRef {
                index: self.index,
                name: fit.bearing.clone(),
            },
            law: "F = (a0 + a1 W) (u_r - gamma)_+^(b0 + b1 W)",
            coefficients: coefficients(&fit.law),
            samples: "cage-averaged elastic Hertz force at the recorded bearing deflection",
            r_squared: fit.r_squared,
            rms_relative_error: fit.rms_relative_error,
            points: fit.points.len(),
            iterations: fit.iterations,
            time_step_s: fit.step,
            speeds: fit
                .speeds
                .iter()
                .map(|s| SpeedSummary {
                    speed_hz: hz(s.speed),
                    speed_rad_s: s.speed,
                    points: s.points,
                    excluded: s.excluded,
                    r_squared: s.r_squared,
                    rms_relative_error: s.rms_relative_error,
                    own_coefficient: s.coefficient,
                    own_exponent: s.exponent,
                    wall_time_s: s.wall_time_s,
                })
                .collect(),
            valid_up_to_hz: self.valid_up_to.map(hz),
            warning: self.warning.clone(),
        }
    }

    /// `fit`: every sample (speed, deflection, force, fitted force).
    fn tables(&self) -> Vec<Table> {
        let (fit, p) = (&self.fit, &self.fit.points);
        let mut t = Table::new("fit");
        t.numbers("speed_hz", p.iter().map(|p| hz(p.speed)))
            .numbers("speed_rad_s", p.iter().map(|p| p.speed))
            .numbers("deflection_m", p.iter().map(|p| p.deflection))
            .numbers("force_n", p.iter().map(|p| p.force))
            .numbers("fitted_force_n", p.iter().map(|p| fit.fitted(p)));
        vec![t]
    }
}
