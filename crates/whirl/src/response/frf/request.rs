//! What frequency response functions are asked for (`whirl frf`, `whirl.frf`): where the
//! force acts and where the response is read (`NODE:DIR`, read once here), the speed, the
//! frequencies and the force; each option left out takes the library's default.

// Options are read once per analysis; a large error type on this cold path is fine.
#![allow(clippy::result_large_err)]

use super::default_frequencies;
use crate::error::{InputError, Result};
use crate::fe::{dof, Direction};
use crate::given::{unknown_option, Given, SetByName};
use crate::model::Model;

/// The force amplitude of the response columns by default, N.
pub const DEFAULT_FRF_FORCE: f64 = 1.0;

/// A degree of freedom as given: a node and a direction.
pub type DofSpec = (usize, Direction);

/// Frequency response functions as asked for; `None` (or empty) is the library's default.
#[derive(Debug, Clone, Default)]
pub struct FrfRequest {
    /// Where the force acts (required).
    pub input: Option<DofSpec>,
    /// Where the response is read; empty for the input DOF.
    pub outputs: Vec<DofSpec>,
    /// Spin speed, rad/s; `None` for rest.
    pub speed: Option<f64>,
    /// Excitation frequencies, rad/s; `None` for [`default_frequencies`].
    pub frequencies: Option<Vec<f64>>,
    /// Force amplitude, N; `None` for [`DEFAULT_FRF_FORCE`].
    pub force: Option<f64>,
}

/// What [`FrfRequest::resolved`] gives: the input DOF, the output DOFs (global indices), the
/// speed (rad/s), the frequencies (rad/s) and the force (N).
pub type ResolvedFrf = (usize, Vec<usize>, f64, Vec<f64>, f64);

/// The options [`FrfRequest::set`] knows.
const OPTIONS: [&str; 5] = ["input", "output", "speed", "frequencies", "force"];

impl FrfRequest {
    /// Every choice made for `model`: the DOFs checked against its nodes, the defaults
    /// filled in.
    ///
    /// # Errors
    /// [`InputError`] naming `input` (none given, or off the shaft) or `output` (off the
    /// shaft); what [`default_frequencies`] reports.
    pub fn resolved(&self, model: &Model) -> Result<ResolvedFrf> {
        let input = self.input.ok_or_else(|| {
            InputError::field("input", "where the force acts is needed").help("e.g. 10:uy")
        })?;
        let input = global(model, "input", input)?;
        let outputs = match self.outputs.is_empty() {
            true => vec![input],
            false => self
                .outputs
                .iter()
                .map(|&d| global(model, "output", d))
                .collect::<Result<_>>()?,
        };
        let frequencies = match &self.frequencies {
            Some(w) => w.clone(),
            None => default_frequencies(model)?,
        };
        Ok((
            input,
            outputs,
            self.speed.unwrap_or(0.0),
            frequencies,
            self.force.unwrap_or(DEFAULT_FRF_FORCE),
        ))
    }
}

/// The global DOF of `(node, direction)`, the node on `model`'s shaft.
fn global(model: &Model, field: &str, (node, direction): DofSpec) -> Result<usize> {
    let last = model.node_count() - 1;
    if node > last {
        return Err(
            InputError::field(field, format!("node {node} is not on the shaft"))
                .help(format!(
                    "nodes are numbered 0 (z = 0) to {last} (z = {} m)",
                    model.length()
                ))
                .into(),
        );
    }
    Ok(dof(node, direction))
}

/// A DOF `NODE:DIR` (`"10:uy"`) with DIR one of ux, uy, tx, ty.
///
/// # Errors
/// [`InputError`] naming `field` for anything else.
pub fn dof_spec(field: &str, text: &str) -> std::result::Result<DofSpec, InputError> {
    let bad = |why: String| InputError::field(field, format!("`{text}`: {why}")).help("e.g. 10:uy");
    let (node, dir) = text
        .split_once(':')
        .ok_or_else(|| bad("expected NODE:DIR".into()))?;
    let node = node
        .trim()
        .parse::<usize>()
        .map_err(|_| bad(format!("`{node}` is not a node number (0, 1, 2, ...)")))?;
    let direction = Direction::ALL
        .into_iter()
        .find(|d| d.name() == dir.trim())
        .ok_or_else(|| {
            bad(format!(
                "the direction `{dir}` is not one of ux, uy, tx, ty"
            ))
        })?;
    Ok((node, direction))
}

/// A DOF given as text `NODE:DIR` or as a pair `[node, "dir"]`.
fn given_dof(field: &str, value: &Given) -> std::result::Result<DofSpec, InputError> {
    match value {
        Given::Text(t) => dof_spec(field, t),
        Given::List(pair) => match pair.as_slice() {
            [node, Given::Text(dir)] => {
                let node = node.whole(field, 0, usize::MAX >> 1)?;
                dof_spec(field, &format!("{node}:{dir}"))
            }
            _ => Err(
                InputError::field(field, "expected NODE:DIR or (node, direction)")
                    .help("e.g. \"10:uy\" or (10, \"uy\")"),
            ),
        },
        _ => Err(
            InputError::field(field, "expected NODE:DIR or (node, direction)")
                .help("e.g. \"10:uy\" or (10, \"uy\")"),
        ),
    }
}

impl SetByName for FrfRequest {
    fn set(&mut self, name: &str, value: &Given) -> std::result::Result<(), InputError> {
        let v = value;
        match name {
            "input" => self.input = Some(given_dof(name, v)?),
            "output" => {
                // One pair (10, "uy") is one DOF; otherwise each item is one.
                let one_pair = matches!(v, Given::List(p) if matches!(p.as_slice(), [Given::Whole(_), Given::Text(_)]));
                self.outputs = match one_pair {
                    true => vec![given_dof(name, v)?],
                    false => v
                        .items()
                        .iter()
                        .map(|x| given_dof(name, x))
                        .collect::<std::result::Result<_, _>>()?,
                };
            }
            "speed" => self.speed = Some(v.speed(name)?),
            "frequencies" => self.frequencies = Some(v.spin_speeds(name)?),
            "force" => self.force = Some(v.force(name)?),
            _ => return Err(unknown_option(name, &OPTIONS, "frequency response")),
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dof_is_read_from_text_or_a_pair() {
        assert_eq!(dof_spec("input", "10:uy").unwrap(), (10, Direction::Uy));
        let mut r = FrfRequest::default();
        r.set("output", &Given::Text("3:ux, 4:ty".into())).unwrap();
        assert_eq!(r.outputs, vec![(3, Direction::Ux), (4, Direction::Ty)]);
        r.set(
            "output",
            &Given::List(vec![Given::Whole(5), Given::Text("tx".into())]),
        )
        .unwrap();
        assert_eq!(r.outputs, vec![(5, Direction::Tx)]);
        for bad in ["10", "x:uy", "10:uz"] {
            let e = dof_spec("input", bad).unwrap_err();
            assert_eq!(e.field.as_deref(), Some("input"), "{bad}");
        }
        let model = Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None).unwrap();
        r.input = Some((10_000, Direction::Ux));
        let e = r.resolved(&model).unwrap_err().to_string();
        assert!(e.contains("not on the shaft"), "{e}");
    }
}
