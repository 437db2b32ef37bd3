//! Models saved by ROSS (the Python rotordynamics library, `Rotor.save`) read as whirl
//! model files.
//!
//! A ROSS file is TOML with one table per element, named `"<Class>_<tag>"`: shaft elements
//! (length `L`, left and right bores and diameters `idl`, `odl`, `idr`, `odr`, element index
//! `n`, flags `shear_effects`, `rotary_inertia`, `gyroscopic`, proportional damping `alpha`,
//! `beta`, and a `material` sub-table with `rho`, `E`, `G_s`), disks (`n`, `m`, `Id`, `Ip`)
//! and bearings (`n` and coefficient lists `kxx` ... `cyy`, one value per frequency). ROSS
//! numbers nodes as whirl does (node `n` at the left end of element `n`, from z = 0), and its
//! lateral DOFs are whirl's; its axial and torsional DOFs have no counterpart (whirl models
//! bending), so axial and torsional coefficients are dropped with a note.
//!
//! Everything that whirl represents exactly is translated: uniform shaft elements (equal
//! neighbours merged into one section), Euler-Bernoulli or Timoshenko with Cowper's shear
//! coefficient (whirl's default for a circular tube, from the Poisson ratio
//! nu = E / (2 G_s) - 1), rigid disks, linear bearings with constant coefficients. What it
//! cannot represent is refused, naming the element: tapered elements, speed-dependent or
//! mass coefficients, seals, magnetic bearings, point masses with unequal x and y mass,
//! support links, element torque, axial loads or damping that differ from element to element.
//! ROSS's Rayleigh damping of the shaft elements (uniform alpha, beta) becomes whirl's rotor
//! damping, which also acts on the disks: a note says so.

use std::collections::BTreeMap;
use std::fmt::Write;

use toml::{Table, Value};

use crate::error::{InputError, Result};

/// A ROSS model translated to whirl's model file.
#[derive(Debug, Clone, PartialEq)]
pub struct RossImport {
    /// The whirl model file (TOML), ready for [`crate::model::Model::from_toml_str`].
    pub toml: String,
    /// What the translation dropped or changed, one sentence each.
    pub notes: Vec<String>,
}

/// A shaft element of the ROSS file.
#[derive(Debug, Clone, PartialEq)]
struct ShaftElement {
    tag: String,
    index: usize,
    length: f64,
    bore: f64,
    outer: f64,
    material: Material,
    shear: bool,
    rotary_inertia: bool,
    gyroscopic: bool,
    axial_force: f64,
    damping: (f64, f64),
}

#[derive(Debug, Clone, PartialEq)]
struct Material {
    name: String,
    density: f64,
    young_modulus: f64,
    shear_modulus: f64,
}

/// Translates the text of a file written by ROSS's `Rotor.save` into a whirl model file.
///
/// # Errors
///
/// [`crate::Error::Input`] naming the element and field when the file is not TOML, lacks a
/// field, or holds something whirl cannot represent (see the module documentation).
pub fn from_ross_toml(text: &str, name: &str) -> Result<RossImport> {
    let table: Table = text.parse().map_err(|e: toml::de::Error| {
        InputError::field("ross", format!("not a TOML file: {}", e.message()))
    })?;
    let mut notes = Vec::new();
    let mut shaft = Vec::new();
    let mut disks = String::new();
    let mut bearings = String::new();
    for (key, value) in &table {
        if matches!(key.as_str(), "ross_version" | "parameters") {
            continue;
        }
        let element = value
            .as_table()
            .ok_or_else(|| refuse(key, "is not a table of element fields"))?;
        let class = key.split('_').next().unwrap_or_default();
        match class {
            "ShaftElement" => shaft.push(shaft_element(key, element)?),
            "DiskElement" => disks.push_str(&disk(key, element)?),
            "PointMass" => disks.push_str(&point_mass(key, element)?),
            "BearingElement" | "BallBearingElement" | "RollerBearingElement" => {
                bearings.push_str(&bearing(key, element, &mut notes)?)
            }
            _ => {
                return Err(refuse(
                    key,
                    format!(
                        "is a ROSS {class}, which whirl cannot represent (it has shaft \
                         elements, disks, point masses and linear bearings with constant \
                         coefficients)"
                    ),
                )
                .into())
            }
        }
    }
    shaft.sort_by_key(|e| e.index);
    check_consecutive(&shaft)?;
    let mut toml = format!(
        "# Translated by whirl from a model file written by ROSS {} (Rotor.save).\nname = {}\n\n",
        table
            .get("ross_version")
            .and_then(Value::as_str)
            .unwrap_or("(version not given)"),
        quoted(name)
    );
    toml.push_str(&elements_and_damping(&shaft, &mut notes)?);
    toml.push_str(&materials_and_sections(&shaft));
    toml.push_str(&disks);
    toml.push_str(&bearings);
    Ok(RossImport { toml, notes })
}

