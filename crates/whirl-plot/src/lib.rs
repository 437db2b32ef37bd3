//! PNG and SVG figures for whirl, built on `plotters`.
//!
//! This crate knows nothing about rotors: it draws generic figures, and whirl-figures maps
//! analysis results (Campbell diagrams, mode shapes, orbits, Bode plots, cascades) onto them.
//! Figures are plain data and serialise (serde) to a specification another renderer can draw
//! (the Python package's matplotlib); [`NamedFigure`] is one with the stem of its files.
//!
//! | figure | type | typical use |
//! |---|---|---|
//! | x-y lines and markers | [`Figure2d`] | Campbell diagram, unbalance response, time series |
//! | panels in rows x columns | [`Grid`] | mode shapes of six modes, Bode magnitude above phase |
//! | colour map with overlays | [`HeatMap`] | cascade (waterfall seen from above) with order lines |
//! | colour maps in rows x columns | [`HeatMapGrid`] | the cascades of a parameter study |
//!
//! Every figure is saved twice by `save(stem)`: `stem.png` (raster, about 1000 x 700 pixels,
//! drawn at twice that size and averaged down because plotters does not anti-alias lines) and
//! `stem.svg` (vector; heat map cells are one embedded PNG). Text is drawn with DejaVu Sans
//! embedded in the binary (see `assets/README.md`), so nothing depends on fontconfig or on the
//! fonts installed on a machine.
//!
//! Data that cannot be drawn never panics: NaN and infinite values break a line into segments,
//! non-positive values are dropped from logarithmic axes, an empty figure is drawn with empty axes
//! and a degenerate range (all values equal) is padded. Only inconsistent input (x and y of
//! different lengths, an explicit range that is reversed or not finite, a ragged heat map) is an
//! error, [`PlotError`], reported before any file is written.
//!
//! ```no_run
//! use whirl_plot::{Figure2d, Series, Style, Colour, Marker};
//!
//! let speed: Vec<f64> = (0..=100).map(|i| i as f64 * 100.0).collect(); // rpm
//! let freq: Vec<f64> = speed.iter().map(|s| 40.0 + 0.002 * s).collect(); // Hz
//! let one_x: Vec<f64> = speed.iter().map(|s| s / 60.0).collect(); // Hz
//! let mut fig = Figure2d::new("Campbell diagram", "Speed [rpm]", "Frequency [Hz]");
//! fig.series.push(Series::new(speed.clone(), freq).label("mode 1 forward"));
//! fig.series.push(
//!     Series::new(speed, one_x)
//!         .label("1X")
//!         .style(Style::dashed(Colour::Rgb(80, 80, 80))),
//! );
//! let written = fig.save(std::path::Path::new("out/campbell"))?;
//! assert_eq!(written.len(), 2); // out/campbell.png and out/campbell.svg
//! # Ok::<(), whirl_plot::PlotError>(())
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod axis;
mod chart;
mod clip;
mod colormap;
mod figure;
mod font;
mod grid;
mod heatmap;
mod heatmap_grid;
mod marker;
mod named;
mod render;
mod rpm;
mod series;
mod style;

pub use colormap::viridis;
pub use figure::{Annotation, Figure2d, RefLine};
pub use font::{FONT_BYTES, FONT_FAMILY};
pub use grid::Grid;
pub use heatmap::HeatMap;
pub use heatmap_grid::HeatMapGrid;
pub use named::{Figure, NamedFigure, SpeedMarks};
pub use rpm::{SpeedAxis, SpeedInRpm, RPM_PER_HZ};
pub use series::{LegendPosition, Series};
pub use style::{Colour, Line, Marker, Style, PALETTE};

/// Size in pixels of a single figure (PNG; the SVG uses the same user units).
pub const FIGURE_SIZE: (u32, u32) = (1000, 700);

/// Why a figure could not be drawn or written.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The embedded font could not be parsed or registered with plotters.
    #[error("the embedded font could not be registered with plotters")]
    Font,
    /// A series has x and y vectors of different lengths.
    #[error("series {label:?}: x has {x_len} values but y has {y_len}")]
    LengthMismatch {
        /// The series label, or its index if it has none.
        label: String,
        /// Number of x values.
        x_len: usize,
        /// Number of y values.
        y_len: usize,
    },
    /// The shape of a heat map's data does not match its axes.
    #[error("heat map: {0}")]
    Shape(String),
    /// An explicit axis range cannot be used.
    #[error("invalid {axis} range ({lo}, {hi}): {reason}")]
    InvalidRange {
        /// Which axis: "x", "y" or "colour".
        axis: &'static str,
        /// Requested lower limit.
        lo: f64,
        /// Requested upper limit.
        hi: f64,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// A grid has no cells or fewer cells than panels.
    #[error("grid of {rows} x {cols} cannot hold {panels} panels")]
    GridShape {
        /// Rows requested.
        rows: usize,
        /// Columns requested.
        cols: usize,
        /// Panels supplied.
        panels: usize,
    },
    /// The figure (or a grid panel) is smaller than 200 x 150 pixels.
    #[error("figure size {0} x {1} pixels is below the minimum of 200 x 150")]
    TooSmall(u32, u32),
    /// Creating the output directory or writing a file failed.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The directory or file that could not be written.
        path: std::path::PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// plotters failed while drawing or writing a file.
    #[error("drawing {path} failed: {message}")]
    Draw {
        /// The file being written.
        path: std::path::PathBuf,
        /// plotters' description of the failure.
        message: String,
    },
}
