//! Figures of `whirl stiffness`: equivalent stiffness versus clearance (thesis fig. 3.10)
//! and force-deflection surfaces as heat maps (figs. 3.8-3.9). Displacements in µm,
//! stiffness in MN/m, forces in N.

use std::f64::consts::PI;

use whirl::bearing::stiffness::{ForceSurface, Stiffness2, StiffnessStudy};
use whirl_plot::{Colour, Figure2d, Grid, HeatMap, LegendPosition, Line, Marker, Series, Style};

use whirl::bearing::stiffness::clearance_label;

/// One force component of a surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Component {
    /// F_x.
    Fx,
    /// F_y.
    Fy,
    /// F_r = sqrt(F_x^2 + F_y^2).
    Fr,
}

impl Component {
    /// All three, in file order.
    pub const ALL: [Component; 3] = [Component::Fx, Component::Fy, Component::Fr];

    /// Short name for file names: `fx`.
    pub fn name(self) -> &'static str {
        match self {
            Component::Fx => "fx",
            Component::Fy => "fy",
            Component::Fr => "fr",
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Component::Fx => "Horizontal force on the shaft F_x [N]",
            Component::Fy => "Vertical force on the shaft F_y [N]",
            Component::Fr => "Radial force F_r [N]",
        }
    }

    fn values(self, s: &ForceSurface) -> &Vec<Vec<f64>> {
        match self {
            Component::Fx => &s.fx,
            Component::Fy => &s.fy,
            Component::Fr => &s.fr,
        }
    }
}

/// MN/m from N/m.
fn mega(values: impl Iterator<Item = f64>) -> Vec<f64> {
    values.map(|k| k * 1e-6).collect()
}

/// One panel (kxx or kyy) with the three kinds of stiffness over clearance.
fn stiffness_panel(study: &StiffnessStudy, name: &str, entry: fn(&Stiffness2) -> f64) -> Figure2d {
    let mut panel = Figure2d::new(name, "Radial clearance [µm]", format!("{name} [MN/m]"));
    let gamma: Vec<f64> = study.clearances.iter().map(|c| c.clearance * 1e6).collect();
    let c = &study.clearances;
    let series = [
        (
            "frozen cage, equilibrium",
            mega(c.iter().map(|c| entry(&c.frozen.tangent.stiffness))),
            Style::line_markers(Colour::Palette(0), Marker::Circle),
        ),
        (
            "passage average",
            mega(c.iter().map(|c| entry(&c.averaged.mean))),
            Style::line_markers(Colour::Palette(1), Marker::Square),
        ),
        (
            "fixed displacement",
            mega(c.iter().map(|c| entry(&c.fixed.stiffness))),
            Style {
                line: Line::Dashed,
                ..Style::line_markers(Colour::Palette(2), Marker::Triangle)
            },
        ),
    ];
    for (label, k, style) in series {
        panel
            .series
            .push(Series::new(gamma.clone(), k).label(label).style(style));
    }
    // The passage's spread: the varying compliance as the rollers pass.
    let spread = Style {
        line: Line::Dotted,
        ..Style::solid(Colour::Palette(1)).width(1)
    };
    panel.series.push(
        Series::new(
            gamma.clone(),
            mega(c.iter().map(|c| entry(&c.averaged.min))),
        )
        .label("passage min / max")
        .style(spread),
    );
    panel
        .series
        .push(Series::new(gamma, mega(c.iter().map(|c| entry(&c.averaged.max)))).style(spread));
    // Stiffness is never negative; from zero, with room above for the legend.
    let top = panel
        .series
        .iter()
        .flat_map(|s| s.y.iter().copied())
        .filter(|k| k.is_finite())
        .fold(0.0, f64::max);
    panel.y_range = Some((0.0, if top > 0.0 { 1.35 * top } else { 1.0 }));
    panel.legend = LegendPosition::UpperRight;
    panel
}

/// k_xx and k_yy versus clearance, the three kinds side by side (thesis fig. 3.10).
pub fn stiffness_vs_clearance(study: &StiffnessStudy) -> Grid {
    let w = study.load;
    let mut grid = Grid::new(
        format!(
            "{}: equivalent stiffness, load ({:.1}, {:.1}) N, roller 0 at {:.1} deg",
            study.bearing,
            w[0],
            w[1],
            study.cage_angle.to_degrees()
        ),
        1,
        2,
    );
    grid.panels.push(stiffness_panel(study, "k_xx", |k| k.kxx));
    grid.panels.push(stiffness_panel(study, "k_yy", |k| k.kyy));
    grid
}

/// A circle of radius `r` (µm) about the origin, closed.
fn circle(r: f64) -> Series {
    let n = 180;
    let (x, y) = (0..=n)
        .map(|k| {
            let t = 2.0 * PI * k as f64 / n as f64;
            (r * t.cos(), r * t.sin())
        })
        .unzip();
    Series::new(x, y)
}

/// One force component over the displacement grid, the clearance circle drawn on top
/// (thesis figs. 3.8-3.9).
pub fn force_surface(surface: &ForceSurface, component: Component) -> HeatMap {
    let gamma = surface.clearance * 1e6;
    let mut map = HeatMap::new(
        format!(
            "{} at clearance {}, roller 0 at {:.1} deg",
            component.describe(),
            clearance_label(surface.clearance),
            surface.cage_angle.to_degrees()
        ),
        "u_x [µm]",
        "u_y [µm]",
        component.describe(),
    )
    .with_data(
        surface.ux.iter().map(|x| x * 1e6).collect(),
        surface.uy.iter().map(|y| y * 1e6).collect(),
        component.values(surface).clone(),
    );
    map.overlays.push(
        circle(gamma)
            .label(format!("clearance {}", clearance_label(surface.clearance)))
            .style(Style::dashed(Colour::Rgb(255, 255, 255)).width(2)),
    );
    // The radial force spans zero to tens of kN: a logarithmic scale shows the whole range,
    // and draws the force-free zone (F_r = 0) grey.
    map.log_colour = component == Component::Fr;
    // Near-equal scales on u_x and u_y, so that the clearance circle looks round.
    map.size = (1000, 820);
    map.legend = LegendPosition::UpperRight;
    map
}
