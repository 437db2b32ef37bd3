//! The figure of `whirl fit-forcing`: a roller bearing's contact force over its deflection
//! beyond the clearance, log-log, the samples and the fitted forcing function per speed.

use whirl::time::ForcingFit;
use whirl::units::rad_s_to_hz as hz;
use whirl_plot::{Colour, Figure2d, LegendPosition, Marker, Series, Style};

/// Samples drawn per speed in the plot: enough to show the cloud, few enough to keep the
/// SVG small (fit.csv has them all).
const PLOTTED_SAMPLES: usize = 300;

/// Force over deflection beyond the clearance, log-log: each speed's samples as dots and
/// the law at that speed as a line through the same deflections.
pub fn force_deflection(fit: &ForcingFit) -> Figure2d {
    let mut fig = Figure2d::new(
        format!("Forcing function of {}", fit.bearing),
        "Deflection beyond the clearance u_r - γ [µm]",
        "Contact force [N]",
    );
    fig.log_x = true;
    fig.log_y = true;
    fig.legend = LegendPosition::LowerRight;
    for (k, s) in fit.speeds.iter().enumerate() {
        let mut at: Vec<_> = fit.points.iter().filter(|p| p.speed == s.speed).collect();
        at.sort_by(|a, b| a.deflection.total_cmp(&b.deflection));
        let gamma = fit.clearance.at_speed(s.speed);
        let micro = |d: f64| 1e6 * (d - gamma);
        let every = at.len().div_ceil(PLOTTED_SAMPLES).max(1);
        let shown: Vec<_> = at.iter().step_by(every).collect();
        let colour = Colour::Palette(k);
        fig.series.push(
            Series::new(
                shown.iter().map(|p| micro(p.deflection)).collect(),
                shown.iter().map(|p| p.force).collect(),
            )
            .style(Style::markers(colour, Marker::Circle).marker_size(2)),
        );
        fig.series.push(
            Series::new(
                at.iter().map(|p| micro(p.deflection)).collect(),
                at.iter().map(|p| fit.fitted(p)).collect(),
            )
            .label(format!("{:.0} Hz", hz(s.speed)))
            .style(Style::solid(colour).width(2)),
        );
    }
    fig
}
