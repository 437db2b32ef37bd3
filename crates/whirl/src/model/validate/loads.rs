//! Damping, `[[unbalance]]` and `[operating]` -> Rayleigh damping, unbalance phasors and the
//! operating speed range.

use super::*;

/// `[damping]`: the coefficients as given (alpha/beta or ratios), times `scale`. Scaling both
/// coefficients scales the damping ratio at every frequency alike (zeta = alpha / (2 w) +
/// beta w / 2), which is what a study of damping varies.
pub(super) fn damping(raw: &Spanned<DampingFile>) -> V<RayleighDamping> {
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

pub(super) fn unbalance(
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

pub(super) fn operating(raw: &Spanned<OperatingFile>) -> V<(f64, f64)> {
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
