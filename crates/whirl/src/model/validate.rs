//! Model file -> validated [`Model`]: units converted to SI, references resolved, and
//! every value checked. Each check names the field and points at its place in the file.

// Validation runs once per file; a large error type on this cold path is fine.
#![allow(clippy::result_large_err)]

mod ball;
mod bearings;
mod elements;
mod housing;
mod loads;
mod plausible;

use std::collections::HashMap;
use std::f64::consts::PI;
use std::ops::Range;

use toml::Spanned;

use super::schema::*;
use super::*;
use crate::units::{check_speed, parse_quantity, Dimension};

use bearings::{cage_speed_ratio, clearance, defects, linear_bearing, roller_bearing, waviness};
use elements::{disk, element_options, sections};
use loads::{damping, operating, unbalance};
use plausible::bearings_plausible;

pub(super) use elements::too_many_elements;
pub use elements::MAX_ELEMENTS;
pub(super) use plausible::{supports, warnings};

type V<T> = std::result::Result<T, InputError>;

fn err(field: &str, span: Range<usize>, message: impl Into<String>) -> InputError {
    InputError::field(field, message).at(span)
}

/// A quantity in SI, finite.
fn quantity(q: &Q, dim: Dimension, field: &str) -> V<f64> {
    let value = match q.get_ref() {
        NumOrText::Number(x) => {
            check_speed(*x, &x.to_string(), dim)
                .map_err(|e| err(field, q.span(), e.to_string()))?;
            *x
        }
        NumOrText::Text(t) => {
            parse_quantity(t, dim).map_err(|e| err(field, q.span(), e.to_string()))?
        }
    };
    finite(value, q.span(), field)
}

/// The largest magnitude a model's number may have in SI units. The largest a rotor model
/// needs are a steel's Young modulus (2e11 Pa) and a stiff support or contact (1e10 N/m); a
/// number past 1e15 is a typo of unit or exponent, and one near f64's range (1e308) passed
/// `check` only to fail later with the wrong reason (a 0 Hz mode, a non-converging
/// eigen-solver, an infinite time step, a singular matrix).
pub const MAX_MAGNITUDE: f64 = 1e15;

fn finite(value: f64, span: Range<usize>, field: &str) -> V<f64> {
    if !value.is_finite() {
        return Err(err(
            field,
            span,
            format!("must be a finite number, got {value}"),
        ));
    }
    if value.abs() > MAX_MAGNITUDE {
        return Err(err(
            field,
            span,
            format!(
                "{value:e} is beyond any physical magnitude of a rotor model (at most \
                 {MAX_MAGNITUDE:e} in SI units)"
            ),
        )
        .help("check the unit and the exponent"));
    }
    Ok(value)
}

fn positive(value: f64, span: Range<usize>, field: &str, unit: &str) -> V<f64> {
    let v = finite(value, span.clone(), field)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(err(
            field,
            span,
            format!("must be positive, got {v} {unit}"),
        ))
    }
}

fn non_negative(value: f64, span: Range<usize>, field: &str, unit: &str) -> V<f64> {
    let v = finite(value, span.clone(), field)?;
    if v >= 0.0 {
        Ok(v)
    } else {
        Err(err(
            field,
            span,
            format!("must not be negative, got {v} {unit}"),
        ))
    }
}

fn positive_q(q: &Q, dim: Dimension, field: &str) -> V<f64> {
    let v = quantity(q, dim, field)?;
    positive(v, q.span(), field, dim.si_name())
}

fn non_negative_q(q: &Q, dim: Dimension, field: &str) -> V<f64> {
    let v = quantity(q, dim, field)?;
    non_negative(v, q.span(), field, dim.si_name())
}

fn opt_f64(x: &Option<Spanned<f64>>, field: &str, default: f64) -> V<f64> {
    x.as_ref()
        .map(|s| finite(*s.get_ref(), s.span(), field))
        .unwrap_or(Ok(default))
}

fn opt_non_negative(x: &Option<Spanned<f64>>, field: &str, unit: &str) -> V<f64> {
    x.as_ref()
        .map(|s| non_negative(*s.get_ref(), s.span(), field, unit))
        .unwrap_or(Ok(0.0))
}

