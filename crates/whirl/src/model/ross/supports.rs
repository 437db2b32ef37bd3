//! ROSS's point masses and bearings, linked or not, as whirl's disks, bearings and housings.
//!
//! ROSS numbers its support nodes after the shaft's: a point mass on such a node is a
//! housing (a pedestal), a bearing from node `n` to node `n_link` joins the two (to the
//! ground when `n_link` is absent). A bearing between the shaft and a support node becomes
//! a `[[bearing]]` in that housing; the bearings between a support node and the ground or
//! another support node become the housing's mounting (`on`, kxx ... cyy; bearings in
//! parallel add). A point mass on the shaft is a disk without inertia.

use std::fmt::Write;

use toml::{Table, Value};

use super::{
    bearing_coefficients, coefficient_lines, float, node, point_mass, quoted, refuse, tag,
};
use crate::error::Result;

/// The far end of a ROSS bearing: `n_link`, absent (or the string "None") for the ground.
fn link(key: &str, t: &Table) -> Result<Option<usize>> {
    match t.get("n_link") {
        None | Some(Value::String(_)) => Ok(None),
        Some(Value::Integer(i)) if *i >= 0 => Ok(Some(*i as usize)),
        Some(v) => Err(refuse(key, format!("has n_link = {v}, not a node index")).into()),
    }
}

/// A housing being gathered: its point mass and its mounting.
struct Pedestal<'a> {
    key: &'a str,
    node: usize,
    mass: f64,
    /// The node it is mounted on (`None`: ground) and the summed coefficients, once known.
    mounting: Option<(Option<usize>, [f64; 8], &'a str)>,
}

/// The disks, bearings and housings of ROSS's `point_masses` and `bearings` (key, table),
/// for a shaft of `elements` elements (nodes 0 to `elements`).
pub(super) fn translate<'a>(
    point_masses: &[(&'a str, &Table)],
    bearings: &[(&'a str, &Table)],
    elements: usize,
    notes: &mut Vec<String>,
) -> Result<(String, String)> {
    let mut disks = String::new();
    let mut pedestals: Vec<Pedestal<'a>> = Vec::new();
    for &(key, t) in point_masses {
        let mass = point_mass(key, t, notes)?;
        let n = node(key, t)?;
        if n <= elements {
            let _ = write!(
                disks,
                "[[disk]]\nname = {}\nnode = {n}\nmass = {}\npolar_inertia = 0\n\
                 diametral_inertia = 0\n\n",
                quoted(tag(key)),
                float(mass)
            );
        } else {
            pedestals.push(Pedestal {
                key,
                node: n,
                mass,
                mounting: None,
            });
        }
    }
    let pedestal_of = |n: usize, key: &str, pedestals: &[Pedestal]| -> Result<usize> {
        pedestals.iter().position(|p| p.node == n).ok_or_else(|| {
            refuse(
                key,
                format!(
                    "is linked to node {n}, past the shaft's last node ({elements}), where no \
                     point mass sits: whirl's housings need a mass"
                ),
            )
            .into()
        })
    };
    let mut shaft_bearings = String::new();
    for &(key, t) in bearings {
        let values = bearing_coefficients(key, t, notes)?;
        let (a, b) = (node(key, t)?, link(key, t)?);
        // A linear bearing acts on the relative motion of its two ends, alike both ways:
        // put the shaft's end first.
        let (a, b) = match b {
            Some(b) if b <= elements && a > elements => (b, Some(a)),
            _ => (a, b),
        };
        if a <= elements {
            let housing = match b {
                None => None,
                Some(b) if b <= elements => {
                    return Err(refuse(
                        key,
                        format!(
                            "joins shaft nodes {a} and {b}: whirl's bearings join the shaft to \
                             the ground or to a housing"
                        ),
                    )
                    .into())
                }
                Some(b) => Some(pedestal_of(b, key, &pedestals)?),
            };
            let _ = write!(
                shaft_bearings,
                "[[bearing]]\nname = {}\nnode = {a}\n",
                quoted(tag(key))
            );
            if let Some(h) = housing {
                let _ = writeln!(
                    shaft_bearings,
                    "housing = {}",
                    quoted(tag(pedestals[h].key))
                );
            }
            let _ = writeln!(shaft_bearings, "{}", coefficient_lines(&values));
            continue;
        }
        let h = pedestal_of(a, key, &pedestals)?;
        let on = b.map(|b| pedestal_of(b, key, &pedestals)).transpose()?;
        let pedestal = &mut pedestals[h];
        match &mut pedestal.mounting {
            None => pedestal.mounting = Some((on, values, key)),
            Some((first_on, sum, _)) if *first_on == on => {
                sum.iter_mut().zip(values).for_each(|(s, v)| *s += v);
            }
            Some((_, _, first)) => {
                return Err(refuse(
                    key,
                    format!(
                        "mounts the point mass on node {} elsewhere than `{first}` does: a \
                         whirl housing has one mounting (to the ground or to one other \
                         housing)",
                        pedestal.node
                    ),
                )
                .into())
            }
        }
    }
    let mut housings = String::new();
    for p in &pedestals {
        let Some((on, values, _)) = &p.mounting else {
            return Err(refuse(
                p.key,
                format!(
                    "is a point mass on support node {} without a bearing to the ground or to \
                     another support: nothing holds it",
                    p.node
                ),
            )
            .into());
        };
        let _ = write!(
            housings,
            "[[housing]]\nname = {}\nmass = {}\n",
            quoted(tag(p.key)),
            float(p.mass)
        );
        if let Some(o) = on {
            let _ = writeln!(housings, "on = {}", quoted(tag(pedestals[*o].key)));
        }
        let _ = writeln!(housings, "{}", coefficient_lines(values));
    }
    Ok((disks, housings + &shaft_bearings))
}
