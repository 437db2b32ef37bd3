//! Model file -> validated [`Model`]: units converted to SI, references resolved, and
//! every value checked. Each check names the field and points at its place in the file.

// Validation runs once per file; a large error type on this cold path is fine.
#![allow(clippy::result_large_err)]

mod housing;

use std::collections::HashMap;
use std::f64::consts::PI;
use std::ops::Range;

use toml::Spanned;

use super::schema::*;
use super::*;
use crate::units::{check_speed, parse_quantity, Dimension};

mod ball;

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
    let mut bearings = raw
        .bearing
        .iter()
        .enumerate()
        .map(|(i, b)| linear_bearing(b, &format!("bearing[{i}]"), &nodes))
        .collect::<V<Vec<_>>>()?;
    let mut roller_bearings = raw
        .roller_bearing
        .iter()
        .enumerate()
        .map(|(i, b)| roller_bearing(b, &format!("roller_bearing[{i}]"), &nodes))
        .collect::<V<Vec<_>>>()?;
    for (i, b) in raw.ball_bearing.iter().enumerate() {
        roller_bearings.push(ball::ball_bearing(
            b,
            &format!("ball_bearing[{i}]"),
            &nodes,
        )?);
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
    for (i, (b, file)) in model
        .roller_bearings
        .iter()
        .zip(&raw.roller_bearing)
        .enumerate()
    {
        let f = file.get_ref();
        let spans = BearingSpans {
            clearance: f.clearance.span(),
            waviness: f
                .waviness
                .iter()
                .map(|w| w.get_ref().amplitude.span())
                .collect(),
            forcing: f.forcing_function.as_ref().map(|l| l.span()),
        };
        roller_bearing_plausible(b, &spans, &format!("roller_bearing[{i}]"), model.operating)?;
    }
    let balls = model.roller_bearings.iter().filter(|b| b.is_ball());
    for (i, (b, file)) in balls.zip(&raw.ball_bearing).enumerate() {
        let f = file.get_ref();
        let spans = BearingSpans {
            clearance: f.clearance.as_ref().map_or(file.span(), |c| c.span()),
            waviness: f
                .waviness
                .iter()
                .map(|w| w.get_ref().amplitude.span())
                .collect(),
            forcing: None,
        };
        roller_bearing_plausible(b, &spans, &format!("ball_bearing[{i}]"), model.operating)?;
    }
    Ok(model)
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

/// The most beam elements a shaft may have, in one section or in all: the largest entries of
/// the stiffness grow as the cube of the element count (12 EI / h^3) while the lowest modes'
/// stiffness stays, so round-off takes more of their digits the finer the mesh. The
/// reference rotor's first frequency is 49.822 Hz at 10,000 elements (7e-5 from the
/// coarser meshes' 49.819 Hz, already no gain), 53.88 Hz at 20,000 and 168.7 Hz at 50,000.
pub const MAX_ELEMENTS: usize = 10_000;

/// Why `total` elements are too many.
pub(super) fn too_many_elements(total: usize) -> String {
    format!(
        "{total} elements in all, at most {MAX_ELEMENTS}: round-off in the stiffness, whose \
         largest entries grow as the cube of the element count, swamps the lowest modes beyond \
         that"
    )
}

/// Refuses sections with more than [`MAX_ELEMENTS`] elements in all, at the first section
/// that takes the count past it.
fn total_elements(raw: &[Spanned<ShaftSectionFile>], sections: &[ShaftSection]) -> V<()> {
    let mut total = 0;
    for (i, (r, s)) in raw.iter().zip(sections).enumerate() {
        total += s.elements;
        if total > MAX_ELEMENTS {
            let all: usize = sections.iter().map(|s| s.elements).sum();
            return Err(err(
                &format!("shaft[{i}].elements"),
                r.get_ref().elements.span(),
                format!("the shaft's sections have {}", too_many_elements(all)),
            )
            .help(
                "use fewer elements: cubic beam elements converge fast (`whirl convergence` \
                 shows how many the first modes need)",
            ));
        }
    }
    Ok(())
}

fn sections(
    raw: &[Spanned<ShaftSectionFile>],
    materials: &HashMap<String, Material>,
    default_beam: BeamTheory,
) -> V<Vec<ShaftSection>> {
    if raw.is_empty() {
        return Err(InputError::field("shaft", "the model has no shaft").help(
            "add at least one [[shaft]] section with length, outer_diameter, material and elements",
        ));
    }
    raw.iter()
        .enumerate()
        .map(|(i, s)| {
            let f = format!("shaft[{i}]");
            let s = s.get_ref();
            let length = positive_q(&s.length, Dimension::Length, &format!("{f}.length"))?;
            let od = positive_q(
                &s.outer_diameter,
                Dimension::Length,
                &format!("{f}.outer_diameter"),
            )?;
            let id = match &s.inner_diameter {
                Some(q) => {
                    let idv = non_negative_q(q, Dimension::Length, &format!("{f}.inner_diameter"))?;
                    if idv >= od {
                        return Err(err(
                            &format!("{f}.inner_diameter"),
                            q.span(),
                            format!(
                                "the bore ({} m) must be smaller than the outer diameter ({} m)",
                                Si(idv),
                                Si(od)
                            ),
                        ));
                    }
                    idv
                }
                None => 0.0,
            };
            let material = find_material(&s.material, materials, &format!("{f}.material"))?;
            let elements = count(
                &s.elements,
                &format!("{f}.elements"),
                1,
                MAX_ELEMENTS as i64,
            )?;
            let beam = match &s.beam {
                Some(b) => beam_theory(b, &format!("{f}.beam"))?,
                None => default_beam,
            };
            let shear_factor = match &s.shear_factor {
                Some(k) => positive(*k.get_ref(), k.span(), &format!("{f}.shear_factor"), "")?,
                None => circular_shear_factor(od, id, material.poisson_ratio),
            };
            Ok(ShaftSection {
                length,
                outer_diameter: od,
                inner_diameter: id,
                material,
                elements,
                beam,
                shear_factor,
            })
        })
        .collect::<V<Vec<_>>>()
        .and_then(|sections| total_elements(raw, &sections).map(|()| sections))
}

fn element_options(raw: &Option<ElementOptionsFile>) -> V<ElementOptions> {
    let d = ElementOptions::default();
    Ok(match raw {
        None => d,
        Some(o) => ElementOptions {
            rotary_inertia: o.rotary_inertia.unwrap_or(d.rotary_inertia),
            gyroscopic: o.gyroscopic.unwrap_or(d.gyroscopic),
            axial_load: opt_f64(&o.axial_load, "elements.axial_load", 0.0)?,
            beam: match &o.beam {
                Some(b) => beam_theory(b, "elements.beam")?,
                None => d.beam,
            },
        },
    })
}

fn beam_theory(raw: &Spanned<String>, field: &str) -> V<BeamTheory> {
    match raw.get_ref().trim().to_ascii_lowercase().as_str() {
        "euler-bernoulli" => Ok(BeamTheory::EulerBernoulli),
        "timoshenko" => Ok(BeamTheory::Timoshenko),
        other => Err(
            err(field, raw.span(), format!("unknown beam theory `{other}`")).help(
                "use \"euler-bernoulli\" (the default) or \"timoshenko\" (shear deformation)",
            ),
        ),
    }
}

fn disk(
    raw: &Spanned<DiskFile>,
    field: &str,
    nodes: &Nodes,
    materials: &HashMap<String, Material>,
) -> V<Disk> {
    let d = raw.get_ref();
    let station = nodes.station(&d.node, &d.z, field, raw.span())?;
    let geometry = d.outer_diameter.is_some() || d.width.is_some() || d.material.is_some();
    let direct = d.mass.is_some() || d.polar_inertia.is_some() || d.diametral_inertia.is_some();
    let (mass, ip, id) = match (direct, geometry) {
        (true, false) => {
            let missing = |name: &str| {
                err(field, raw.span(), format!("missing `{name}`"))
                .help("give mass, polar_inertia and diametral_inertia, or outer_diameter, width and material")
            };
            let mass = positive_q(
                d.mass.as_ref().ok_or_else(|| missing("mass"))?,
                Dimension::Mass,
                &format!("{field}.mass"),
            )?;
            let ip = d
                .polar_inertia
                .as_ref()
                .ok_or_else(|| missing("polar_inertia"))?;
            let id = d
                .diametral_inertia
                .as_ref()
                .ok_or_else(|| missing("diametral_inertia"))?;
            let ipv = non_negative(
                *ip.get_ref(),
                ip.span(),
                &format!("{field}.polar_inertia"),
                "kg m^2",
            )?;
            let idv = non_negative(
                *id.get_ref(),
                id.span(),
                &format!("{field}.diametral_inertia"),
                "kg m^2",
            )?;
            // Perpendicular axes: I_p = sum m (x^2 + y^2) = I_x + I_y - 2 sum m z^2, so
            // I_p <= 2 I_d for any body symmetric about its axis (equal for a flat disk).
            // The allowance is round-off of inertias computed elsewhere.
            if ipv > 2.0 * idv * (1.0 + 1e-9) {
                return Err(err(
                    &format!("{field}.polar_inertia"),
                    ip.span(),
                    format!(
                        "a polar inertia of {} kg m^2 is more than twice the diametral inertia \
                         ({} kg m^2): no rigid body has that (I_p <= 2 I_d, equal for a flat disk)",
                        Si(ipv),
                        Si(idv)
                    ),
                )
                .help("check that the two values are not swapped"));
            }
            (mass, ipv, idv)
        }
        (false, true) => disk_from_geometry(d, field, raw.span(), materials)?,
        (true, true) => {
            return Err(err(field, raw.span(), "give the inertias (mass, polar_inertia, diametral_inertia) or the geometry (outer_diameter, bore, width, material), not both"));
        }
        (false, false) => {
            return Err(err(field, raw.span(), "a disk needs its inertia")
                .help("give mass, polar_inertia and diametral_inertia, or outer_diameter, width and material"));
        }
    };
    Ok(Disk {
        name: d
            .name
            .clone()
            .unwrap_or_else(|| format!("disk {}", station.node)),
        station,
        mass,
        polar_inertia: ip,
        diametral_inertia: id,
    })
}

/// Mass and inertias of a ring of outer radius R, bore r and width b (thesis eq. 2.14
/// generalised to a bore): m = rho pi (R^2 - r^2) b, Ip = m (R^2 + r^2) / 2,
/// Id = m (3 (R^2 + r^2) + b^2) / 12.
fn disk_from_geometry(
    d: &DiskFile,
    field: &str,
    span: Range<usize>,
    materials: &HashMap<String, Material>,
) -> V<(f64, f64, f64)> {
    let missing = |name: &str| {
        err(
            field,
            span.clone(),
            format!("missing `{name}` for a disk given by its geometry"),
        )
    };
    let od = positive_q(
        d.outer_diameter
            .as_ref()
            .ok_or_else(|| missing("outer_diameter"))?,
        Dimension::Length,
        &format!("{field}.outer_diameter"),
    )?;
    let width = positive_q(
        d.width.as_ref().ok_or_else(|| missing("width"))?,
        Dimension::Length,
        &format!("{field}.width"),
    )?;
    let material = find_material(
        d.material.as_ref().ok_or_else(|| missing("material"))?,
        materials,
        &format!("{field}.material"),
    )?;
    let bore = match &d.bore {
        Some(q) => {
            let b = non_negative_q(q, Dimension::Length, &format!("{field}.bore"))?;
            if b >= od {
                return Err(err(
                    &format!("{field}.bore"),
                    q.span(),
                    format!(
                        "the bore ({} m) must be smaller than the outer diameter ({} m)",
                        Si(b),
                        Si(od)
                    ),
                ));
            }
            b
        }
        None => 0.0,
    };
    let (r_o, r_i) = (od / 2.0, bore / 2.0);
    let mass = material.density * PI * (r_o * r_o - r_i * r_i) * width;
    let ip = mass * (r_o * r_o + r_i * r_i) / 2.0;
    let id = mass * (3.0 * (r_o * r_o + r_i * r_i) + width * width) / 12.0;
    Ok((mass, ip, id))
}

fn linear_bearing(
    raw: &Spanned<LinearBearingFile>,
    field: &str,
    nodes: &Nodes,
) -> V<LinearBearing> {
    let b = raw.get_ref();
    let station = nodes.station(&b.node, &b.z, field, raw.span())?;
    let any_k = [&b.kxx, &b.kyy, &b.kxy, &b.kyx].iter().any(|k| k.is_some());
    let ring = b.springs.is_some() || b.spring_stiffness.is_some();
    let f = |name: &str| format!("{field}.{name}");
    let stiffness = match (any_k, ring) {
        (true, true) => {
            return Err(err(
                field,
                raw.span(),
                "give kxx/kyy/kxy/kyx or springs/spring_stiffness, not both",
            ))
        }
        (false, false) => {
            return Err(err(field, raw.span(), "a bearing needs a stiffness").help(
                "give kxx and kyy (N/m), or springs and spring_stiffness for a ring of springs",
            ))
        }
        (true, false) => {
            let kxx = opt_non_negative(&b.kxx, &f("kxx"), "N/m")?;
            let kyy = opt_non_negative(&b.kyy, &f("kyy"), "N/m")?;
            [
                [kxx, opt_f64(&b.kxy, &f("kxy"), 0.0)?],
                [opt_f64(&b.kyx, &f("kyx"), 0.0)?, kyy],
            ]
        }
        (false, true) => {
            let missing = |name: &str| {
                err(
                    field,
                    raw.span(),
                    format!("missing `{name}` for a ring of springs"),
                )
            };
            let n = count(
                b.springs.as_ref().ok_or_else(|| missing("springs"))?,
                &f("springs"),
                3,
                10_000,
            )?;
            let k = b
                .spring_stiffness
                .as_ref()
                .ok_or_else(|| missing("spring_stiffness"))?;
            let k = positive(*k.get_ref(), k.span(), &f("spring_stiffness"), "N/m")?;
            // N_s equal springs equally spaced: sum cos^2 = sum sin^2 = N_s/2, sum sin cos = 0
            // (docs/theory-errata.md, thesis eq. 2.20).
            let kr = n as f64 / 2.0 * k;
            [[kr, 0.0], [0.0, kr]]
        }
    };
    let cxx = opt_non_negative(&b.cxx, &f("cxx"), "N s/m")?;
    let cyy = opt_non_negative(&b.cyy, &f("cyy"), "N s/m")?;
    let damping = [
        [cxx, opt_f64(&b.cxy, &f("cxy"), 0.0)?],
        [opt_f64(&b.cyx, &f("cyx"), 0.0)?, cyy],
    ];
    Ok(LinearBearing {
        name: b
            .name
            .clone()
            .unwrap_or_else(|| format!("bearing {}", station.node)),
        station,
        stiffness,
        damping,
        housing: None,
    })
}

/// Bounds of a contact law's exponent n (F = k delta^n): Hertz theory gives 10/9 (line) and
/// 3/2 (point); measured roller contacts lie between linear and quadratic.
const MIN_CONTACT_EXPONENT: f64 = 1.0;
const MAX_CONTACT_EXPONENT: f64 = 2.0;

/// The cage speed ratio: as given, which must lie strictly between 0 (a cage that stands
/// still) and 1 (a cage turning with the shaft), or from the rolling kinematics of a fixed
/// outer ring, (1 - D_b / D_p) / 2, with `diameter_ratio` = D_b / D_p.
fn cage_speed_ratio(given: &Option<Spanned<f64>>, diameter_ratio: f64, field: &str) -> V<f64> {
    let Some(given) = given else {
        return Ok(0.5 * (1.0 - diameter_ratio));
    };
    let ratio = finite(*given.get_ref(), given.span(), field)?;
    if ratio > 0.0 && ratio < 1.0 {
        Ok(ratio)
    } else {
        Err(err(
            field,
            given.span(),
            format!(
                "the cage turns slower than the shaft and in the same sense: expected 0 < ratio \
                 < 1, got {ratio}"
            ),
        )
        .help(format!(
            "the cage frequency over the shaft frequency; this bearing's geometry gives {:.4}",
            0.5 * (1.0 - diameter_ratio)
        )))
    }
}

fn roller_bearing(
    raw: &Spanned<RollerBearingFile>,
    field: &str,
    nodes: &Nodes,
) -> V<RollerBearing> {
    let b = raw.get_ref();
    let f = |name: &str| format!("{field}.{name}");
    let station = nodes.station(&b.node, &b.z, field, raw.span())?;
    let rollers = count(&b.rollers, &f("rollers"), 3, 1000)?;
    let dp = positive_q(&b.pitch_diameter, Dimension::Length, &f("pitch_diameter"))?;
    let db = positive_q(&b.roller_diameter, Dimension::Length, &f("roller_diameter"))?;
    let length = positive_q(&b.roller_length, Dimension::Length, &f("roller_length"))?;
    if db >= dp {
        return Err(err(
            &f("roller_diameter"),
            b.roller_diameter.span(),
            format!(
                "the roller diameter ({} m) must be smaller than the pitch diameter ({} m)",
                Si(db),
                Si(dp)
            ),
        ));
    }
    // Rollers must fit side by side on the pitch circle.
    if rollers as f64 * db >= PI * dp {
        return Err(err(
            &f("rollers"),
            b.rollers.span(),
            format!(
                "{rollers} rollers of diameter {} m do not fit on a pitch circle of diameter {} m",
                Si(db),
                Si(dp)
            ),
        )
        .help(format!(
            "at most {} rollers fit",
            ((PI * dp / db).ceil() as usize).saturating_sub(1)
        )));
    }
    let clearance = clearance(&b.clearance, &f("clearance"))?;
    let skew = opt_f64(&b.skew_angle, &f("skew_angle"), 0.0)?;
    if skew.abs() >= 45.0 {
        return Err(err(
            &f("skew_angle"),
            b.skew_angle.as_ref().map_or(raw.span(), |s| s.span()),
            format!("a skew of {skew} degrees is not a small misalignment; expected |skew| < 45"),
        ));
    }
    let roller_tilt = b.roller_tilt.unwrap_or(false);
    let slices = roller_slices(b, skew, &f("slices"))?;
    let exponent = opt_f64(&b.contact_exponent, &f("contact_exponent"), 10.0 / 9.0)?;
    if !(MIN_CONTACT_EXPONENT..=MAX_CONTACT_EXPONENT).contains(&exponent) {
        let span = b
            .contact_exponent
            .as_ref()
            .map(|e| e.span())
            .unwrap_or(raw.span());
        return Err(err(
            &f("contact_exponent"),
            span,
            format!(
                "must lie in [{MIN_CONTACT_EXPONENT}, {MAX_CONTACT_EXPONENT}], got {}: Hertz \
                 theory gives 10/9 for line and 3/2 for point contact",
                Si(exponent)
            ),
        )
        .help("10/9 = 1.1111 for line contact, 3/2 for point contact"));
    }
    let contact_stiffness = match b.contact_stiffness.get_ref() {
        ContactStiffnessFile::Value(k) => positive(
            *k,
            b.contact_stiffness.span(),
            &f("contact_stiffness"),
            "N/m^n",
        )?,
        ContactStiffnessFile::Rule(r) if r == "palmgren" => {
            if (exponent - 10.0 / 9.0).abs() > 1e-9 {
                return Err(err(
                    &f("contact_exponent"),
                    raw.span(),
                    "Palmgren's stiffness is for the line-contact exponent 10/9",
                )
                .help("remove contact_exponent or give contact_stiffness as a number"));
            }
            RollerBearing::palmgren_stiffness(length)
        }
        ContactStiffnessFile::Rule(r) => {
            return Err(err(
                &f("contact_stiffness"),
                b.contact_stiffness.span(),
                format!("expected a number (N/m^n) or \"palmgren\", got \"{r}\""),
            ))
        }
    };
    let (race_defects, element_defects) = defects(&b.defect, field, rollers)?;
    Ok(RollerBearing {
        name: b
            .name
            .clone()
            .unwrap_or_else(|| format!("roller bearing {}", station.node)),
        station,
        rollers,
        pitch_diameter: dp,
        roller_diameter: db,
        roller_length: length,
        clearance,
        contact_stiffness,
        contact_exponent: exponent,
        contact_damping: opt_non_negative(&b.contact_damping, &f("contact_damping"), "N s/m")?,
        cage_angle: opt_f64(&b.cage_angle, &f("cage_angle"), 0.0)?.to_radians(),
        cage_speed_ratio: cage_speed_ratio(&b.cage_speed_ratio, db / dp, &f("cage_speed_ratio"))?,
        linear_stiffness: non_negative(
            *b.linear_stiffness.get_ref(),
            b.linear_stiffness.span(),
            &f("linear_stiffness"),
            "N/m",
        )?,
        linear_damping: opt_non_negative(&b.linear_damping, &f("linear_damping"), "N s/m")?,
        roller_tilt,
        slices,
        skew_angle: skew.to_radians(),
        waviness: b
            .waviness
            .iter()
            .enumerate()
            .map(|(i, w)| waviness(w, &f(&format!("waviness[{i}]"))))
            .collect::<V<Vec<_>>>()?,
        defects: race_defects,
        element_defects,
        forcing_function: b
            .forcing_function
            .as_ref()
            .map(|ff| forcing_function(ff, &f("forcing_function")))
            .transpose()?,
        ball: None,
        dynamic_load_rating: b
            .dynamic_load_rating
            .as_ref()
            .map(|c| positive_q(c, Dimension::Force, &f("dynamic_load_rating")))
            .transpose()?,
        housing: None,
    })
}

/// Slices along a roller: 1 unless tilt or skew is modelled, then 10 unless given.
fn roller_slices(b: &RollerBearingFile, skew: f64, field: &str) -> V<usize> {
    let profiled = b.roller_tilt == Some(true) || skew != 0.0;
    match &b.slices {
        Some(c) if !profiled => Err(err(
            field,
            c.span(),
            "slices only matter with roller_tilt = true or a skew_angle",
        )
        .help("remove slices, or set roller_tilt = true")),
        Some(c) => count(c, field, 1, 200),
        None if profiled => Ok(10),
        None => Ok(1),
    }
}

fn waviness(raw: &Spanned<WavinessFile>, field: &str) -> V<Waviness> {
    let w = raw.get_ref();
    let form = match w.form.as_ref().map(|f| (f.get_ref().as_str(), f.span())) {
        None | Some(("thesis", _)) => WavinessForm::Thesis,
        Some(("ring_fixed", _)) => WavinessForm::RingFixed,
        Some((other, span)) => {
            return Err(err(
                &format!("{field}.form"),
                span,
                format!("expected \"thesis\" or \"ring_fixed\", got \"{other}\""),
            ))
        }
    };
    Ok(Waviness {
        ring: ring(&w.ring, field)?,
        form,
        order: count(&w.order, &format!("{field}.order"), 1, 10_000)?,
        amplitude: non_negative_q(
            &w.amplitude,
            Dimension::Length,
            &format!("{field}.amplitude"),
        )?,
        phase: opt_f64(&w.phase, &format!("{field}.phase"), 0.0)?.to_radians(),
    })
}

fn ring(raw: &Spanned<String>, field: &str) -> V<Ring> {
    match raw.get_ref().as_str() {
        "outer" => Ok(Ring::Outer),
        "inner" => Ok(Ring::Inner),
        other => Err(err(
            &format!("{field}.ring"),
            raw.span(),
            format!("expected \"outer\" or \"inner\", got \"{other}\""),
        )),
    }
}

/// The `defect` tables of a bearing with `elements` rollers or balls: race defects, and
/// spots on elements (`ring = "element"`).
fn defects(
    raw: &[Spanned<DefectFile>],
    bearing: &str,
    elements: usize,
) -> V<(Vec<RaceDefect>, Vec<ElementDefect>)> {
    let (mut races, mut spots) = (Vec::new(), Vec::new());
    for (i, d) in raw.iter().enumerate() {
        let field = format!("{bearing}.defect[{i}]");
        let file = d.get_ref();
        let on_element = file.ring.get_ref() == "element";
        match (&file.element, on_element) {
            (Some(e), false) => {
                return Err(err(
                    &format!("{field}.element"),
                    e.span(),
                    "`element` names a roller or ball: only with ring = \"element\"",
                ))
            }
            (None, true) => {
                return Err(err(
                    &field,
                    d.span(),
                    "a defect on a rolling element needs `element`, its index from 0",
                ))
            }
            _ => {}
        }
        let race = race_defect(d, &field)?;
        if let Some(e) = &file.element {
            let element = count(e, &format!("{field}.element"), 0, elements as i64 - 1)?;
            if race.width >= PI {
                return Err(err(
                    &format!("{field}.width"),
                    file.width.span(),
                    "a spot on a rolling element must be narrower than 180 degrees (it \
                     meets the outer race and, half a turn later, the inner)",
                ));
            }
            spots.push(ElementDefect {
                element,
                angle: race.angle,
                width: race.width,
                depth: race.depth,
            });
        } else {
            races.push(race);
        }
    }
    Ok((races, spots))
}

fn race_defect(raw: &Spanned<DefectFile>, field: &str) -> V<RaceDefect> {
    let d = raw.get_ref();
    let width_field = format!("{field}.width");
    let width = finite(*d.width.get_ref(), d.width.span(), &width_field)?;
    if width <= 0.0 || width >= 360.0 {
        return Err(err(
            &width_field,
            d.width.span(),
            format!("must lie strictly between 0 and 360 degrees, got {width}"),
        ));
    }
    // The ring of an element's spot is irrelevant: its place is the element's.
    let ring = if d.ring.get_ref() == "element" {
        Ring::Outer
    } else {
        ring(&d.ring, field)?
    };
    Ok(RaceDefect {
        ring,
        angle: opt_f64(&d.angle, &format!("{field}.angle"), 0.0)?.to_radians(),
        width: width.to_radians(),
        depth: non_negative_q(&d.depth, Dimension::Length, &format!("{field}.depth"))?,
    })
}

fn forcing_function(raw: &Spanned<ForcingFunctionFile>, field: &str) -> V<ForcingFunction> {
    let ff = raw.get_ref();
    let law = ForcingFunction {
        a0: ff.a0,
        a1: ff.a1,
        b0: ff.b0,
        b1: ff.b1,
    };
    if [law.a0, law.a1, law.b0, law.b1]
        .iter()
        .any(|c| !c.is_finite())
        || law.a0 <= 0.0
        || law.b0 <= 0.0
    {
        return Err(err(
            field,
            raw.span(),
            "a0, a1, b0, b1 must be finite, with a0 > 0 (N/m^b) and b0 > 0",
        )
        .help("`whirl fit-forcing` writes a fitted block to paste here"));
    }
    Ok(law)
}

fn clearance(raw: &Spanned<ClearanceFile>, field: &str) -> V<Clearance> {
    match raw.get_ref() {
        ClearanceFile::Constant(c) => {
            let q = Spanned::new(raw.span(), c.clone());
            Ok(Clearance::Constant(non_negative_q(
                &q,
                Dimension::Length,
                field,
            )?))
        }
        ClearanceFile::Polynomial(p) => {
            let unit = |text: &str, dim| {
                parse_quantity(&format!("1 {text}"), dim)
                    .map_err(|e| err(field, raw.span(), e.to_string()))
            };
            let cu = unit(&p.clearance_unit, Dimension::Length)?;
            let su = unit(&p.speed_unit, Dimension::AngularSpeed)?;
            if p.coefficients.is_empty() || p.coefficients.iter().any(|c| !c.is_finite()) {
                return Err(err(
                    field,
                    raw.span(),
                    "coefficients must be a non-empty list of finite numbers",
                ));
            }
            let si: Vec<f64> = p
                .coefficients
                .iter()
                .enumerate()
                .map(|(i, c)| c * cu / su.powi(i as i32))
                .collect();
            if si[0] < 0.0 {
                return Err(err(
                    field,
                    raw.span(),
                    "the clearance at rest (first coefficient) must not be negative",
                ));
            }
            Ok(Clearance::Polynomial(si))
        }
    }
}

/// `[damping]`: the coefficients as given (alpha/beta or ratios), times `scale`. Scaling both
/// coefficients scales the damping ratio at every frequency alike (zeta = alpha / (2 w) +
/// beta w / 2), which is what a study of damping varies.
fn damping(raw: &Spanned<DampingFile>) -> V<RayleighDamping> {
    let given = given_damping(raw)?;
    let Some(scale) = raw.get_ref().scale else {
        return Ok(given);
    };
    if !(scale.is_finite() && scale > 0.0) {
        return Err(err(
            "damping.scale",
            raw.span(),
            format!("the scale must be a positive number, got {scale}"),
        )
        .help("1 keeps the damping as given, 2.5 turns 2 % into 5 %"));
    }
    Ok(RayleighDamping {
        alpha: scale * given.alpha,
        beta: scale * given.beta,
    })
}

fn given_damping(raw: &Spanned<DampingFile>) -> V<RayleighDamping> {
    let d = raw.get_ref();
    let span = raw.span();
    let coefficients = d.alpha.is_some() || d.beta.is_some();
    let ratios = d.ratios.is_some() || d.frequencies.is_some();
    let check = |v: f64, name: &str, unit: &str| {
        non_negative(v, span.clone(), &format!("damping.{name}"), unit)
    };
    match (coefficients, ratios) {
        (true, true) => Err(err(
            "damping",
            span,
            "give alpha/beta or ratios/frequencies, not both",
        )),
        (false, false) => Ok(RayleighDamping::default()),
        (true, false) => Ok(RayleighDamping {
            alpha: check(d.alpha.unwrap_or(0.0), "alpha", "1/s")?,
            beta: check(d.beta.unwrap_or(0.0), "beta", "s")?,
        }),
        (false, true) => {
            let (Some(z), Some(f)) = (&d.ratios, &d.frequencies) else {
                return Err(err(
                    "damping",
                    span,
                    "ratios and frequencies go together: two of each",
                ));
            };
            if z.len() != 2 || f.len() != 2 {
                return Err(err(
                    "damping",
                    span,
                    "give exactly two ratios and two frequencies",
                ));
            }
            let w = f
                .iter()
                .map(|x| {
                    let q = Spanned::new(span.clone(), x.clone());
                    positive_q(&q, Dimension::AngularSpeed, "damping.frequencies")
                })
                .collect::<V<Vec<_>>>()?;
            if (w[0] - w[1]).abs() <= 1e-9 * w[0] {
                return Err(err(
                    "damping.frequencies",
                    span,
                    "the two frequencies must differ",
                ));
            }
            for &zi in z {
                if !(0.0..1.0).contains(&zi) {
                    return Err(err(
                        "damping.ratios",
                        span,
                        format!("damping ratios must lie in [0, 1), got {zi}"),
                    ));
                }
            }
            let r = RayleighDamping::from_ratios([z[0], z[1]], [w[0], w[1]]);
            if r.alpha < 0.0 || r.beta < 0.0 {
                return Err(err("damping", span, format!(
                    "these ratios need a negative coefficient (alpha = {:.4e}, beta = {:.4e})",
                    r.alpha, r.beta
                )).help("Rayleigh damping cannot fall faster than 1/w or rise faster than w between the two frequencies"));
            }
            Ok(r)
        }
    }
}

fn unbalance(
    raw: &Spanned<UnbalanceFile>,
    field: &str,
    nodes: &Nodes,
    disks: &[Disk],
) -> V<Unbalance> {
    let u = raw.get_ref();
    let f = |name: &str| format!("{field}.{name}");
    let station = nodes.station(&u.node, &u.z, field, raw.span())?;
    let given = [
        u.eccentricity.is_some(),
        u.mass_radius.is_some(),
        u.grade.is_some(),
    ];
    if given.iter().filter(|g| **g).count() != 1 {
        return Err(err(
            field,
            raw.span(),
            "give exactly one of eccentricity, mass_radius or grade",
        ));
    }
    let carrier_mass = || -> V<f64> {
        if let Some(m) = &u.mass {
            return positive_q(m, Dimension::Mass, &f("mass"));
        }
        let m: f64 = disks
            .iter()
            .filter(|d| d.station.node == station.node)
            .map(|d| d.mass)
            .sum();
        if m > 0.0 {
            Ok(m)
        } else {
            Err(err(
                field,
                raw.span(),
                format!("no disk at node {} to carry the eccentricity", station.node),
            )
            .help("give `mass` (the mass that is off-centre), or use mass_radius"))
        }
    };
    let mass_radius = if let Some(e) = &u.eccentricity {
        non_negative_q(e, Dimension::Length, &f("eccentricity"))? * carrier_mass()?
    } else if let Some(mr) = &u.mass_radius {
        non_negative(*mr.get_ref(), mr.span(), &f("mass_radius"), "kg m")?
    } else if let Some(g) = &u.grade {
        // ISO 21940-11: permissible eccentricity e = G / Omega with G in mm/s.
        let grade = positive(*g.get_ref(), g.span(), &f("grade"), "mm/s")?;
        let speed = u.grade_speed.as_ref().ok_or_else(|| {
            err(
                field,
                raw.span(),
                "a balance grade needs `grade_speed`, the maximum service speed",
            )
        })?;
        let omega = positive_q(speed, Dimension::AngularSpeed, &f("grade_speed"))?;
        grade * 1e-3 / omega * carrier_mass()?
    } else {
        0.0
    };
    Ok(Unbalance {
        station,
        mass_radius,
        phase: opt_f64(&u.phase, &f("phase"), 0.0)?.to_radians(),
    })
}

fn operating(raw: &Spanned<OperatingFile>) -> V<(f64, f64)> {
    let o = raw.get_ref();
    let q = |x: &NumOrText, name: &str| {
        positive_q(
            &Spanned::new(raw.span(), x.clone()),
            Dimension::AngularSpeed,
            &format!("operating.{name}"),
        )
    };
    let (lo, hi) = (q(&o.min_speed, "min_speed")?, q(&o.max_speed, "max_speed")?);
    if lo > hi {
        return Err(err(
            "operating",
            raw.span(),
            "min_speed must not exceed max_speed",
        ));
    }
    Ok((lo, hi))
}

/// Refuses a rotor that cannot stand: bearings at fewer than two nodes leave it free to
/// tilt (or, with none, to fall), a rigid-body mode at 0 Hz that no rotor analysis can use.
pub(super) fn supports(model: &Model) -> V<()> {
    let nodes = model.bearing_nodes();
    if nodes.len() >= 2 {
        return Ok(());
    }
    let why = match nodes.first() {
        Some(n) => format!(
            "the rotor rests on bearings at one node only ({n}): it is free to tilt about it"
        ),
        None => "the rotor has no bearing: it is free to fall and to tilt".to_string(),
    };
    Err(InputError::field("bearing", why)
        .help("support it at two nodes at least, with [[bearing]] or [[roller_bearing]] tables"))
}

/// Speeds (rad/s) at which speed-dependent laws are checked: from rest to the top of the
/// operating range, in [`LAW_CHECKS`] steps (only rest when the model states no range).
fn checked_speeds(operating: Option<(f64, f64)>) -> Vec<f64> {
    let top = operating.map_or(0.0, |(_, high)| high);
    (0..=LAW_CHECKS)
        .map(|k| top * k as f64 / LAW_CHECKS as f64)
        .collect()
}

/// Steps of [`checked_speeds`]: a polynomial of the few degrees a clearance law has cannot
/// dip below zero and back between 1 % steps of the range without its coefficients being
/// far larger than any fitted law's.
const LAW_CHECKS: usize = 100;

/// A ring's waviness larger than this many times the clearance scale is refused: waviness is
/// a form error of micrometres, below the clearance; ten times it would jam or free the
/// rollers in turn, which is no longer a waviness but a broken ring.
const MAX_WAVINESS_OVER_CLEARANCE: f64 = 10.0;

/// The smallest clearance scale, as a fraction of the pitch diameter: radial clearances of
/// roller bearings are about 1e-4 to 1e-3 of the diameter (ISO 5753 groups), so a
/// zero-clearance (preloaded) bearing is judged against 1e-4 of it.
const MIN_CLEARANCE_SCALE: f64 = 1e-4;

/// Where in the file a bearing's checked values are written.
struct BearingSpans {
    clearance: Range<usize>,
    /// Each waviness component's amplitude.
    waviness: Vec<Range<usize>>,
    forcing: Option<Range<usize>>,
}

/// Refuses a roller bearing that cannot exist: a clearance that goes negative or grows past
/// the rollers within the operating speeds, a forcing law whose coefficients turn negative
/// there, waviness far above the clearance.
fn roller_bearing_plausible(
    b: &RollerBearing,
    spans: &BearingSpans,
    field: &str,
    operating: Option<(f64, f64)>,
) -> V<()> {
    let clearance_span = spans.clearance.clone();
    let speeds = checked_speeds(operating);
    let mut largest = 0.0_f64;
    for &w in &speeds {
        let c = b.clearance.at_speed(w);
        if c.is_nan() || c < 0.0 {
            return Err(err(
                &format!("{field}.clearance"),
                clearance_span,
                format!(
                    "the clearance is {} m at {} Hz, within the operating speeds: it must not be \
                     negative",
                    Si(c),
                    Si(w / (2.0 * PI))
                ),
            )
            .help("check the polynomial's coefficients and units"));
        }
        largest = largest.max(c);
    }
    if largest >= b.roller_diameter {
        return Err(err(
            &format!("{field}.clearance"),
            clearance_span,
            format!(
                "a clearance of {} m is not smaller than the rollers ({} m in diameter): the \
                 rings could not hold them",
                Si(largest),
                Si(b.roller_diameter)
            ),
        )
        .help("radial clearances are micrometres: about 1e-4 to 1e-3 of the pitch diameter"));
    }
    let scale = largest.max(MIN_CLEARANCE_SCALE * b.pitch_diameter);
    for (i, (w, span)) in b.waviness.iter().zip(&spans.waviness).enumerate() {
        if w.amplitude > MAX_WAVINESS_OVER_CLEARANCE * scale {
            return Err(err(
                &format!("{field}.waviness[{i}].amplitude"),
                span.clone(),
                format!(
                    "a waviness of {} m is more than {MAX_WAVINESS_OVER_CLEARANCE} times the \
                     clearance scale ({} m): waviness is a form error below the clearance",
                    Si(w.amplitude),
                    Si(scale)
                ),
            )
            .help("waviness amplitudes are micrometres, e.g. \"1 um\""));
        }
    }
    if let (Some(law), Some(lf)) = (&b.forcing_function, &spans.forcing) {
        // a and b are linear in the speed: their signs over the range are those at its ends.
        let ends = [speeds[0], speeds[speeds.len() - 1]];
        if let Some(&w) = ends.iter().find(|&&w| {
            let (a, e) = law.at_speed(w);
            !(a > 0.0 && e > 0.0)
        }) {
            let (a, e) = law.at_speed(w);
            return Err(err(
                &format!("{field}.forcing_function"),
                lf.clone(),
                format!(
                    "at {} Hz, within the operating speeds, the law's stiffness a0 + a1 W = {} \
                     and exponent b0 + b1 W = {}: both must stay positive",
                    Si(w / (2.0 * PI)),
                    Si(a),
                    Si(e)
                ),
            )
            .help("W is in rad/s; `whirl fit-forcing` fits a law over the speeds you give it"));
        }
    }
    Ok(())
}

/// Warnings about a valid but implausible model: values no real rotor has, which usually
/// mean a unit slipped. One sentence each, naming the field.
pub(super) fn warnings(model: &Model) -> Vec<String> {
    // Ball bearings follow the roller bearings in the model, each table numbered apart.
    let rollers = model
        .roller_bearings
        .iter()
        .filter(|b| !b.is_ball())
        .count();
    let mut out: Vec<String> = model
        .roller_bearings
        .iter()
        .enumerate()
        .filter_map(|(i, b)| {
            let field = if b.is_ball() {
                format!("ball_bearing[{}]", i - rollers)
            } else {
                format!("roller_bearing[{i}]")
            };
            clearance_warning(b, &field, model.operating)
        })
        .collect();
    out.extend(
        model
            .materials
            .iter()
            .enumerate()
            .filter_map(|(i, m)| density_warning(m, &format!("material[{i}]"))),
    );
    let shaft: f64 = model
        .sections
        .iter()
        .map(|s| s.material.density * s.area() * s.length)
        .sum();
    let disks: f64 = model.disks.iter().map(|d| d.mass).sum();
    if shaft < MIN_SHAFT_MASS_FRACTION * (shaft + disks) {
        out.push(format!(
            "shaft: its mass ({} kg) is below {} % of the rotor's ({} kg); a near-massless shaft \
             gives modes of its own at very high frequencies and tiny stable time steps \
             (check the material's density, kg/m^3)",
            Si(shaft),
            100.0 * MIN_SHAFT_MASS_FRACTION,
            Si(shaft + disks)
        ));
    }
    out
}

/// A warning when the bearing's largest clearance from rest to the top operating speed is
/// a large part of the pitch diameter or of the rollers (refused outright when it reaches
/// the roller diameter).
fn clearance_warning(
    b: &RollerBearing,
    field: &str,
    operating: Option<(f64, f64)>,
) -> Option<String> {
    let largest = checked_speeds(operating)
        .iter()
        .map(|&w| b.clearance.at_speed(w))
        .fold(0.0, f64::max);
    let implausible = largest > MAX_PLAUSIBLE_CLEARANCE * b.pitch_diameter
        || largest > MAX_CLEARANCE_PER_ROLLER * b.roller_diameter;
    implausible.then(|| {
        format!(
            "{field}.clearance: {} m is {:.1} % of the roller diameter and {:.2} % of the pitch \
             diameter; radial clearances are micrometres, 0.01 to 0.1 % of the pitch diameter \
             (a unit may be missing: \"20 um\")",
            Si(largest),
            100.0 * largest / b.roller_diameter,
            100.0 * largest / b.pitch_diameter
        )
    })
}

/// A warning when a material's density lies outside [`PLAUSIBLE_DENSITY`].
fn density_warning(m: &Material, field: &str) -> Option<String> {
    let (low, high) = PLAUSIBLE_DENSITY;
    (!(low..=high).contains(&m.density)).then(|| {
        format!(
            "{field}.density: {} kg/m^3 (material `{}`) is outside the {low} to {high} kg/m^3 \
             of engineering solids (polymers about 1000, aluminium 2700, steel 7850, tungsten \
             19300); masses and every frequency follow from it (give it in kg/m^3: steel is \
             7850, not 7.85)",
            Si(m.density),
            m.name
        )
    })
}

/// A clearance above this fraction of the pitch diameter draws a warning (ten times the
/// largest clearance group of ISO 5753).
const MAX_PLAUSIBLE_CLEARANCE: f64 = 0.01;

/// A clearance above this fraction of the roller diameter draws a warning: the largest
/// clearance groups of ISO 5753 stay near 1 % of the rollers (0.1 mm on 10 mm rollers);
/// five times that is no bearing in service.
const MAX_CLEARANCE_PER_ROLLER: f64 = 0.05;

/// Densities (kg/m^3) outside this range draw a warning: below it lie foams, not shaft or
/// disk materials (polymers start near 900); above it nothing, since osmium, the densest
/// element, has 22,590.
const PLAUSIBLE_DENSITY: (f64, f64) = (100.0, 25_000.0);

/// A shaft lighter than this fraction of the rotor draws a warning.
const MIN_SHAFT_MASS_FRACTION: f64 = 0.01;

/// A number in a message, to six significant digits: `0.0061`, not `0.0060999999999999995`.
struct Si(f64);

impl std::fmt::Display for Si {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let rounded: f64 = format!("{:.5e}", self.0).parse().unwrap_or(self.0);
        write!(f, "{rounded}")
    }
}
