//! Time marching at one speed, read in the terms of a harmonic-balance point (thesis fig.
//! 4.27): the settled amplitude of each order of the running speed, and the largest
//! non-synchronous component, which harmonic balance in the running speed cannot hold.

use serde::Serialize;

use crate::bearing::ContactLaw;
use crate::error::Result;
use crate::model::Model;
use crate::nsv::{DEFAULT_RECORD, DEFAULT_SETTLE};
use crate::post::order_component;
use crate::system::SpeedProfile;
use crate::time::{simulate, SimulationOptions, DEFAULT_MODES};

/// How the time simulation runs.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct MarchSettings {
    /// Time discarded before the settled part, s.
    pub settle: f64,
    /// Settled time analysed, s.
    pub record: f64,
    /// Craig-Bampton fixed-interface modes of the integrated model.
    pub modes: usize,
    /// Contact law of the roller bearings.
    pub contact: ContactLaw,
}

impl Default for MarchSettings {
    /// The cascade's settling and recorded times on the reduced model with 12 modes and
    /// Hertz contacts: the thesis' cascade settings (section 5.1).
    fn default() -> Self {
        MarchSettings {
            settle: DEFAULT_SETTLE,
            record: DEFAULT_RECORD,
            modes: DEFAULT_MODES,
            contact: ContactLaw::Hertz,
        }
    }
}

/// What the settled time response shows at one node.
#[derive(Debug, Clone, Serialize)]
pub struct SettledResponse {
    /// Running speed, rad/s.
    pub speed: f64,
    /// Node.
    pub node: usize,
    /// Zero-to-peak amplitude of orders 1..=H of u_x, m (order tracking of the settled part).
    pub ux: Vec<f64>,
    /// Same for u_y, m.
    pub uy: Vec<f64>,
    /// Largest non-synchronous peak of u_y ([`crate::time::SettledChannel`]): (Hz, m).
    pub non_synchronous: Option<(f64, f64)>,
}

/// Simulates `model` at constant `speed` (rad/s) from static equilibrium and reads the
/// settled orders 1..=`harmonics` and the largest non-synchronous peak at `node`.
///
/// # Errors
/// As [`simulate`] (a diverged run is an error), or when the record is too short
/// for order tracking.
pub fn settled_response(
    model: &Model,
    speed: f64,
    node: usize,
    harmonics: usize,
    settings: &MarchSettings,
) -> Result<SettledResponse> {
    let mut options = SimulationOptions {
        duration: settings.settle + settings.record,
        contact: Some(settings.contact),
        reduction: Some(settings.modes),
        settle: Some(settings.settle),
        nodes: Some(vec![node]),
        record_rollers: false,
        ..SimulationOptions::new(SpeedProfile::Constant(speed))
    };
    // Recorded at about 20 kHz: well above the orders looked at, small to store.
    let step = options.time_step(model)?;
    options.step = Some(step);
    options.record_every = Some(((5e-5 / step).floor() as usize).max(1));
    let result = simulate(model, &options)?.completed()?;
    let start = result.settled_start();
    let angle: Vec<f64> = result.time[start..].iter().map(|t| speed * t).collect();
    let channel = |name: &str| {
        result
            .channels
            .iter()
            .find(|c| c.name == name)
            .map(|c| &c.values[start..])
    };
    let (Some(x), Some(y)) = (
        channel(&format!("n{node}.ux")),
        channel(&format!("n{node}.uy")),
    ) else {
        return Err(crate::Error::InvalidOption(format!(
            "node {node} was not recorded"
        )));
    };
    let orders = |signal: &[f64]| {
        (1..=harmonics)
            .map(|k| order_component(&angle, signal, k as f64).map(|c| c.amplitude))
            .collect::<Result<Vec<f64>>>()
    };
    // The settled-record analysis of `whirl simulate`: orders within 2 bins synchronous.
    let vertical = format!("n{node}.uy");
    let non_synchronous = result
        .settled(&options.speed)?
        .into_iter()
        .find(|c| c.name == vertical)
        .and_then(|c| c.non_synchronous)
        .map(|p| (p.frequency_hz, p.amplitude));
    Ok(SettledResponse {
        speed,
        node,
        ux: orders(x)?,
        uy: orders(y)?,
        non_synchronous,
    })
}
