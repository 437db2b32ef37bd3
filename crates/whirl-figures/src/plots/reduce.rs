//! Figures of a Craig-Bampton reduction study (thesis fig. 4.3): frequency error and
//! stable time step against the number of fixed-interface modes.

use whirl::reduce::ReductionStudy;
use whirl_plot::{Colour, Figure2d, Line, Marker, RefLine, Series, Style};

/// The error plot follows this many of the lowest modes.
const PLOTTED_MODES: usize = 4;

/// Marker shapes that tell apart modes whose curves coincide (an isotropic rotor's modes
/// come in pairs of equal frequency).
const MARKERS: [Marker; 4] = [
    Marker::Circle,
    Marker::Triangle,
    Marker::Square,
    Marker::Cross,
];

fn mode_counts(study: &ReductionStudy) -> Vec<f64> {
    study.rows.iter().map(|r| r.modes as f64).collect()
}

/// Relative error of the lowest modes' frequencies against the number of modes kept,
/// logarithmic (a mode the reduced model does not have yet is left out).
pub fn reduction_error(study: &ReductionStudy) -> Figure2d {
    let mut fig = Figure2d::new(
        format!(
            "Craig-Bampton frequency error ({} boundary DOFs, full model {} DOFs)",
            study.boundary_dofs, study.full_dofs
        ),
        "Fixed-interface modes kept",
        "|Relative frequency error| [-]",
    );
    fig.log_y = true;
    let x = mode_counts(study);
    let modes = study.full_frequencies_hz.len().min(PLOTTED_MODES);
    for (j, marker) in MARKERS.iter().enumerate().take(modes) {
        let y: Vec<f64> = study
            .rows
            .iter()
            .map(|r| r.relative_error.get(j).map_or(f64::NAN, |e| e.abs()))
            .collect();
        let style = Style {
            line: if j % 2 == 0 {
                Line::Solid
            } else {
                Line::Dashed
            },
            ..Style::line_markers(Colour::Palette(j), *marker)
        };
        fig.series.push(
            Series::new(x.clone(), y)
                .label(format!(
                    "mode {} ({:.2} Hz)",
                    j + 1,
                    study.full_frequencies_hz[j]
                ))
                .style(style),
        );
    }
    fig
}

/// The explicit central difference's stable step of each reduced model, and of the full
/// model as a reference line.
pub fn stable_steps(study: &ReductionStudy) -> Figure2d {
    let mut fig = Figure2d::new(
        "Stability limit of the central difference, 2 / w_max",
        "Fixed-interface modes kept",
        "Largest stable time step [s]",
    );
    fig.log_y = true;
    let y: Vec<f64> = study.rows.iter().map(|r| r.stable_step).collect();
    fig.series.push(
        Series::new(mode_counts(study), y)
            .label("reduced model")
            .style(Style::line_markers(Colour::Palette(0), Marker::Circle)),
    );
    fig.horizontal_lines.push(
        RefLine::new(study.full_stable_step)
            .label(format!("full model {:.3e} s", study.full_stable_step)),
    );
    // Room below for the full model's line, which lies under every reduced model's limit.
    let top = study.rows.iter().map(|r| r.stable_step).fold(0.0, f64::max);
    if top > 0.0 {
        fig.y_range = Some((0.5 * study.full_stable_step, 2.0 * top));
    }
    fig
}
