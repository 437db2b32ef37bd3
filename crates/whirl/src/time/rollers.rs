//! Roller bearings in a time simulation: what each roller did at every recorded instant
//! (docs/theory.md sections 5-6, thesis figs. 4.7 and 4.9).
//!
//! A [`RollerRecord`] holds, per recorded sample and roller, the roller's angle theta_j,
//! its approach delta_j (positive = penetration, eq. 3.2 / 3.19) and its contact force
//! Q_j. The rollers' forces excite the rotor at the frequencies of
//! [`crate::bearing::contact_frequencies`]; [`peak_near`] finds the spectral peak that
//! shows each.

use std::ops::Range;

use serde::Serialize;

use crate::bearing::RollerGeometry;
use crate::model::RollerBearing;
use crate::post::{spectral_peaks, SpectralPeak, Spectrum};

/// What the rollers of one bearing did at each recorded sample. Per-sample arrays hold
/// `rollers` values per sample, sample after sample: roller j of sample i is at
/// `i * rollers + j`.
#[derive(Debug, Clone, Serialize)]
pub struct RollerRecord {
    /// The bearing's name.
    pub name: String,
    /// Its node.
    pub node: usize,
    /// Number of rollers N_b.
    pub rollers: usize,
    /// Cage speed per spin speed, (1 - D_b/D_p)/2.
    pub cage_ratio: f64,
    /// Roller angle theta_j, rad (not wrapped).
    pub angle: Vec<f64>,
    /// Roller approach delta_j, m: positive is penetration.
    pub approach: Vec<f64>,
    /// Roller contact force Q_j, N (>= 0); NaN when the law has no per-roller forces.
    pub force: Vec<f64>,
}

impl RollerRecord {
    /// An empty record of `bearing`.
    pub fn new(bearing: &RollerBearing, capacity: usize) -> Self {
        let geometry = RollerGeometry::new(bearing);
        let values = capacity * bearing.rollers;
        RollerRecord {
            name: bearing.name.clone(),
            node: bearing.station.node,
            rollers: bearing.rollers,
            cage_ratio: geometry.cage_ratio,
            angle: Vec::with_capacity(values),
            approach: Vec::with_capacity(values),
            force: Vec::with_capacity(values),
        }
    }

    /// Number of samples recorded.
    pub fn samples(&self) -> usize {
        self.angle.len() / self.rollers.max(1)
    }

    fn at<'a>(&self, values: &'a [f64], sample: usize) -> &'a [f64] {
        &values[sample * self.rollers..(sample + 1) * self.rollers]
    }

    /// Roller angles of sample `i`, rad.
    pub fn angles_at(&self, i: usize) -> &[f64] {
        self.at(&self.angle, i)
    }

    /// Roller approaches of sample `i`, m.
    pub fn approaches_at(&self, i: usize) -> &[f64] {
        self.at(&self.approach, i)
    }

    /// Roller forces of sample `i`, N.
    pub fn forces_at(&self, i: usize) -> &[f64] {
        self.at(&self.force, i)
    }

    /// Whether roller `j` touches at sample `i`: it carries load, or, for a law without
    /// per-roller forces, it penetrates.
    pub fn in_contact(&self, i: usize, j: usize) -> bool {
        let k = i * self.rollers + j;
        let force = self.force[k];
        if force.is_nan() {
            self.approach[k] > 0.0
        } else {
            force > 0.0
        }
    }

    /// Rollers in contact at sample `i`.
    pub fn contacts_at(&self, i: usize) -> usize {
        (0..self.rollers).filter(|&j| self.in_contact(i, j)).count()
    }

    /// Whether the record holds per-roller forces (not for the forcing-function law).
    pub fn has_forces(&self) -> bool {
        !self.force.iter().any(|f| f.is_nan())
    }

    /// Contact statistics over the samples `range`.
    pub fn summary(&self, range: Range<usize>) -> ContactSummary {
        let samples = range.len();
        let mut s = ContactSummary {
            samples,
            max_in_contact: 0,
            min_in_contact: if samples == 0 { 0 } else { usize::MAX },
            mean_in_contact: 0.0,
            largest_penetration: f64::NEG_INFINITY,
            largest_force: 0.0,
        };
        let mut total = 0usize;
        for i in range {
            let n = self.contacts_at(i);
            total += n;
            s.max_in_contact = s.max_in_contact.max(n);
            s.min_in_contact = s.min_in_contact.min(n);
            for (&a, &f) in self.approaches_at(i).iter().zip(self.forces_at(i)) {
                s.largest_penetration = s.largest_penetration.max(a);
                if f > s.largest_force {
                    s.largest_force = f;
                }
            }
        }
        if samples > 0 {
            s.mean_in_contact = total as f64 / samples as f64;
        }
        if !self.has_forces() {
            s.largest_force = f64::NAN;
        }
        s
    }
}

/// Contact statistics of one bearing over a stretch of samples.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ContactSummary {
    /// Samples counted.
    pub samples: usize,
    /// Most rollers in contact at once.
    pub max_in_contact: usize,
    /// Fewest rollers in contact at once.
    pub min_in_contact: usize,
    /// Rollers in contact, averaged over the samples.
    pub mean_in_contact: f64,
    /// Largest roller approach, m: positive is penetration (the Hertz law's deformation;
    /// round-off for Lagrange multipliers); negative when no roller ever touched.
    pub largest_penetration: f64,
    /// Largest roller force, N; NaN without per-roller forces.
    pub largest_force: f64,
}

/// The largest local maximum of `spectrum` within `within_bins` bins of `frequency_hz`,
/// refined between bins (as [`spectral_peaks`]); `None` when there is none. `running_hz`
/// only fills the peak's order.
pub fn peak_near(
    spectrum: &Spectrum,
    frequency_hz: f64,
    within_bins: f64,
    running_hz: f64,
) -> Option<SpectralPeak> {
    let reach = within_bins * spectrum.resolution_hz;
    spectral_peaks(spectrum, running_hz, 0.0, usize::MAX)
        .into_iter()
        .find(|p| (p.frequency_hz - frequency_hz).abs() <= reach)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(forces: &[f64], approaches: &[f64], rollers: usize) -> RollerRecord {
        RollerRecord {
            name: "b".into(),
            node: 0,
            rollers,
            cage_ratio: 0.45,
            angle: vec![0.0; forces.len()],
            approach: approaches.to_vec(),
            force: forces.to_vec(),
        }
    }

    #[test]
    fn summary_counts_contacts_and_extremes() {
        // Two samples of three rollers.
        let r = record(
            &[10.0, 0.0, 5.0, 0.0, 0.0, 20.0],
            &[1e-6, -2e-6, 5e-7, -1e-6, -3e-6, 2e-6],
            3,
        );
        assert_eq!(r.samples(), 2);
        let s = r.summary(0..2);
        assert_eq!((s.max_in_contact, s.min_in_contact), (2, 1));
        assert_eq!(s.mean_in_contact, 1.5);
        assert_eq!(s.largest_penetration, 2e-6);
        assert_eq!(s.largest_force, 20.0);
        assert_eq!(r.summary(1..2).largest_force, 20.0);
        // Without forces, contact is penetration.
        let r = record(&[f64::NAN; 3], &[1e-6, -1e-6, 0.0], 3);
        assert_eq!(r.contacts_at(0), 1);
        assert!(r.summary(0..1).largest_force.is_nan());
    }
}
