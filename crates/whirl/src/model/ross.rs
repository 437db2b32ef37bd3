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
//! nu = E / (2 G_s) - 1), rigid disks, linear bearings with constant coefficients, point
//! masses on support nodes with the bearings linked to them (`n_link`) as housings
//! (`supports`). What it cannot represent is refused, naming the element: tapered
//! elements, speed-dependent or mass coefficients, seals, magnetic bearings, point masses
//! with unequal x and y mass, bearings between two shaft nodes, a support node mounted in
//! two places, element torque, axial loads or damping that differ from element to element,
//! ROSS 3's modal damping (`modal_damping_ratio`).
//!
//! ROSS 3 writes the rotor's own parameters (`Rotor(alpha=..., beta=..., min_w=...)`) into a
//! `[parameters]` table. Its Rayleigh damping C = alpha M + beta K of the rotor without its
//! bearings (shaft, disks, point masses) is whirl's `[damping]` exactly; ROSS then ignores the
//! shaft elements' own alpha, beta, and so does the reader. `min_w` and `max_w` become the
//! `[operating]` speed range. ROSS 2's Rayleigh damping of the shaft elements (uniform alpha,
//! beta) becomes whirl's rotor damping, which also acts on the disks: a note says so.
//!
//! Nothing is dropped in silence: a parameter or element field that the reader does not
//! translate (`rated_w`, an axial coefficient, a field it does not know) is named in a note.
//! Only what does not change the numbers passes without one: tags, colours, plot scale
//! factors, and the frequencies and interpolation of coefficients that are constant.

use std::collections::BTreeMap;
use std::fmt::Write;

use toml::{Table, Value};

use crate::error::{InputError, Result};