fn count(c: &Count, field: &str, min: i64, max: i64) -> V<usize> {
    let v = *c.get_ref();
    if v < min || v > max {
        return Err(err(
            field,
            c.span(),
            format!("must be a whole number from {min} to {max}, got {v}"),
        ));
    }
    Ok(v as usize)
}

/// The mesh's node positions, for placing features.
struct Nodes {
    z: Vec<f64>,
    length: f64,
}

impl Nodes {
    /// Resolves `node = i` or `z = ...` (exactly one) to a station on a node.
    fn station(
        &self,
        node: &Option<Count>,
        z: &Option<Q>,
        field: &str,
        table: Range<usize>,
    ) -> V<Station> {
        let last = self.z.len() - 1;
        match (node, z) {
            (Some(n), None) => {
                let i = count(n, &format!("{field}.node"), 0, last as i64).map_err(|e| {
                    e.help(format!(
                        "nodes are numbered 0 (z = 0) to {last} (z = {} m)",
                        Si(self.length)
                    ))
                })?;
                Ok(Station {
                    node: i,
                    z: self.z[i],
                })
            }
            (None, Some(q)) => {
                let f = format!("{field}.z");
                let zv = quantity(q, Dimension::Length, &f)?;
                let tol = 1e-9 * self.length;
                let (i, zn) = self
                    .z
                    .iter()
                    .copied()
                    .enumerate()
                    .min_by(|a, b| (a.1 - zv).abs().total_cmp(&(b.1 - zv).abs()))
                    .unwrap_or((0, 0.0));
                if (zn - zv).abs() > tol {
                    return Err(
                        err(&f, q.span(), format!("z = {} m is not at a node", Si(zv))).help(
                            format!(
                                "the nearest node is {i} at z = {} m; adjust the shaft sections' \
                             lengths or element counts so that a node falls there",
                                Si(zn)
                            ),
                        ),
                    );
                }
                Ok(Station { node: i, z: zn })
            }
            (Some(_), Some(_)) => Err(err(field, table, "give `node` or `z`, not both")),
            (None, None) => Err(err(
                field,
                table,
                "missing its position: give `node` or `z`",
            )),
        }
    }
}

pub(super) fn validate(raw: ModelFile) -> V<Model> {
    let gravity = match &raw.gravity {
        Some(g) => non_negative(*g.get_ref(), g.span(), "gravity", "m/s^2")?,
        None => 9.81,
    };
    let materials = materials(&raw.material)?;
    let material_list = raw
        .material
        .iter()
        .filter_map(|m| materials.get(m.get_ref().name.get_ref()).cloned())
        .collect();
    let options = element_options(&raw.elements)?;
    let sections = sections(&raw.shaft, &materials, options.beam)?;
    let z = node_positions(&sections);
    let nodes = Nodes {
        length: sections.iter().map(|s| s.length).sum(),
        z,
    };
    let disks = raw
        .disk
        .iter()
        .enumerate()
        .map(|(i, d)| disk(d, &format!("disk[{i}]"), &nodes, &materials))
        .collect::<V<Vec<_>>>()?;
    let (bearings, roller_bearings, housings) = bearings_and_housings(&raw, &nodes)?;
    let damping = raw
        .damping
        .as_ref()
        .map(damping)
        .transpose()?
        .unwrap_or_default();
    let unbalances = raw
        .unbalance
        .iter()
        .enumerate()
        .map(|(i, u)| unbalance(u, &format!("unbalance[{i}]"), &nodes, &disks))
        .collect::<V<Vec<_>>>()?;
    let operating = raw.operating.as_ref().map(operating).transpose()?;
    let model = Model {
        name: raw.name.clone().unwrap_or_else(|| "rotor".into()),
        gravity,
        materials: material_list,
        sections,
        options,
        disks,
        bearings,
        roller_bearings,
        housings,
        damping,
        unbalances,
        operating,
    };
    bearings_plausible(&model, &raw)?;
    Ok(model)
}

