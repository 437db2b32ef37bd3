//! What the modes at a speed are asked for (`whirl modal`, `whirl.modal`): each option left
//! out takes the library's default, written here once.

// Options are read once per analysis; a large error type on this cold path is fine.
#![allow(clippy::result_large_err)]

use crate::error::InputError;
use crate::given::{mode_count, unknown_option, Given, SetByName, MAX_MODES};

/// Modes found, undamped and damped, when none are asked for.
pub const DEFAULT_MODAL_MODES: usize = 6;

/// The modes at a speed as asked for; `None` is the library's default.
#[derive(Debug, Clone, Copy, Default)]
pub struct ModalRequest {
    /// Spin speed of the damped modes, rad/s, 0 or more; `None` for rest.
    pub speed: Option<f64>,
    /// Modes, 1 to [`MAX_MODES`]; `None` for [`DEFAULT_MODAL_MODES`].
    pub modes: Option<usize>,
}

/// The options [`ModalRequest::set`] knows.
const OPTIONS: [&str; 2] = ["speed", "modes"];

impl ModalRequest {
    /// The speed (rad/s) and the number of modes, every default filled in.
    ///
    /// # Errors
    /// [`InputError`] naming `speed` or `modes` for a value out of range.
    pub fn resolved(&self) -> Result<(f64, usize), InputError> {
        let speed = self.speed.unwrap_or(0.0);
        if !(speed.is_finite() && speed >= 0.0) {
            return Err(InputError::field(
                "speed",
                format!("{speed} rad/s: the speed must be 0 or more"),
            )
            .help("e.g. 300Hz or 3000rpm"));
        }
        let modes = mode_count("modes", self.modes.unwrap_or(DEFAULT_MODAL_MODES))?;
        Ok((speed, modes))
    }
}

impl SetByName for ModalRequest {
    fn set(&mut self, name: &str, value: &Given) -> Result<(), InputError> {
        match name {
            "speed" => self.speed = Some(value.speed(name)?),
            "modes" => self.modes = Some(value.whole(name, 1, MAX_MODES)?),
            _ => return Err(unknown_option(name, &OPTIONS, "modal analysis")),
        }
        Ok(())
    }
}
