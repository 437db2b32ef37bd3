//! What a Campbell diagram is asked for, option by option (`whirl campbell`, `whirl.campbell`):
//! each option left out takes the library's default, written here once.

// Options are read once per diagram; a large error type on this cold path is fine.
#![allow(clippy::result_large_err)]

use super::CampbellOptions;
use crate::error::InputError;
use crate::given::{mode_count, unknown_option, Given, SetByName, MAX_MODES};
use crate::model::Model;

/// Speeds of a diagram when none are given: from rest to 1.2 x the model's top operating
/// speed ([`Model::default_speeds`]).
pub const DEFAULT_CAMPBELL_SPEEDS: usize = 161;

/// Whirl branches followed when none are asked for.
pub const DEFAULT_BRANCHES: usize = 8;

/// The excitation order drawn when none are asked for: the running speed, 1X.
pub const DEFAULT_ORDER: f64 = 1.0;

/// The highest excitation order a diagram draws.
pub const MAX_ORDER: f64 = 100.0;

/// A Campbell diagram's options as given; `None` (and `false`) is the library's default.
#[derive(Debug, Clone, Default)]
pub struct CampbellRequest {
    /// Spin speeds, rad/s, 0 or more; `None` for [`DEFAULT_CAMPBELL_SPEEDS`] from rest.
    pub speeds: Option<Vec<f64>>,
    /// Branches to follow, 1 to [`MAX_MODES`]; `None` for [`DEFAULT_BRANCHES`].
    pub modes: Option<usize>,
    /// Excitation orders, each above 0 and at most [`MAX_ORDER`]; `None` for
    /// [`DEFAULT_ORDER`].
    pub orders: Option<Vec<f64>>,
    /// Solve the full system at every speed instead of a basis of 2 x modes + 8 undamped
    /// modes ([`CampbellOptions::default_basis`]).
    pub full: bool,
}

/// The options [`CampbellRequest::set`] knows.
const OPTIONS: [&str; 4] = ["speeds", "modes", "orders", "full"];

impl CampbellRequest {
    /// The diagram's options for `model`, every default filled in.
    ///
    /// # Errors
    /// [`InputError`] naming `modes` or `orders` for a value out of range.
    pub fn options(&self, model: &Model) -> Result<CampbellOptions, InputError> {
        let modes = mode_count("modes", self.modes.unwrap_or(DEFAULT_BRANCHES))?;
        let orders = self.orders.clone().unwrap_or_else(|| vec![DEFAULT_ORDER]);
        check_orders(&orders)?;
        Ok(CampbellOptions {
            speeds: self.speeds(model),
            modes,
            orders,
            basis_size: (!self.full).then(|| CampbellOptions::default_basis(modes)),
            ..CampbellOptions::new(Vec::new())
        })
    }

    /// The speeds, given or the default, rad/s.
    pub fn speeds(&self, model: &Model) -> Vec<f64> {
        self.speeds
            .clone()
            .unwrap_or_else(|| model.default_speeds(0.0, DEFAULT_CAMPBELL_SPEEDS))
    }
}

/// Every order above 0 and at most [`MAX_ORDER`], and at least one.
fn check_orders(orders: &[f64]) -> Result<(), InputError> {
    let bad =
        |what: String| InputError::field("orders", what).help("e.g. 1 or 0.5, or several: 1,2,0.5");
    if orders.is_empty() {
        return Err(bad("needs at least one order".into()));
    }
    match orders
        .iter()
        .find(|k| !(k.is_finite() && **k > 0.0 && **k <= MAX_ORDER))
    {
        Some(k) => Err(bad(format!(
            "{k} is not an order between 0 and {MAX_ORDER}"
        ))),
        None => Ok(()),
    }
}

impl SetByName for CampbellRequest {
    fn set(&mut self, name: &str, value: &Given) -> Result<(), InputError> {
        match name {
            "speeds" => self.speeds = Some(value.spin_speeds(name)?),
            "modes" => self.modes = Some(value.whole(name, 1, MAX_MODES)?),
            "orders" => {
                let orders = value
                    .items()
                    .iter()
                    .map(|k| k.number(name))
                    .collect::<Result<Vec<_>, _>>()?;
                check_orders(&orders)?;
                self.orders = Some(orders);
            }
            "full" => self.full = value.flag(name)?,
            _ => return Err(unknown_option(name, &OPTIONS, "Campbell diagram")),
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reference() -> Model {
        Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None).unwrap()
    }

    #[test]
    fn options_left_out_take_the_librarys_defaults() {
        let o = CampbellRequest::default().options(&reference()).unwrap();
        assert_eq!(o.speeds.len(), DEFAULT_CAMPBELL_SPEEDS);
        assert_eq!(o.speeds[0], 0.0);
        assert_eq!(
            (o.modes, o.orders.as_slice()),
            (DEFAULT_BRANCHES, &[DEFAULT_ORDER][..])
        );
        assert_eq!(o.basis_size, Some(2 * DEFAULT_BRANCHES + 8));
        let full = CampbellRequest {
            full: true,
            ..CampbellRequest::default()
        };
        assert_eq!(full.options(&reference()).unwrap().basis_size, None);
    }

    #[test]
    fn a_bad_option_names_itself() {
        let mut r = CampbellRequest::default();
        let e = r.set("orders", &Given::Text("1,0".into())).unwrap_err();
        assert_eq!(e.field.as_deref(), Some("orders"));
        assert!(e.message.contains("between 0 and 100"), "{}", e.message);
        let e = r
            .set("speeds", &Given::Text("-5:800Hz:10".into()))
            .unwrap_err();
        assert_eq!(e.field.as_deref(), Some("speeds"));
        let e = r.set("mode", &Given::Whole(4)).unwrap_err();
        assert!(e.help.unwrap().contains("modes"));
        r.set(
            "speeds",
            &Given::List(vec![Given::Whole(0), Given::Number(10.0)]),
        )
        .unwrap();
        assert_eq!(r.speeds, Some(vec![0.0, 10.0]));
    }
}