/// The linear, roller and ball bearings of the file (the ball bearings after the roller
/// bearings, as [`Model::roller_bearings`] holds them) and the housings, each bearing's
/// `housing` resolved.
fn bearings_and_housings(
    raw: &ModelFile,
    nodes: &Nodes,
) -> V<(Vec<LinearBearing>, Vec<RollerBearing>, Vec<Housing>)> {
    let mut bearings = raw
        .bearing
        .iter()
        .enumerate()
        .map(|(i, b)| linear_bearing(b, &format!("bearing[{i}]"), nodes))
        .collect::<V<Vec<_>>>()?;
    let mut roller_bearings = raw
        .roller_bearing
        .iter()
        .enumerate()
        .map(|(i, b)| roller_bearing(b, &format!("roller_bearing[{i}]"), nodes))
        .collect::<V<Vec<_>>>()?;
    for (i, b) in raw.ball_bearing.iter().enumerate() {
        roller_bearings.push(ball::ball_bearing(b, &format!("ball_bearing[{i}]"), nodes)?);
    }
    let housings = housing::housings(&raw.housing)?;
    let housing_names: Vec<String> = housings.iter().map(|h| h.name.clone()).collect();
    for (i, (b, file)) in bearings.iter_mut().zip(&raw.bearing).enumerate() {
        let field = format!("bearing[{i}].housing");
        b.housing = housing::reference(&file.get_ref().housing, &housing_names, &field)?;
    }
    for (i, (b, file)) in roller_bearings
        .iter_mut()
        .zip(&raw.roller_bearing)
        .enumerate()
    {
        let field = format!("roller_bearing[{i}].housing");
        b.housing = housing::reference(&file.get_ref().housing, &housing_names, &field)?;
    }
    // Ball bearings follow the roller bearings in `roller_bearings`.
    let balls = roller_bearings.iter_mut().skip(raw.roller_bearing.len());
    for (i, (b, file)) in balls.zip(&raw.ball_bearing).enumerate() {
        let field = format!("ball_bearing[{i}].housing");
        b.housing = housing::reference(&file.get_ref().housing, &housing_names, &field)?;
    }
    Ok((bearings, roller_bearings, housings))
}

fn materials(raw: &[Spanned<MaterialFile>]) -> V<HashMap<String, Material>> {
    let mut out = HashMap::new();
    for (i, m) in raw.iter().enumerate() {
        let f = format!("material[{i}]");
        let mf = m.get_ref();
        let name = mf.name.get_ref().clone();
        let e = positive(
            *mf.young_modulus.get_ref(),
            mf.young_modulus.span(),
            &format!("{f}.young_modulus"),
            "Pa",
        )?;
        let rho = positive(
            *mf.density.get_ref(),
            mf.density.span(),
            &format!("{f}.density"),
            "kg/m^3",
        )?;
        let nu = opt_f64(&mf.poisson_ratio, &format!("{f}.poisson_ratio"), 0.3)?;
        if !(-1.0..0.5).contains(&nu) {
            let span = mf
                .poisson_ratio
                .as_ref()
                .map(|p| p.span())
                .unwrap_or(m.span());
            return Err(err(
                &format!("{f}.poisson_ratio"),
                span,
                format!("must lie in [-1, 0.5), got {nu}"),
            ));
        }
        let material = Material {
            name: name.clone(),
            young_modulus: e,
            density: rho,
            poisson_ratio: nu,
        };
        if out.insert(name.clone(), material).is_some() {
            return Err(err(
                &format!("{f}.name"),
                mf.name.span(),
                format!("material `{name}` is defined twice"),
            ));
        }
    }
    Ok(out)
}

fn find_material(
    name: &Spanned<String>,
    materials: &HashMap<String, Material>,
    field: &str,
) -> V<Material> {
    materials.get(name.get_ref()).cloned().ok_or_else(|| {
        let mut known: Vec<&str> = materials.keys().map(|k| k.as_str()).collect();
        known.sort_unstable();
        err(
            field,
            name.span(),
            format!("unknown material `{}`", name.get_ref()),
        )
        .help(if known.is_empty() {
            "define it in a [[material]] table".to_string()
        } else {
            format!("defined materials: {}", known.join(", "))
        })
    })
}

/// A number in a message, to six significant digits: `0.0061`, not `0.0060999999999999995`.
struct Si(f64);

impl std::fmt::Display for Si {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let rounded: f64 = format!("{:.5e}", self.0).parse().unwrap_or(self.0);
        write!(f, "{rounded}")
    }
}
