//! Roller bearings in harmonic balance (docs/theory.md section 7).
//!
//! With the rollers orbiting at the cage speed w_c the bearing force varies at the roller
//! passage frequency N_b w_c, which is incommensurate with the running speed w: the true
//! response is quasi-periodic and a Fourier series in w alone cannot hold it. Two periodic
//! approximations make the force a function of the shaft's motion only:
//!
//! - [`CageModel::PassageAveraged`]: the force averaged over one roller pitch of cage
//!   positions, the mean stiffness the shaft feels over many passages. Its varying part,
//!   the source of the N_b w_c lines of a time simulation, is dropped.
//! - [`CageModel::Frozen`]: the cage held at its position at t = 0 (the model's
//!   `cage_angle`): the stiffness of one roller arrangement, anisotropic where the average
//!   is nearly isotropic.
//!
//! In both the rollers keep their orbiting speed in the approach rate, so contact damping
//! acts as in the time simulation. Waviness moves with the cage and the inner ring and
//! has no periodic counterpart: a bearing with waviness or a race defect is refused.

use std::f64::consts::TAU;

use serde::Serialize;

use crate::bearing::geometry::Slice;
use crate::bearing::{contact_coordinates, HertzBearing};
use crate::error::{Error, Result};
use crate::force::{Kinematics, NonlinearForce};
use crate::model::Model;

/// How the roller passage is made periodic in the running speed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum CageModel {
    /// The force averaged over `positions` cage positions evenly spread over one roller
    /// pitch.
    PassageAveraged {
        /// Cage positions per roller pitch.
        positions: usize,
    },
    /// The cage held at its position at t = 0.
    Frozen,
}

/// Cage positions per roller pitch of the default passage average. On the reference rotor
/// (10 um, 330 Hz, H = 5) going to 32 positions changes the 1X by 7e-5 (disk) and 1.1e-4
/// (bearing) and the bearing's 2X by 2.6e-4 relative; 4 positions would change them by 4e-4
/// to 1.3e-3.
pub const DEFAULT_CAGE_POSITIONS: usize = 8;

/// A [`CageModel`] by name, as the command line, Python and a study choose it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum CageKind {
    /// Force averaged over cage positions across one roller pitch.
    Passage,
    /// Cage held at the model's cage angle.
    Frozen,
}

impl CageModel {
    /// The passage average over [`DEFAULT_CAGE_POSITIONS`] positions.
    pub const DEFAULT: CageModel = CageModel::PassageAveraged {
        positions: DEFAULT_CAGE_POSITIONS,
    };

    /// The model of `kind`; a passage average over `positions` cage positions per roller
    /// pitch ([`DEFAULT_CAGE_POSITIONS`] when `None`; a frozen cage has none to give).
    pub fn new(kind: CageKind, positions: Option<usize>) -> CageModel {
        match kind {
            CageKind::Passage => CageModel::PassageAveraged {
                positions: positions.unwrap_or(DEFAULT_CAGE_POSITIONS),
            },
            CageKind::Frozen => CageModel::Frozen,
        }
    }

    /// Its kind, by the name every front end gives it.
    pub fn kind(&self) -> CageKind {
        match self {
            CageModel::PassageAveraged { .. } => CageKind::Passage,
            CageModel::Frozen => CageKind::Frozen,
        }
    }

    /// A sentence for outputs saying which approximation was used.
    pub fn describe(&self) -> String {
        match self {
            CageModel::PassageAveraged { positions } => format!(
                "roller passage averaged over {positions} cage positions per roller pitch \
                 (the varying-compliance excitation at N_b w_c is not represented)"
            ),
            CageModel::Frozen => "cage frozen at its position at t = 0 (the varying-compliance \
                                  excitation at N_b w_c is not represented)"
                .into(),
        }
    }
}

/// A Hertz roller bearing with its cage positions fixed by a [`CageModel`].
pub struct CagedBearing {
    inner: HertzBearing,
    /// Spin angles that place the cage at each averaged position.
    angles: Vec<f64>,
    /// The contact slices of every cage position at [`Self::slices_speed`], position by
    /// position: with the cage fixed they depend on the speed alone (through the clearance
    /// and the cage speed), not on the time or the motion, so the rollers' angles, sines
    /// and cosines are made once per speed instead of at every time sample of the AFT.
    slices: Vec<Vec<Slice>>,
    /// The speed the slices were made at (NaN before the first call).
    slices_speed: f64,
    /// One cage position's force, dF/dq and dF/dv, summed over its slices.
    force_buffer: Vec<f64>,
    buffer: Vec<f64>,
    buffer_v: Vec<f64>,
}

