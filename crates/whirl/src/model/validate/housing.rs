//! `[[housing]]` -> [`Housing`]: the support checked, the mounting resolved to an index
//! (never the housing itself, never a loop), and the bearings' `housing` resolved.

use super::*;

/// Every housing of the file, validated, with `on` resolved.
pub(super) fn housings(raw: &[Spanned<HousingFile>]) -> V<Vec<Housing>> {
    let names = names(raw)?;
    let out = raw
        .iter()
        .enumerate()
        .map(|(i, h)| housing(h, &format!("housing[{i}]"), &names))
        .collect::<V<Vec<_>>>()?;
    refuse_loops(raw, &out)?;
    Ok(out)
}

/// The housings' names, each once.
fn names(raw: &[Spanned<HousingFile>]) -> V<Vec<String>> {
    let mut names: Vec<String> = Vec::with_capacity(raw.len());
    for (i, h) in raw.iter().enumerate() {
        let name = &h.get_ref().name;
        if names.contains(name.get_ref()) {
            return Err(err(
                &format!("housing[{i}].name"),
                name.span(),
                format!("another housing is already named \"{}\"", name.get_ref()),
            )
            .help("bearings and housings refer to a housing by its name: give each its own"));
        }
        names.push(name.get_ref().clone());
    }
    Ok(names)
}

/// The index of the housing `name` refers to; `None` (the ground) when absent.
pub(super) fn reference(
    name: &Option<Spanned<String>>,
    names: &[String],
    field: &str,
) -> V<Option<usize>> {
    let Some(name) = name else { return Ok(None) };
    names
        .iter()
        .position(|n| n == name.get_ref())
        .map(Some)
        .ok_or_else(|| {
            let known = if names.is_empty() {
                "the file has no [[housing]]".to_string()
            } else {
                format!("the housings are {}", quoted_list(names))
            };
            err(
                field,
                name.span(),
                format!("no housing is named \"{}\"", name.get_ref()),
            )
            .help(format!(
                "{known}; leave the field out to mount it on the ground"
            ))
        })
}

fn quoted_list(names: &[String]) -> String {
    names
        .iter()
        .map(|n| format!("\"{n}\""))
        .collect::<Vec<_>>()
        .join(", ")
}

fn housing(raw: &Spanned<HousingFile>, field: &str, names: &[String]) -> V<Housing> {
    let h = raw.get_ref();
    let f = |name: &str| format!("{field}.{name}");
    let mass = positive_q(&h.mass, Dimension::Mass, &f("mass"))?;
    let on = reference(&h.on, names, &f("on"))?;
    if on.is_some_and(|o| names[o] == *h.name.get_ref()) {
        let span = h.on.as_ref().map_or(raw.span(), |o| o.span());
        return Err(err(&f("on"), span, "a housing cannot be mounted on itself")
            .help("name the housing (or casing) it sits on, or leave `on` out for the ground"));
    }
    let kxx = opt_non_negative(&h.kxx, &f("kxx"), "N/m")?;
    let kyy = opt_non_negative(&h.kyy, &f("kyy"), "N/m")?;
    for (k, name) in [(kxx, "kxx"), (kyy, "kyy")] {
        if k <= 0.0 {
            let span = match name {
                "kxx" => h.kxx.as_ref(),
                _ => h.kyy.as_ref(),
            }
            .map_or(raw.span(), |s| s.span());
            return Err(err(
                &f(name),
                span,
                "a housing needs a support stiffness in x and in y: without it the housing \
                 (and the rotor in it) is free to drift",
            )
            .help(
                "give kxx and kyy (N/m) of its mounting; for a squeeze-film damper this is \
                 the centring spring",
            ));
        }
    }
    let cxx = opt_non_negative(&h.cxx, &f("cxx"), "N s/m")?;
    let cyy = opt_non_negative(&h.cyy, &f("cyy"), "N s/m")?;
    Ok(Housing {
        name: h.name.get_ref().clone(),
        mass,
        on,
        stiffness: [
            [kxx, opt_f64(&h.kxy, &f("kxy"), 0.0)?],
            [opt_f64(&h.kyx, &f("kyx"), 0.0)?, kyy],
        ],
        damping: [
            [cxx, opt_f64(&h.cxy, &f("cxy"), 0.0)?],
            [opt_f64(&h.cyx, &f("cyx"), 0.0)?, cyy],
        ],
        squeeze_film: h
            .squeeze_film
            .as_ref()
            .map(|s| squeeze_film(s, &f("squeeze_film")))
            .transpose()?,
    })
}

/// Refuses a chain of mountings that comes back to where it started (A on B on A): such
/// housings are held by nothing.
fn refuse_loops(raw: &[Spanned<HousingFile>], housings: &[Housing]) -> V<()> {
    for start in 0..housings.len() {
        let mut at = start;
        for _ in 0..housings.len() {
            match housings[at].on {
                Some(next) if next == start => {
                    let on = raw[start].get_ref().on.as_ref();
                    let span = on.map_or(raw[start].span(), |o| o.span());
                    return Err(err(
                        &format!("housing[{start}].on"),
                        span,
                        format!(
                            "housing \"{}\" is mounted, through others, on itself: the chain \
                             of `on` never reaches the ground",
                            housings[start].name
                        ),
                    )
                    .help("mount one housing of the chain on the ground (leave its `on` out)"));
                }
                Some(next) => at = next,
                None => break,
            }
        }
    }
    Ok(())
}

fn squeeze_film(raw: &Spanned<SqueezeFilmFile>, field: &str) -> V<SqueezeFilm> {
    let s = raw.get_ref();
    let f = |name: &str| format!("{field}.{name}");
    let cavitation = match s.cavitation.as_ref() {
        None => Cavitation::Pi,
        Some(c) => match c.get_ref().as_str() {
            "pi" => Cavitation::Pi,
            "full" => Cavitation::Full,
            other => {
                return Err(err(
                    &f("cavitation"),
                    c.span(),
                    format!("unknown cavitation \"{other}\""),
                )
                .help("\"pi\" (cavitated film, the default) or \"full\" (uncavitated)"))
            }
        },
    };
    let clearance = positive_q(&s.clearance, Dimension::Length, &f("clearance"))?;
    let offset = [&s.offset_x, &s.offset_y].map(|o| o.as_ref());
    let mut xy = [0.0; 2];
    for (k, (o, name)) in offset.iter().zip(["offset_x", "offset_y"]).enumerate() {
        if let Some(o) = o {
            xy[k] = quantity(o, Dimension::Length, &f(name))?;
        }
    }
    Ok(SqueezeFilm {
        radius: positive_q(&s.radius, Dimension::Length, &f("radius"))?,
        length: positive_q(&s.length, Dimension::Length, &f("length"))?,
        clearance,
        viscosity: positive(
            *s.viscosity.get_ref(),
            s.viscosity.span(),
            &f("viscosity"),
            "Pa s",
        )?,
        cavitation,
        offset: xy,
    })
}
