//! `[[bearing]]` entries -> linear and roller bearings: stiffness and damping, the roller
//! set and its contact law, clearance, waviness, race defects and forcing functions.

use super::*;

pub(super) fn linear_bearing(
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
pub(super) fn cage_speed_ratio(
    given: &Option<Spanned<f64>>,
    diameter_ratio: f64,
    field: &str,
) -> V<f64> {
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

pub(super) fn roller_bearing(
    raw: &Spanned<RollerBearingFile>,
    field: &str,
    nodes: &Nodes,
) -> V<RollerBearing> {
    let b = raw.get_ref();
    let f = |name: &str| format!("{field}.{name}");
    let station = nodes.station(&b.node, &b.z, field, raw.span())?;
    let (rollers, dp, db, length) = roller_geometry(b, field)?;
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
    let (contact_stiffness, exponent) = roller_contact(raw, field, length)?;
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

/// The roller count, pitch and roller diameters and roller length (m) of a roller bearing,
/// the rollers smaller than the pitch diameter and fitting side by side on the pitch circle.
fn roller_geometry(b: &RollerBearingFile, field: &str) -> V<(usize, f64, f64, f64)> {
    let f = |name: &str| format!("{field}.{name}");
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
    Ok((rollers, dp, db, length))
}

/// The contact law's stiffness (N/m^n; Palmgren's rule for rollers of `length` where asked
/// for) and exponent n, between [`MIN_CONTACT_EXPONENT`] and [`MAX_CONTACT_EXPONENT`].
fn roller_contact(raw: &Spanned<RollerBearingFile>, field: &str, length: f64) -> V<(f64, f64)> {
    let b = raw.get_ref();
    let f = |name: &str| format!("{field}.{name}");
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
    Ok((contact_stiffness, exponent))
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

pub(super) fn waviness(raw: &Spanned<WavinessFile>, field: &str) -> V<Waviness> {
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

pub(super) fn ring(raw: &Spanned<String>, field: &str) -> V<Ring> {
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
pub(super) fn defects(
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

pub(super) fn forcing_function(
    raw: &Spanned<ForcingFunctionFile>,
    field: &str,
) -> V<ForcingFunction> {
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

pub(super) fn clearance(raw: &Spanned<ClearanceFile>, field: &str) -> V<Clearance> {
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