impl CagedBearing {
    /// `inner` with its cage positions set by `cage`.
    ///
    /// # Errors
    /// [`Error::Unsupported`] when the bearing has waviness or a race defect, [`Error::InvalidOption`] when
    /// `cage` has no positions.
    pub fn new(inner: HertzBearing, cage: CageModel) -> Result<CagedBearing> {
        let geometry = inner.geometry();
        if !geometry.is_round() {
            return Err(Error::Unsupported(format!(
                "{}: waviness and race defects make the bearing force quasi-periodic (they \
                 move with the cage and the inner ring), which harmonic balance in the running \
                 speed cannot hold; remove them for harmonic balance or use `whirl simulate`",
                inner.name()
            )));
        }
        // The cage advances by cage_ratio per radian of spin angle.
        let pitch_angle = TAU / geometry.rollers as f64 / geometry.cage_ratio;
        let angles = match cage {
            CageModel::PassageAveraged { positions: 0 } => {
                return Err(Error::InvalidOption(
                    "the passage average needs at least one cage position per pitch".into(),
                ))
            }
            CageModel::PassageAveraged { positions } => (0..positions)
                .map(|k| pitch_angle * k as f64 / positions as f64)
                .collect(),
            CageModel::Frozen => vec![0.0],
        };
        let m = inner.dofs().len();
        Ok(CagedBearing {
            inner,
            slices: vec![Vec::new(); angles.len()],
            slices_speed: f64::NAN,
            angles,
            force_buffer: vec![0.0; m],
            buffer: vec![0.0; m * m],
            buffer_v: vec![0.0; m * m],
        })
    }

    /// Makes the slices of every cage position at `speed` unless they are made already.
    fn place_rollers(&mut self, speed: f64) {
        if self.slices_speed == speed {
            return;
        }
        for (slices, &angle) in self.slices.iter_mut().zip(&self.angles) {
            // Without waviness the slices do not depend on the time.
            let position = Kinematics {
                time: 0.0,
                speed,
                angle,
            };
            slices.clear();
            self.inner
                .geometry()
                .for_each_slice(&position, |slice| slices.push(*slice));
        }
        self.slices_speed = speed;
    }

    fn weight(&self) -> f64 {
        1.0 / self.angles.len() as f64
    }

    /// The force (into `force`) and the tangents (into `tangents`, dF/dq and dF/dv), each
    /// where asked for, averaged over the cage positions: each position's slices summed
    /// apart, then weighted, so either part is the same alone or with the other.
    fn accumulate(
        &mut self,
        at: &Kinematics,
        motion: (&[f64], &[f64]),
        mut force: Option<&mut [f64]>,
        mut tangents: Option<(&mut [f64], &mut [f64])>,
    ) {
        if let Some(out) = force.as_deref_mut() {
            out.fill(0.0);
        }
        if let Some((dfdq, dfdv)) = tangents.as_mut() {
            dfdq.fill(0.0);
            dfdv.fill(0.0);
        }
        self.place_rollers(at.speed);
        let w = self.weight();
        let cage_speed = self.inner.geometry().cage_speed(at.speed);
        let wanted = (force.is_some(), tangents.is_some());
        for k in 0..self.angles.len() {
            self.position_into_buffers(k, at.speed, cage_speed, motion, wanted);
            if let Some(out) = force.as_deref_mut() {
                add_weighted(out, &self.force_buffer, w);
            }
            if let Some((dfdq, dfdv)) = tangents.as_mut() {
                add_weighted(dfdq, &self.buffer, w);
                add_weighted(dfdv, &self.buffer_v, w);
            }
        }
    }

    /// The force and the tangents (`wanted`: either, both) of cage position `k` alone, into
    /// the buffers: each slice of its rollers, or for a ball bearing the whole bearing.
    fn position_into_buffers(
        &mut self,
        k: usize,
        speed: f64,
        cage_speed: f64,
        motion: (&[f64], &[f64]),
        (force, tangents): (bool, bool),
    ) {
        let m = motion.0.len();
        self.force_buffer.fill(0.0);
        self.buffer.fill(0.0);
        self.buffer_v.fill(0.0);
        if self.inner.is_ball() {
            // A ball bearing's balls share the axial balance: the whole bearing at this
            // cage position, not slice by slice.
            let angle = self.angles[k];
            let position = Kinematics {
                time: 0.0,
                speed,
                angle,
            };
            let (q, v) = motion;
            if force {
                self.inner
                    .force(&position, q, v, &mut self.force_buffer[..m]);
            }
            if tangents {
                self.inner
                    .jacobian(&position, q, v, &mut self.buffer, &mut self.buffer_v);
            }
            return;
        }
        for slice in &self.slices[k] {
            self.inner.add_slice(
                slice,
                cage_speed,
                motion,
                force.then_some(&mut self.force_buffer[..m]),
                tangents.then_some((&mut self.buffer[..], &mut self.buffer_v[..])),
            );
        }
    }
}

impl NonlinearForce for CagedBearing {
    fn name(&self) -> String {
        self.inner.name()
    }

    fn dofs(&self) -> &[usize] {
        self.inner.dofs()
    }

    fn force(&mut self, at: &Kinematics, q: &[f64], v: &[f64], out: &mut [f64]) {
        self.accumulate(at, (q, v), Some(out), None);
    }