/// A refusal naming the ROSS element (its table in the file) and why.
fn refuse(element: &str, why: impl Into<String>) -> InputError {
    InputError::field("ross", format!("ROSS element `{element}` {}", why.into()))
}

fn number(element: &str, table: &Table, field: &str) -> Result<f64> {
    match table.get(field) {
        Some(Value::Float(x)) => Ok(*x),
        Some(Value::Integer(i)) => Ok(*i as f64),
        Some(_) => Err(refuse(element, format!("has a `{field}` that is not a number")).into()),
        None => Err(refuse(element, format!("has no `{field}`")).into()),
    }
}

fn optional_number(element: &str, table: &Table, field: &str) -> Result<f64> {
    if table.contains_key(field) {
        number(element, table, field)
    } else {
        Ok(0.0)
    }
}

fn flag(element: &str, table: &Table, field: &str, default: bool) -> Result<bool> {
    match table.get(field) {
        Some(Value::Boolean(b)) => Ok(*b),
        Some(_) => Err(refuse(
            element,
            format!("has a `{field}` that is not true or false"),
        )
        .into()),
        None => Ok(default),
    }
}

fn node(element: &str, table: &Table) -> Result<usize> {
    let n = number(element, table, "n")?;
    if n >= 0.0 && n.fract() == 0.0 {
        Ok(n as usize)
    } else {
        Err(refuse(element, format!("has node n = {n}, not a node index")).into())
    }
}

fn shaft_element(key: &str, t: &Table) -> Result<ShaftElement> {
    let [idl, odl, idr, odr] = ["idl", "odl", "idr", "odr"].map(|f| number(key, t, f));
    let (idl, odl, idr, odr) = (idl?, odl?, idr?, odr?);
    if idl != idr || odl != odr {
        return Err(refuse(
            key,
            format!(
                "is tapered (bore {idl} -> {idr} m, diameter {odl} -> {odr} m): whirl's beam \
                 elements are uniform; split it into uniform elements in ROSS"
            ),
        )
        .into());
    }
    if optional_number(key, t, "torque")? != 0.0 {
        return Err(refuse(key, "carries a torque, which whirl's elements do not model").into());
    }
    let method = t.get("shear_method_calc").and_then(Value::as_str);
    let shear = flag(key, t, "shear_effects", true)?;
    if shear && method.is_some_and(|m| m != "cowper") {
        return Err(refuse(
            key,
            format!(
                "uses the shear coefficient `{}`; whirl uses Cowper's",
                method.unwrap_or_default()
            ),
        )
        .into());
    }
    let m = t
        .get("material")
        .and_then(Value::as_table)
        .ok_or_else(|| refuse(key, "has no material table"))?;
    let field = format!("{key}.material");
    let material = Material {
        name: m
            .get("name")
            .and_then(Value::as_str)
            .unwrap_or("material")
            .to_string(),
        density: number(&field, m, "rho")?,
        young_modulus: number(&field, m, "E")?,
        shear_modulus: number(&field, m, "G_s")?,
    };
    Ok(ShaftElement {
        tag: key.to_string(),
        index: node(key, t)?,
        length: number(key, t, "L")?,
        bore: idl,
        outer: odl,
        material,
        shear,
        rotary_inertia: flag(key, t, "rotary_inertia", true)?,
        gyroscopic: flag(key, t, "gyroscopic", true)?,
        axial_force: optional_number(key, t, "axial_force")?,
        damping: (
            optional_number(key, t, "alpha")?,
            optional_number(key, t, "beta")?,
        ),
    })
}

