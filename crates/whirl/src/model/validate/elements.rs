//! `[[shaft]]` sections and `[[disk]]` entries -> shaft sections and disks: materials
//! resolved, geometry and element options checked, and the element count bounded.

use super::*;

/// The most beam elements a shaft may have, in one section or in all: the largest entries of
/// the stiffness grow as the cube of the element count (12 EI / h^3) while the lowest modes'
/// stiffness stays, so round-off takes more of their digits the finer the mesh. The
/// reference rotor's first frequency is 49.822 Hz at 10,000 elements (7e-5 from the
/// coarser meshes' 49.819 Hz, already no gain), 53.88 Hz at 20,000 and 168.7 Hz at 50,000.
pub const MAX_ELEMENTS: usize = 10_000;

/// Why `total` elements are too many.
pub(in crate::model) fn too_many_elements(total: usize) -> String {
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

pub(super) fn sections(
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

pub(super) fn element_options(raw: &Option<ElementOptionsFile>) -> V<ElementOptions> {
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

pub(super) fn disk(
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