    fn jacobian(
        &mut self,
        at: &Kinematics,
        q: &[f64],
        v: &[f64],
        dfdq: &mut [f64],
        dfdv: &mut [f64],
    ) {
        self.accumulate(at, (q, v), None, Some((dfdq, dfdv)));
    }

    fn force_and_jacobian(
        &mut self,
        at: &Kinematics,
        q: &[f64],
        v: &[f64],
        out: &mut [f64],
        dfdq: &mut [f64],
        dfdv: &mut [f64],
    ) {
        self.accumulate(at, (q, v), Some(out), Some((dfdq, dfdv)));
    }

    fn stiffness_bound(&self) -> Vec<f64> {
        self.inner.stiffness_bound()
    }
}

/// Hertz contacts of every roller bearing of `model` with their cages fixed by `cage` and
/// the law smoothed below the approach `smoothing` (m; [`HertzBearing::smoothed`]), a
/// [`crate::force::ForceBuilder`] once both are bound.
///
/// # Errors
/// As [`CagedBearing::new`], or when a bearing's coordinates are missing.
pub fn caged_bearings(
    model: &Model,
    coordinate: &dyn Fn(usize) -> Option<usize>,
    cage: CageModel,
    smoothing: f64,
) -> Result<Vec<Box<dyn NonlinearForce>>> {
    model
        .roller_bearings
        .iter()
        .map(|b| {
            let hertz =
                HertzBearing::new(b, contact_coordinates(b, coordinate)?)?.smoothed(smoothing);
            let caged = Box::new(CagedBearing::new(hertz, cage)?);
            crate::bearing::mounted(model, b.housing, caged, coordinate)
        })
        .collect()
}

crate::given::choice!(CageKind { "passage" => CageKind::Passage, "frozen" => CageKind::Frozen });

/// out += w values, entry by entry.
fn add_weighted(out: &mut [f64], values: &[f64], w: f64) {
    for (o, f) in out.iter_mut().zip(values) {
        *o += w * f;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bearing::stiffness::FrozenBearing;

    fn reference_bearing() -> crate::model::RollerBearing {
        let model = Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None).unwrap();
        model.roller_bearings[0].clone()
    }

    #[test]
    fn frozen_cage_force_equals_the_frozen_bearing_of_the_stiffness_module() {
        // The stiffness module's FrozenBearing places the cage by its angle at rest; the
        // caged bearing must place it at the model's cage angle whatever the time and spin
        // angle it is called with.
        let bearing = reference_bearing();
        let hertz = HertzBearing::new(&bearing, vec![0, 1]).unwrap();
        let mut caged = CagedBearing::new(hertz, CageModel::Frozen).unwrap();
        let gamma = bearing.clearance.at_speed(0.0);
        let mut frozen = FrozenBearing::new(&bearing, gamma, bearing.cage_angle).unwrap();
        let at = Kinematics {
            time: 0.3,
            speed: 0.0,
            angle: 5.0,
        };
        for u in [[3e-6, -2.2e-5], [-1.5e-5, -1.1e-5], [0.0, 2.5e-5]] {
            let mut f = [0.0; 2];
            caged.force(&at, &u, &[0.0; 2], &mut f);
            let expected = frozen.force(u);
            let scale = expected[0].hypot(expected[1]).max(1.0);
            // Same Hertz sum in another order: round-off only.
            assert!(
                (f[0] - expected[0]).abs() < 1e-9 * scale
                    && (f[1] - expected[1]).abs() < 1e-9 * scale,
                "{f:?} vs {expected:?}"
            );
        }
    }

    #[test]
    fn passage_average_does_not_depend_on_time_or_spin_angle() {
        let bearing = reference_bearing();
        let hertz = HertzBearing::new(&bearing, vec![0, 1]).unwrap();
        let mut caged = CagedBearing::new(hertz, CageModel::DEFAULT).unwrap();
        let u = [2e-6, -2.3e-5];
        let mut first = [0.0; 2];
        let mut other = [0.0; 2];
        let at = |t: f64| Kinematics {
            time: t,
            speed: 300.0,
            angle: 300.0 * t,
        };
        caged.force(&at(0.0), &u, &[0.0; 2], &mut first);
        caged.force(&at(0.0123), &u, &[0.0; 2], &mut other);
        assert!(first[1] > 0.0, "the rollers push the shaft up: {first:?}");
        assert_eq!(first, other);
    }

    #[test]
    fn waviness_is_refused_with_the_reason() {
        let mut bearing = reference_bearing();
        bearing.waviness.push(crate::model::Waviness {
            ring: crate::model::Ring::Outer,
            form: crate::model::WavinessForm::Thesis,
            order: 5,
            amplitude: 1e-6,
            phase: 0.0,
        });
        let hertz = HertzBearing::new(&bearing, vec![0, 1]).unwrap();
        let Err(e) = CagedBearing::new(hertz, CageModel::DEFAULT) else {
            panic!("a wavy bearing was accepted");
        };
        assert!(e.to_string().contains("waviness"), "{e}");
    }
}
