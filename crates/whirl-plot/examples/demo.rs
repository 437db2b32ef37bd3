//! Renders one figure of each kind with made-up rotor-like data.
//!
//! `cargo run -p whirl-plot --example demo -- [output directory]` (default `/tmp/whirl-plot-demo`).

use std::f64::consts::PI;
use std::path::PathBuf;

use whirl_plot::{
    Annotation, Colour, Figure2d, Grid, HeatMap, LegendPosition, Marker, PlotError, RefLine,
    Series, Style,
};

fn main() -> Result<(), PlotError> {
    let dir = std::env::args()
        .nth(1)
        .map_or_else(|| PathBuf::from("/tmp/whirl-plot-demo"), PathBuf::from);
    let written = [
        campbell().save(&dir.join("campbell"))?,
        bode().save(&dir.join("bode"))?,
        mode_shapes().save(&dir.join("mode_shapes"))?,
        orbit().save(&dir.join("orbit"))?,
        cascade().save(&dir.join("cascade"))?,
    ];
    for path in written.iter().flatten() {
        println!("{}", path.display());
    }
    Ok(())
}

fn linspace(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| a + (b - a) * i as f64 / (n - 1) as f64)
        .collect()
}

/// Forward and backward whirl branches splitting with speed, one branch lost for a while.
fn campbell() -> Figure2d {
    let speed = linspace(0.0, 12_000.0, 121); // rpm
    let mut fig = Figure2d::new(
        "Campbell diagram",
        "Rotor speed [rpm]",
        "Natural frequency [Hz]",
    );
    for (k, base) in [42.0, 118.0].iter().enumerate() {
        let fw: Vec<f64> = speed
            .iter()
            .map(|s| base + 0.0025 * s * (k + 1) as f64)
            .collect();
        let mut bw: Vec<f64> = speed
            .iter()
            .map(|s| base - 0.0018 * s * (k + 1) as f64)
            .collect();
        if k == 1 {
            bw[60..75].iter_mut().for_each(|v| *v = f64::NAN); // branch lost by the tracker
        }
        let colour = Colour::Palette(k);
        fig.series.push(
            Series::new(speed.clone(), fw)
                .label(format!("mode {} forward", k + 1))
                .style(Style::line_markers(colour, Marker::Triangle).marker_size(3)),
        );
        fig.series.push(
            Series::new(speed.clone(), bw)
                .label(format!("mode {} backward", k + 1))
                .style(Style::dashed(colour)),
        );
    }
    let one_x: Vec<f64> = speed.iter().map(|s| s / 60.0).collect();
    fig.series.push(
        Series::new(speed.clone(), one_x)
            .label("1X")
            .style(Style::solid(Colour::BLACK).width(1)),
    );
    fig.vertical_lines
        .push(RefLine::new(2_950.0).label("1st critical 2950 rpm"));
    fig.horizontal_lines
        .push(RefLine::new(150.0).label("150 Hz limit"));
    fig.annotations
        .push(Annotation::new(9_000.0, 150.0, "2X crossing").marked());
    fig.legend = LegendPosition::UpperLeft;
    fig
}

/// Magnitude (log) above phase of a single degree of freedom with 2 % damping.
fn bode() -> Grid {
    let f = linspace(1.0, 200.0, 400); // Hz
    let (fn_, zeta) = (60.0, 0.02);
    let h = |f: f64| {
        let r = f / fn_;
        (1.0 - r * r, 2.0 * zeta * r)
    };
    let mag: Vec<f64> = f
        .iter()
        .map(|&f| {
            let (a, b) = h(f);
            1e-6 / a.hypot(b)
        })
        .collect();
    let phase: Vec<f64> = f
        .iter()
        .map(|&f| {
            let (a, b) = h(f);
            -b.atan2(a).to_degrees()
        })
        .collect();
    let mut top = Figure2d::new("Unbalance response at bearing 1", "", "Amplitude [m]")
        .with_series(Series::new(f.clone(), mag).label("x"));
    top.log_y = true;
    top.vertical_lines.push(RefLine::new(fn_).label("60 Hz"));
    let mut bottom = Figure2d::new("", "Frequency [Hz]", "Phase [deg]")
        .with_series(Series::new(f, phase).label("x"));
    bottom.y_range = Some((-180.0, 0.0));
    bottom.legend = LegendPosition::Hidden;
    Grid::new("Bode plot", 2, 1)
        .with_panel(top)
        .with_panel(bottom)
}

