//! What a frequency response reports ([`crate::report`]): the FRFs of each output and
//! their resonance peaks, as `whirl frf` writes them.

use serde::Serialize;

use super::{FrfKind, FrfResult};
use crate::report::{Report, Table};
use crate::units::rad_s_to_hz as hz;

/// FRFs with the amplitude of the harmonic force that the response columns are for.
#[derive(Debug, Clone)]
pub struct FrfReport {
    /// The FRFs.
    pub result: FrfResult,
    /// Amplitude of the harmonic force, N.
    pub force: f64,
}

/// The key numbers of an [`FrfReport`].
#[derive(Debug, Clone, Serialize)]
pub struct FrfSummary {
    /// Spin speed, Hz.
    pub speed_hz: f64,
    /// Spin speed, rpm.
    pub speed_rpm: f64,
    /// The input DOF.
    pub input: String,
    /// Force amplitude, N.
    pub force_n: f64,
    /// First and last frequency, Hz.
    pub frequency_range_hz: [f64; 2],
    /// Frequencies.
    pub frequency_count: usize,
    /// Each output's peaks.
    pub outputs: Vec<OutputPeaks>,
}

/// The resonance peaks of one output.
#[derive(Debug, Clone, Serialize)]
pub struct OutputPeaks {
    /// The output DOF.
    pub output: String,
    /// Its receptance peaks.
    pub peaks: Vec<PeakSummary>,
    /// Local maxima within the curve's round-off, which are no peaks, Hz (fine meshes).
    pub maxima_within_round_off_hz: Vec<f64>,
}

/// One receptance peak.
#[derive(Debug, Clone, Serialize)]
pub struct PeakSummary {
    /// Frequency, Hz.
    pub frequency_hz: f64,
    /// Receptance magnitude, m/N.
    pub receptance_m_per_n: f64,
    /// Response amplitude under the force, m.
    pub response_m: f64,
    /// Half-power band, Hz.
    pub half_power_hz: Option<[f64; 2]>,
    /// Amplification factor.
    pub amplification_factor: Option<f64>,
}

impl Report for FrfReport {
    type Summary = FrfSummary;

    fn summary(&self) -> FrfSummary {
        let (r, force) = (&self.result, self.force);
        let f = &r.frequencies_hz;
        FrfSummary {
            speed_hz: hz(r.speed),
            speed_rpm: 60.0 * hz(r.speed),
            input: r.input.1.clone(),
            force_n: force,
            frequency_range_hz: [
                f.first().copied().unwrap_or(f64::NAN),
                f.last().copied().unwrap_or(f64::NAN),
            ],
            frequency_count: f.len(),
            outputs: r
                .outputs
                .iter()
                .map(|o| OutputPeaks {
                    output: o.name.clone(),
                    peaks: o
                        .peaks
                        .iter()
                        .map(|p| PeakSummary {
                            frequency_hz: p.speed_hz,
                            receptance_m_per_n: p.amplitude,
                            response_m: p.amplitude * force,
                            half_power_hz: p.half_power_hz.map(|(a, b)| [a, b]),
                            amplification_factor: p.amplification_factor,
                        })
                        .collect(),
                    maxima_within_round_off_hz: o.maxima_within_round_off_hz.clone(),
                })
                .collect(),
        }
    }

    /// `frf` (per output the receptance, mobility and accelerance as real part, imaginary
    /// part, magnitude and phase, and the response amplitude to the force) and `peaks` (the
    /// resonance peaks of each receptance with half-power bands).
    fn tables(&self) -> Vec<Table> {
        let r = &self.result;
        let k = 0..r.frequencies_hz.len();
        let mut frf = Table::new("frf");
        frf.numbers("frequency_hz", r.frequencies_hz.iter().copied());
        for (j, o) in r.outputs.iter().enumerate() {
            for kind in FrfKind::ALL {
                let name = |part: &str| format!("{}_{}_{part}", o.name, kind.name());
                let v = |k| r.value(kind, j, k);
                frf.numbers(name("re"), k.clone().map(|k| v(k).re))
                    .numbers(name("im"), k.clone().map(|k| v(k).im))
                    .numbers(name("magnitude"), k.clone().map(|k| v(k).norm()))
                    .numbers(
                        name("phase_deg"),
                        k.clone().map(|k| v(k).arg().to_degrees()),
                    );
            }
            frf.numbers(
                format!("{}_response_amplitude", o.name),
                o.receptance.iter().map(|x| x.norm() * self.force),
            );
        }
        let peaks: Vec<_> = r
            .outputs
            .iter()
            .flat_map(|o| o.peaks.iter().map(move |p| (o.name.as_str(), p)))
            .collect();
        let mut table = Table::new("peaks");
        table
            .text("output", peaks.iter().map(|(o, _)| *o))
            .numbers("frequency_hz", peaks.iter().map(|(_, p)| p.speed_hz))
            .numbers(
                "receptance_magnitude",
                peaks.iter().map(|(_, p)| p.amplitude),
            )
            .optional(
                "half_power_low_hz",
                peaks.iter().map(|(_, p)| p.half_power_hz.map(|b| b.0)),
            )
            .optional(
                "half_power_high_hz",
                peaks.iter().map(|(_, p)| p.half_power_hz.map(|b| b.1)),
            )
            .optional(
                "amplification_factor",
                peaks.iter().map(|(_, p)| p.amplification_factor),
            );
        vec![frf, table]
    }
}