/// Shaft elements numbered 0, 1, 2, ... without a gap, or the shaft is not one chain.
fn check_consecutive(shaft: &[ShaftElement]) -> Result<()> {
    if shaft.is_empty() {
        return Err(InputError::field("ross", "the ROSS file has no shaft element").into());
    }
    for (i, e) in shaft.iter().enumerate() {
        if e.index != i {
            return Err(refuse(
                &e.tag,
                format!(
                    "is element n = {} where n = {i} was expected: whirl needs one shaft of \
                     consecutive elements",
                    e.index
                ),
            )
            .into());
        }
    }
    Ok(())
}

/// The same value in every element, or a refusal naming the first that differs.
fn uniform<T: PartialEq + Copy + std::fmt::Debug>(
    shaft: &[ShaftElement],
    what: &str,
    get: impl Fn(&ShaftElement) -> T,
) -> Result<T> {
    let first = get(&shaft[0]);
    match shaft.iter().find(|e| get(e) != first) {
        None => Ok(first),
        Some(e) => Err(refuse(
            &e.tag,
            format!(
                "has {what} {:?} where the first element has {first:?}: whirl sets it for the \
                 whole rotor",
                get(e)
            ),
        )
        .into()),
    }
}

fn elements_and_damping(shaft: &[ShaftElement], notes: &mut Vec<String>) -> Result<String> {
    let rotary = uniform(shaft, "rotary_inertia", |e| e.rotary_inertia)?;
    let gyroscopic = uniform(shaft, "gyroscopic", |e| e.gyroscopic)?;
    let axial = uniform(shaft, "axial_force", |e| e.axial_force)?;
    let (alpha, beta) = uniform(shaft, "damping (alpha, beta)", |e| e.damping)?;
    let mut s = format!(
        "[elements]\nrotary_inertia = {rotary}\ngyroscopic = {gyroscopic}\naxial_load = {}\n\n",
        float(axial)
    );
    if alpha != 0.0 || beta != 0.0 {
        notes.push(format!(
            "ROSS's proportional damping of the shaft elements (alpha = {alpha} 1/s, beta = \
             {beta} s) became whirl's rotor damping C = alpha M + beta K, which also acts on \
             the disks' mass"
        ));
        let _ = write!(
            s,
            "[damping]\nalpha = {}\nbeta = {}\n\n",
            float(alpha),
            float(beta)
        );
    }
    Ok(s)
}

/// `[[material]]` tables (one per distinct material) and `[[shaft]]` sections, equal
/// neighbouring elements merged.
fn materials_and_sections(shaft: &[ShaftElement]) -> String {
    let mut names: BTreeMap<String, &Material> = BTreeMap::new();
    let mut name_of = Vec::with_capacity(shaft.len());
    for e in shaft {
        let existing = names
            .iter()
            .find(|(_, m)| **m == &e.material)
            .map(|(n, _)| n.clone());
        let name = existing.unwrap_or_else(|| {
            let mut name = e.material.name.clone();
            let mut k = 2;
            while names.contains_key(&name) {
                name = format!("{}_{k}", e.material.name);
                k += 1;
            }
            names.insert(name.clone(), &e.material);
            name
        });
        name_of.push(name);
    }
    let mut s = String::new();
    for (name, m) in &names {
        let _ = write!(
            s,
            "[[material]]\nname = {}\nyoung_modulus = {}\ndensity = {}\npoisson_ratio = {}\n\n",
            quoted(name),
            float(m.young_modulus),
            float(m.density),
            float(m.young_modulus / (2.0 * m.shear_modulus) - 1.0)
        );
    }
    let mut i = 0;
    while i < shaft.len() {
        let same = |e: &ShaftElement| {
            let a = &shaft[i];
            e.length == a.length && e.bore == a.bore && e.outer == a.outer && e.shear == a.shear
        };
        let run = shaft[i..]
            .iter()
            .zip(&name_of[i..])
            .take_while(|(e, n)| same(e) && **n == name_of[i])
            .count();
        let e = &shaft[i];
        let _ = write!(
            s,
            "[[shaft]]\nlength = {}\nouter_diameter = {}\ninner_diameter = {}\nmaterial = {}\n\
             elements = {run}\nbeam = \"{}\"\n\n",
            float(e.length * run as f64),
            float(e.outer),
            float(e.bore),
            quoted(&name_of[i]),
            if e.shear {
                "timoshenko"
            } else {
                "euler-bernoulli"
            }
        );
        i += run;
    }
    s
}

