//! Figures of the static response: deflection, bending moment and shear force along the
//! shaft with the bearings and disks marked on the shaft line, and the roller loads.

use whirl::model::Model;
use whirl::statics::{BearingReaction, StaticResult, Station};
use whirl_plot::{
    Annotation, Colour, Figure2d, Grid, LegendPosition, Marker, RefLine, Series, Style,
};

/// One plotted quantity of a station, [x, y].
type Quantity = fn(&Station) -> [f64; 2];

/// Deflection (µm), bending moment (N m) and shear force (N) along the shaft, one panel
/// each; y (vertical) solid, x dashed; triangles mark bearings and circles disks on the
/// shaft line (value 0).
pub fn static_response(model: &Model, result: &StaticResult) -> Grid {
    let z: Vec<f64> = result.stations.iter().map(|s| s.z).collect();
    let pick = |f: Quantity, plane: usize, scale: f64| {
        result
            .stations
            .iter()
            .map(|s| scale * f(s)[plane])
            .collect::<Vec<f64>>()
    };
    let panels: [(&str, &str, Quantity, f64); 3] = [
        ("Deflection", "Deflection [µm]", |s| s.deflection, 1e6),
        (
            "Bending moment (sagging positive)",
            "Moment [N m]",
            |s| s.moment,
            1.0,
        ),
        ("Shear force", "Shear force [N]", |s| s.shear, 1.0),
    ];
    let mut grid = Grid::new(
        format!(
            "{}: static response to its weight of {} N",
            model.name,
            fmt_force(result.weight)
        ),
        3,
        1,
    );
    grid.size = (1000, 1100);
    for (k, (title, label, f, scale)) in panels.into_iter().enumerate() {
        let title = if k == 0 {
            format!(
                "{title}: largest {:.2} µm at z = {:.3} m",
                1e6 * result.max_deflection.value,
                result.max_deflection.z
            )
        } else {
            title.to_string()
        };
        let mut fig = Figure2d::new(title, "Axial position z [m]", label);
        let y = pick(f, 1, scale);
        let x = pick(f, 0, scale);
        let span = |v: &[f64]| v.iter().fold(0.0f64, |m, a| m.max(a.abs()));
        let (sy, sx) = (span(&y), span(&x));
        fig.series.push(
            Series::new(z.clone(), y.clone())
                .label("y (vertical)")
                .style(Style::solid(Colour::Palette(0))),
        );
        // Round-off in a direction without load (1e-10 of the other) is not drawn.
        if sx > 1e-6 * sy {
            fig.series.push(
                Series::new(z.clone(), x.clone())
                    .label("x (horizontal)")
                    .style(Style::dashed(Colour::Palette(1))),
            );
        }
        mark_supports(&mut fig, model, &result.reactions);
        fig.horizontal_lines.push(RefLine::new(0.0));
        if k == 0 {
            // Room below the curves for the legend, which explains every panel.
            let lo = y.iter().chain(&x).fold(0.0f64, |m, &v| m.min(v));
            let hi = y.iter().chain(&x).fold(0.0f64, |m, &v| m.max(v));
            let h = hi - lo;
            if h > 0.0 {
                fig.y_range = Some((lo - 0.6 * h, hi + 0.15 * h));
            }
            fig.legend = LegendPosition::LowerRight;
        } else {
            fig.legend = LegendPosition::Hidden;
        }
        grid.panels.push(fig);
    }
    grid
}

/// Bearings (triangles) and disks (circles) on the shaft line, named.
fn mark_supports(fig: &mut Figure2d, model: &Model, reactions: &[BearingReaction]) {
    let zb: Vec<f64> = reactions.iter().map(|r| r.z).collect();
    if !zb.is_empty() {
        fig.series.push(
            Series::new(zb.clone(), vec![0.0; zb.len()])
                .label("bearing")
                .style(Style::markers(Colour::Palette(2), Marker::Triangle).marker_size(8)),
        );
    }
    let zd: Vec<f64> = model.disks.iter().map(|d| d.station.z).collect();
    if !zd.is_empty() {
        fig.series.push(
            Series::new(zd.clone(), vec![0.0; zd.len()])
                .label("disk")
                .style(Style::markers(Colour::Palette(3), Marker::Circle).marker_size(7)),
        );
    }
    for r in reactions {
        fig.annotations
            .push(Annotation::new(r.z, 0.0, r.name.clone()));
    }
}

/// A force for a title, N, without needless digits.
fn fmt_force(f: f64) -> String {
    format!("{:.4}", f)
        .trim_end_matches('0')
        .trim_end_matches('.')
        .to_string()
}

/// Markers and sizes of successive bearings in [`roller_loads`].
const MARKERS: [(Marker, u32); 3] = [
    (Marker::Circle, 5),
    (Marker::OpenCircle, 9),
    (Marker::Square, 12),
];

/// Each roller's load against its angle, one series per roller bearing.
pub fn roller_loads(model: &Model, result: &StaticResult) -> Figure2d {
    let mut fig = Figure2d::new(
        format!("{}: roller loads at the static equilibrium", model.name),
        "Roller angle [deg] (270 = bottom)",
        "Contact load [N]",
    );
    for (k, r) in result
        .reactions
        .iter()
        .filter(|r| !r.rollers.is_empty())
        .enumerate()
    {
        let (a, f): (Vec<f64>, Vec<f64>) = r.rollers.iter().map(|q| (q.angle_deg, q.force)).unzip();
        // Filled and open markers of different sizes: equal loads stay visible.
        let (marker, size) = MARKERS[k % MARKERS.len()];
        fig.series.push(
            Series::new(a, f)
                .label(r.name.clone())
                .style(Style::markers(Colour::Palette(k), marker).marker_size(size)),
        );
    }
    fig.x_range = Some((0.0, 360.0));
    fig.vertical_lines.push(RefLine::new(270.0).label("bottom"));
    fig.legend = LegendPosition::UpperLeft;
    fig
}