mod supports;

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
    let parameters = parameters(table.get("parameters"), &mut notes)?;
    let mut shaft = Vec::new();
    let mut disks = String::new();
    let mut point_masses = Vec::new();
    let mut bearings = Vec::new();
    for (key, value) in &table {
        if matches!(key.as_str(), "ross_version" | "parameters") {
            continue;
        }
        let element = value
            .as_table()
            .ok_or_else(|| refuse(key, "is not a table of element fields"))?;
        let class = key.split('_').next().unwrap_or_default();
        match class {
            "ShaftElement" => shaft.push(shaft_element(key, element, &mut notes)?),
            "DiskElement" => disks.push_str(&disk(key, element, &mut notes)?),
            "PointMass" => point_masses.push((key.as_str(), element)),
            "BearingElement" | "BallBearingElement" | "RollerBearingElement" => {
                bearings.push((key.as_str(), element))
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
    let (point_disks, supports) =
        supports::translate(&point_masses, &bearings, shaft.len(), &mut notes)?;
    disks.push_str(&point_disks);
    let mut toml = format!(
        "# Translated by whirl from a model file written by ROSS {} (Rotor.save).\nname = {}\n\n",
        table
            .get("ross_version")
            .and_then(Value::as_str)
            .unwrap_or("(version not given)"),
        quoted(name)
    );
    toml.push_str(&elements_and_damping(
        &shaft,
        parameters.damping,
        &mut notes,
    )?);
    toml.push_str(&materials_and_sections(&shaft));
    toml.push_str(&disks);
    toml.push_str(&supports);
    if let Some((min, max)) = parameters.operating {
        let _ = write!(
            toml,
            "[operating]\nmin_speed = {}\nmax_speed = {}\n",
            float(min),
            float(max)
        );
    }
    Ok(RossImport { toml, notes })
}

/// What whirl takes from ROSS 3's `[parameters]`, the rotor's own arguments.
#[derive(Debug, Default)]
struct Parameters {
    /// Rayleigh damping of the rotor without its bearings (alpha 1/s, beta s).
    damping: (f64, f64),
    /// Operating speed range `min_w`, `max_w`, rad/s.
    operating: Option<(f64, f64)>,
}

/// Reads `[parameters]` (absent before ROSS 3, empty in ROSS 2.3's files).
fn parameters(table: Option<&Value>, notes: &mut Vec<String>) -> Result<Parameters> {
    const KEY: &str = "parameters";
    let Some(value) = table else {
        return Ok(Parameters::default());
    };
    let t = value
        .as_table()
        .ok_or_else(|| InputError::field("ross", "`parameters` is not a table"))?;
    if t.contains_key("modal_damping_ratio") {
        return Err(InputError::field(
            "ross",
            "the ROSS rotor has modal damping (`parameters.modal_damping_ratio`), which whirl \
             cannot represent: give it Rayleigh damping (alpha, beta) in ROSS instead",
        )
        .into());
    }
    let speeds = ["min_w", "max_w"].map(|f| t.contains_key(f).then(|| number(KEY, t, f)));
    let operating = match speeds {
        [Some(min), Some(max)] => Some((min?, max?)),
        [None, None] => None,
        _ => {
            notes.push(
                "ROSS's `parameters` give only one of `min_w` and `max_w`: no operating \
                 speed range was set"
                    .to_string(),
            );
            None
        }
    };
    for (field, value) in t {
        let note = match field.as_str() {
            "alpha" | "beta" | "min_w" | "max_w" => continue,
            // Without modal damping ratios ROSS does not use it either.
            "default_damping_ratio" if number(KEY, t, field)? == 0.0 => continue,
            "default_damping_ratio" => format!(
                "ROSS's `parameters.default_damping_ratio` = {value} was dropped: ROSS uses \
                 it only with modal damping ratios, which this rotor has not"
            ),
            "rated_w" => format!(
                "ROSS's rated speed `parameters.rated_w` = {value} rad/s was dropped: whirl's \
                 model has an operating range, not a rated speed"
            ),
            _ => format!("ROSS's `parameters.{field}` = {value} is not read by whirl"),
        };
        notes.push(note);
    }
    Ok(Parameters {
        damping: (
            optional_number(KEY, t, "alpha")?,
            optional_number(KEY, t, "beta")?,
        ),
        operating,
    })
}

/// Names in a note each field of ROSS element `key` that the reader does not translate:
/// none is dropped in silence. Tags, colours and plot scale factors change no number.
fn note_unread(key: &str, t: &Table, read: &[&str], notes: &mut Vec<String>) {
    const COSMETIC: [&str; 3] = ["tag", "color", "scale_factor"];
    let unread: Vec<&str> = t
        .keys()
        .map(String::as_str)
        .filter(|f| !read.contains(f) && !COSMETIC.contains(f))
        .collect();
    if !unread.is_empty() {
        notes.push(format!(
            "`{key}`: {} not read by whirl: `{}`",
            if unread.len() == 1 {
                "this field is"
            } else {
                "these fields are"
            },
            unread.join("`, `")
        ));
    }
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

fn shaft_element(key: &str, t: &Table, notes: &mut Vec<String>) -> Result<ShaftElement> {
    note_unread(
        key,
        t,
        &[
            "L",
            "idl",
            "odl",
            "idr",
            "odr",
            "n",
            "axial_force",
            "torque",
            "shear_effects",
            "rotary_inertia",
            "gyroscopic",
            "shear_method_calc",
            "alpha",
            "beta",
            "material",
        ],
        notes,
    );
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
    note_unread(&field, m, &["name", "rho", "E", "G_s"], notes);
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

/// The `[elements]` table, and `[damping]` from the rotor's Rayleigh damping (ROSS 3's
/// `parameters`, `rotor`) or else from the shaft elements' own.
fn elements_and_damping(
    shaft: &[ShaftElement],
    rotor: (f64, f64),
    notes: &mut Vec<String>,
) -> Result<String> {
    let rotary = uniform(shaft, "rotary_inertia", |e| e.rotary_inertia)?;
    let gyroscopic = uniform(shaft, "gyroscopic", |e| e.gyroscopic)?;
    let axial = uniform(shaft, "axial_force", |e| e.axial_force)?;
    let (alpha, beta) = if rotor != (0.0, 0.0) {
        rotor_damping(shaft, rotor, notes)
    } else {
        element_damping(shaft, notes)?
    };
    let mut s = format!(
        "[elements]\nrotary_inertia = {rotary}\ngyroscopic = {gyroscopic}\naxial_load = {}\n\n",
        float(axial)
    );
    if alpha != 0.0 || beta != 0.0 {
        let _ = write!(
            s,
            "[damping]\nalpha = {}\nbeta = {}\n\n",
            float(alpha),
            float(beta)
        );
    }
    Ok(s)
}

/// ROSS 3's rotor damping, the same matrix as whirl's `[damping]`; ROSS then ignores the
/// shaft elements' own (with a warning of its own), and so does whirl.
fn rotor_damping(
    shaft: &[ShaftElement],
    (alpha, beta): (f64, f64),
    notes: &mut Vec<String>,
) -> (f64, f64) {
    notes.push(format!(
        "ROSS's rotor damping (`parameters`: alpha = {alpha} 1/s, beta = {beta} s; C = alpha M \
         + beta K of the rotor without its bearings) became whirl's [damping], the same matrix"
    ));
    if let Some(e) = shaft.iter().find(|e| e.damping != (0.0, 0.0)) {
        notes.push(format!(
            "the shaft elements' own damping (`{}`: alpha = {}, beta = {}) was ignored, as ROSS \
             ignores it when the rotor has damping",
            e.tag, e.damping.0, e.damping.1
        ));
    }
    (alpha, beta)
}

/// ROSS 2's damping of the shaft elements, uniform, as whirl's rotor damping.
fn element_damping(shaft: &[ShaftElement], notes: &mut Vec<String>) -> Result<(f64, f64)> {
    let (alpha, beta) = uniform(shaft, "damping (alpha, beta)", |e| e.damping)?;
    if alpha != 0.0 || beta != 0.0 {
        notes.push(format!(
            "ROSS's proportional damping of the shaft elements (alpha = {alpha} 1/s, beta = \
             {beta} s) became whirl's rotor damping C = alpha M + beta K, which also acts on \
             the disks' mass"
        ));
    }
    Ok((alpha, beta))
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

fn disk(key: &str, t: &Table, notes: &mut Vec<String>) -> Result<String> {
    note_unread(key, t, &["n", "m", "Ip", "Id"], notes);
    Ok(format!(
        "[[disk]]\nname = {}\nnode = {}\nmass = {}\npolar_inertia = {}\ndiametral_inertia = {}\n\n",
        quoted(tag(key)),
        node(key, t)?,
        float(number(key, t, "m")?),
        float(number(key, t, "Ip")?),
        float(number(key, t, "Id")?)
    ))
}

/// A point mass's mass, when it is the same in x and y (whirl's disks and housings have
/// one mass).
fn point_mass(key: &str, t: &Table, notes: &mut Vec<String>) -> Result<f64> {
    note_unread(key, t, &["n", "mx", "my"], notes);
    let (mx, my) = (number(key, t, "mx")?, number(key, t, "my")?);
    if mx != my {
        return Err(refuse(
            key,
            format!("has mass {mx} kg in x and {my} kg in y: whirl's disks have one mass"),
        )
        .into());
    }
    Ok(mx)
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

/// A ROSS bearing's constant lateral coefficients, in the order of [`COEFFICIENTS`]; its
/// nodes (`n`, `n_link`) are read by [`supports`].
fn bearing_coefficients(key: &str, t: &Table, notes: &mut Vec<String>) -> Result<[f64; 8]> {
    // `frequency` and `interpolation` only say where the coefficients apply, and whirl
    // takes constant ones.
    note_unread(
        key,
        t,
        &[
            "n",
            "n_link",
            "kxx",
            "kxy",
            "kyx",
            "kyy",
            "cxx",
            "cxy",
            "cyx",
            "cyy",
            "kzz",
            "czz",
            "mxx",
            "mxy",
            "myx",
            "myy",
            "mzz",
            "frequency",
            "interpolation",
        ],
        notes,
    );
    for field in ["mxx", "mxy", "myx", "myy"] {
        if coefficient(key, t, field)? != 0.0 {
            return Err(refuse(
                key,
                format!("has a mass coefficient `{field}`, which whirl's bearings do not have"),
            )
            .into());
        }
    }
    for field in ["kzz", "czz", "mzz"] {
        if coefficient(key, t, field)? != 0.0 {
            notes.push(format!(
                "`{key}`: the axial coefficient `{field}` was dropped (whirl models bending only)"
            ));
        }
    }
    let mut values = [0.0; 8];
    for (value, field) in values.iter_mut().zip(COEFFICIENTS) {
        *value = match (field, t.get(field)) {
            // ROSS's BearingElement takes a missing kyy (cyy) as kxx (cxx): a bearing given
            // by one stiffness is isotropic, not free vertically.
            ("kyy", None) => coefficient(key, t, "kxx")?,
            ("cyy", None) => coefficient(key, t, "cxx")?,
            _ => coefficient(key, t, field)?,
        };
    }
    Ok(values)
}

/// The lateral coefficients of a bearing, in the order whirl's tables list them.
const COEFFICIENTS: [&str; 8] = ["kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy"];

/// The coefficient lines of a whirl table.
fn coefficient_lines(values: &[f64; 8]) -> String {
    let mut s = String::new();
    for (field, value) in COEFFICIENTS.iter().zip(values) {
        let _ = writeln!(s, "{field} = {}", float(*value));
    }
    s
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