fn disk(key: &str, t: &Table) -> Result<String> {
    Ok(format!(
        "[[disk]]\nname = {}\nnode = {}\nmass = {}\npolar_inertia = {}\ndiametral_inertia = {}\n\n",
        quoted(tag(key)),
        node(key, t)?,
        float(number(key, t, "m")?),
        float(number(key, t, "Ip")?),
        float(number(key, t, "Id")?)
    ))
}

/// A point mass is a disk without inertia, when its mass is the same in x and y.
fn point_mass(key: &str, t: &Table) -> Result<String> {
    let (mx, my) = (number(key, t, "mx")?, number(key, t, "my")?);
    if mx != my {
        return Err(refuse(
            key,
            format!("has mass {mx} kg in x and {my} kg in y: whirl's disks have one mass"),
        )
        .into());
    }
    Ok(format!(
        "[[disk]]\nname = {}\nnode = {}\nmass = {}\npolar_inertia = 0\ndiametral_inertia = 0\n\n",
        quoted(tag(key)),
        node(key, t)?,
        float(mx)
    ))
}

/// One constant coefficient from ROSS's list over frequencies.
fn coefficient(key: &str, t: &Table, field: &str) -> Result<f64> {
    let values: Vec<f64> = match t.get(field) {
        None => vec![0.0],
        Some(Value::Array(list)) => list
            .iter()
            .map(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)))
            .collect::<Option<Vec<f64>>>()
            .ok_or_else(|| refuse(key, format!("has a `{field}` list that is not numbers")))?,
        Some(v) => vec![v
            .as_float()
            .or_else(|| v.as_integer().map(|i| i as f64))
            .ok_or_else(|| refuse(key, format!("has a `{field}` that is not a number")))?],
    };
    match values.split_first() {
        Some((first, rest)) if rest.iter().all(|v| v == first) => Ok(*first),
        _ => Err(refuse(
            key,
            format!(
                "has `{field}` varying with frequency ({} values): whirl's linear bearings have \
                 constant coefficients; give the coefficients at the speed of interest",
                values.len()
            ),
        )
        .into()),
    }
}

fn bearing(key: &str, t: &Table, notes: &mut Vec<String>) -> Result<String> {
    if t.get("n_link")
        .is_some_and(|v| !matches!(v, Value::String(_)))
    {
        return Err(refuse(
            key,
            "is linked to a support node (n_link): whirl's bearings connect the shaft to the ground",
        )
        .into());
    }
    for field in ["mxx", "mxy", "myx", "myy"] {
        if coefficient(key, t, field)? != 0.0 {
            return Err(refuse(
                key,
                format!("has a mass coefficient `{field}`, which whirl's bearings do not have"),
            )
            .into());
        }
    }
    for field in ["kzz", "czz"] {
        if coefficient(key, t, field)? != 0.0 {
            notes.push(format!(
                "`{key}`: the axial coefficient `{field}` was dropped (whirl models bending only)"
            ));
        }
    }
    let mut s = format!(
        "[[bearing]]\nname = {}\nnode = {}\n",
        quoted(tag(key)),
        node(key, t)?
    );
    for field in ["kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy"] {
        let value = match (field, t.get(field)) {
            // ROSS's BearingElement takes a missing kyy (cyy) as kxx (cxx): a bearing given
            // by one stiffness is isotropic, not free vertically.
            ("kyy", None) => coefficient(key, t, "kxx")?,
            ("cyy", None) => coefficient(key, t, "cxx")?,
            _ => coefficient(key, t, field)?,
        };
        let _ = writeln!(s, "{field} = {}", float(value));
    }
    s.push('\n');
    Ok(s)
}

/// The element's tag: what follows the class name.
fn tag(key: &str) -> &str {
    key.split_once('_').map_or(key, |(_, tag)| tag)
}

/// A TOML string literal.
fn quoted(text: &str) -> String {
    Value::String(text.to_string()).to_string()
}

/// A TOML float that reads back to the same f64 (Rust's shortest round-trip form).
fn float(x: f64) -> String {
    let s = format!("{x:?}");
    if s.contains(['.', 'e', 'i', 'N']) {
        s
    } else {
        format!("{s}.0")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_read_back_exactly() {
        for x in [0.25, 1e6, 0.1 + 0.2, 211e9, 7810.0, 1.0 / 3.0] {
            let text = float(x);
            let back: f64 = text.parse().unwrap();
            assert_eq!(back, x, "{text}");
        }
    }
}