/// Six bending mode shapes along a 1.2 m shaft, markers at the nodes.
fn mode_shapes() -> Grid {
    let z = linspace(0.0, 1.2, 25); // m
    let mut grid = Grid::new("Mode shapes", 2, 3);
    for m in 1..=6 {
        let shape: Vec<f64> = z.iter().map(|z| (m as f64 * PI * z / 1.2).sin()).collect();
        let mut panel = Figure2d::new(
            format!("Mode {m}: {:.1} Hz", 38.0 * (m * m) as f64),
            "Axial position [m]",
            "Displacement [-]",
        )
        .with_series(
            Series::new(z.clone(), shape)
                .label("horizontal")
                .style(Style::line_markers(Colour::Palette(0), Marker::Circle).marker_size(3)),
        );
        panel.legend = if m == 1 {
            LegendPosition::LowerLeft
        } else {
            LegendPosition::Hidden
        };
        grid.panels.push(panel);
    }
    grid
}

/// An elliptic orbit with a 2X loop, equal scales on both axes.
fn orbit() -> Figure2d {
    let t = linspace(0.0, 2.0 * PI, 361);
    let x: Vec<f64> = t
        .iter()
        .map(|t| 40e-6 * t.cos() + 8e-6 * (2.0 * t).cos())
        .collect();
    let y: Vec<f64> = t
        .iter()
        .map(|t| 15e-6 * t.sin() + 8e-6 * (2.0 * t).sin())
        .collect();
    let mut fig = Figure2d::new("Orbit at bearing 2, 3000 rpm", "x [m]", "y [m]")
        .with_series(Series::new(x.clone(), y.clone()).label("orbit"))
        .with_series(
            Series::new(vec![x[0]], vec![y[0]])
                .label("key phasor")
                .style(Style::markers(Colour::Palette(1), Marker::Circle).marker_size(6)),
        );
    fig.equal_aspect = true;
    fig
}

/// Spectrum amplitude over speed and frequency, with 1X and 2X order lines.
fn cascade() -> HeatMap {
    let speed = linspace(500.0, 6_000.0, 56); // rpm
    let freq = linspace(0.0, 250.0, 251); // Hz
    let z: Vec<Vec<f64>> = freq
        .iter()
        .map(|f| {
            speed
                .iter()
                .map(|s| {
                    let order = |k: f64, a: f64| a * (-((f - k * s / 60.0) / 2.0).powi(2)).exp();
                    let resonance = 2e-6 * (-((f - 60.0) / 4.0).powi(2)).exp();
                    1e-8 + order(1.0, 3e-5 * s / 6000.0) + order(2.0, 4e-6) + resonance
                })
                .collect()
        })
        .collect();
    let mut map = HeatMap::new(
        "Cascade at bearing 1",
        "Speed [rpm]",
        "Frequency [Hz]",
        "Amplitude [m]",
    )
    .with_data(speed.clone(), freq, z);
    map.log_colour = true;
    for (k, label) in [(1.0, "1X"), (2.0, "2X")] {
        let line: Vec<f64> = speed.iter().map(|s| k * s / 60.0).collect();
        map.overlays.push(
            Series::new(speed.clone(), line)
                .label(label)
                .style(Style::dashed(Colour::Palette(1)).width(1)),
        );
    }
    map.legend = LegendPosition::UpperLeft;
    map
}
