//! Colour map (heat map) of z over a rectilinear x-y grid, with a colour bar and optional line
//! overlays: the view from above of a cascade (amplitude over speed and frequency) with the
//! order lines 1X, 2X drawn on top.
//!
//! Each value `z[j][i]` fills the cell around `(x[i], y[j])` whose edges lie halfway to the
//! neighbouring grid points (half a step beyond the outer points), so uneven grids are drawn
//! faithfully. The cells are rasterised into one bitmap at the resolution of the plotting area;
//! the SVG file embeds that bitmap as a PNG instead of one rectangle per cell.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontTransform;

use crate::axis::{to_chart, widen_if_degenerate, Axis};
use crate::chart::{
    draw_error, draw_mesh, draw_title, font, split_title, text_width, Built, Frame, TickedRange,
};
use crate::colormap::{viridis, MISSING};
use crate::font::Metrics;
use crate::render::{save, Render};
use crate::series::{draw_all, draw_legend, LegendPosition, Series};
use crate::{PlotError, FIGURE_SIZE};

/// A colour map of `z` over the grid `x` by `y`.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HeatMap {
    /// Title above the plot; empty for none.
    pub title: String,
    /// x axis description, with unit.
    pub x_label: String,
    /// y axis description, with unit.
    pub y_label: String,
    /// Colour bar description, with unit: `"Amplitude [m]"`.
    pub colour_label: String,
    /// Grid abscissae: finite and strictly increasing.
    pub x: Vec<f64>,
    /// Grid ordinates: finite and strictly increasing.
    pub y: Vec<f64>,
    /// Values, one row per y: `z[j][i]` belongs to `(x[i], y[j])`. NaN cells are drawn grey.
    pub z: Vec<Vec<f64>>,
    /// Colour by `log10(z)`; cells with z <= 0 are drawn grey.
    pub log_colour: bool,
    /// Values at the two ends of the colour scale; `None` spans the data. Values outside are
    /// drawn in the end colours.
    pub z_range: Option<(f64, f64)>,
    /// Curves drawn over the colours (clipped to the grid).
    pub overlays: Vec<Series>,
    /// Legend position for labelled overlays.
    pub legend: LegendPosition,
    /// Size in pixels.
    pub size: (u32, u32),
}

impl HeatMap {
    /// A heat map with title and descriptions and no data yet.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
        colour_label: impl Into<String>,
    ) -> Self {
        HeatMap {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            colour_label: colour_label.into(),
            x: Vec::new(),
            y: Vec::new(),
            z: Vec::new(),
            log_colour: false,
            z_range: None,
            overlays: Vec::new(),
            legend: LegendPosition::default(),
            size: FIGURE_SIZE,
        }
    }

    /// The same heat map with grid and values (`z[j][i]` at `(x[i], y[j])`).
    pub fn with_data(self, x: Vec<f64>, y: Vec<f64>, z: Vec<Vec<f64>>) -> Self {
        HeatMap { x, y, z, ..self }
    }

    /// Writes `stem.png` and `stem.svg` (creating the parent directory if needed) and returns
    /// their paths, PNG first.
    pub fn save(&self, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
        save(self, stem)
    }

    /// Checks the data and works out cells and axes.
    fn layout(&self) -> Result<Layout, PlotError> {
        increasing("x", &self.x)?;
        increasing("y", &self.y)?;
        if self.z.len() != self.y.len() {
            let msg = format!(
                "z has {} rows but y has {} values",
                self.z.len(),
                self.y.len()
            );
            return Err(PlotError::Shape(msg));
        }
        if let Some((j, row)) = self
            .z
            .iter()
            .enumerate()
            .find(|(_, r)| r.len() != self.x.len())
        {
            let msg = format!(
                "z row {j} has {} values but x has {}",
                row.len(),
                self.x.len()
            );
            return Err(PlotError::Shape(msg));
        }
        for (i, s) in self.overlays.iter().enumerate() {
            s.check(i)?;
        }
        let (xe, ye) = (cell_edges(&self.x), cell_edges(&self.y));
        let axis = |name, edges: &[f64]| match (edges.first(), edges.last()) {
            (Some(&lo), Some(&hi)) => Axis::resolve(name, [], Some((lo, hi)), false, 0.0),
            _ => Axis::resolve(name, [], None, false, 0.0),
        };
        let (x, y) = (axis("x", &xe)?, axis("y", &ye)?);
        let values = self.z.iter().flatten().copied();
        let colour = Axis::resolve("colour", values, self.z_range, self.log_colour, 0.0)?;
        Ok(Layout {
            x_edges: xe,
            y_edges: ye,
            x,
            y,
            colour,
        })
    }
}

/// Cells and axes of a heat map.
struct Layout {
    /// Cell edges along x, `x.len() + 1` of them (none without data).
    x_edges: Vec<f64>,
    /// Cell edges along y.
    y_edges: Vec<f64>,
    x: Axis,
    y: Axis,
    /// The colour scale in chart space (log10 of z when logarithmic).
    colour: Axis,
}

/// Fails unless all values are finite and strictly increasing.
fn increasing(name: &str, v: &[f64]) -> Result<(), PlotError> {
    let finite = v.iter().all(|a| a.is_finite());
    if finite && v.windows(2).all(|w| w[0] < w[1]) {
        Ok(())
    } else {
        let msg = format!("{name} must be finite and strictly increasing");
        Err(PlotError::Shape(msg))
    }
}

/// Edges of the cells around the grid points `c` (length `c.len() + 1`, or 0 when empty).
fn cell_edges(c: &[f64]) -> Vec<f64> {
    match c {
        [] => Vec::new(),
        [only] => {
            let (lo, hi) = widen_if_degenerate(*only, *only, false);
            vec![lo, hi]
        }
        [first, second, ..] => {
            let n = c.len();
            let mut e = Vec::with_capacity(n + 1);
            e.push(first - 0.5 * (second - first));
            e.extend(c.windows(2).map(|w| 0.5 * (w[0] + w[1])));
            e.push(c[n - 1] + 0.5 * (c[n - 1] - c[n - 2]));
            e
        }
    }
}

/// For each of `n` pixel centres across `axis` (upwards when `flip`), the cell index under it.
fn pixel_cells(axis: &Axis, edges: &[f64], n: u32, flip: bool) -> Vec<Option<usize>> {
    (0..n)
        .map(|p| {
            let f = (f64::from(p) + 0.5) / f64::from(n);
            let v = if flip {
                axis.hi - f * (axis.hi - axis.lo)
            } else {
                axis.lo + f * (axis.hi - axis.lo)
            };
            let k = edges.partition_point(|e| *e <= v);
            (k >= 1 && k < edges.len()).then(|| k - 1)
        })
        .collect()
}

impl Render for HeatMap {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn check(&self) -> Result<(), PlotError> {
        self.layout().map(|_| ())
    }

    fn render<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        scale: f64,
    ) -> Result<(), PlotError> {
        self.draw_on(root, Metrics::FULL.scaled(scale))
    }
}

impl HeatMap {
    /// Draws the heat map on `root` with text and line sizes `m` (a whole figure, or one
    /// panel of a [`crate::HeatMapGrid`]).
    pub(crate) fn draw_on<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        m: Metrics,
    ) -> Result<(), PlotError> {
        let Layout {
            x_edges: xe,
            y_edges: ye,
            x,
            y,
            colour,
        } = self.layout()?;
        let (strip, area) = split_title(root, &self.title, m);
        if let Some(strip) = strip {
            draw_title(&strip, &self.title, m)?;
        }
        let (aw, ah) = area.dim_in_pixel();
        let colour_ticks = colour.ticks((f64::from(ah) / (4.5 * m.tick)) as usize);
        let tick_style = font(m.tick);
        let widest = colour_ticks
            .bold
            .iter()
            .map(|c| text_width(&area, &colour_ticks.label(*c), &tick_style))
            .max()
            .unwrap_or(0);
        let desc = if self.colour_label.is_empty() {
            0.0
        } else {
            1.3 * m.label
        };
        let bar_labels = widest + m.upx(18.0) + desc as u32;
        let bar_width = m.upx(20.0 + COLOUR_BAR) + bar_labels;
        let (main, bar) = area.split_horizontally(aw.saturating_sub(bar_width));

        let frame = Frame {
            x,
            y,
            x_label: &self.x_label,
            y_label: &self.y_label,
            m,
            equal_aspect: false,
            min_y_area: 0,
        };
        let mut built = frame.build(&main)?;
        self.draw_cells(&built, &xe, &ye, &colour)?;
        draw_mesh(&mut built, &frame, false)?;
        draw_all(&mut built, &self.overlays)?;
        draw_legend(&mut built, &self.overlays, self.legend)?;

        // Colour bar, aligned with the plotting area of the main chart.
        let (_, rows) = built.chart.plotting_area().get_pixel_range();
        let (_, bar_top) = bar.get_base_pixel();
        let (_, bar_h) = bar.dim_in_pixel();
        let top = u32::try_from(rows.start - bar_top).unwrap_or(0);
        let bottom = u32::try_from(bar_top + bar_h as i32 - rows.end).unwrap_or(0);
        let unit = Axis::resolve("x", [], None, false, 0.0)?;
        let no_ticks = unit.ticks(2).without_ticks();
        let chart = ChartBuilder::on(&bar)
            .margin_top(top)
            .margin_bottom(bottom)
            .margin_left(m.upx(20.0))
            .right_y_label_area_size(bar_labels)
            .build_cartesian_2d(
                TickedRange::new(&unit, &no_ticks),
                TickedRange::new(&colour, &colour_ticks),
            )
            .map_err(draw_error)?;
        let mut bar_built = Built {
            chart,
            x: unit,
            y: colour,
            x_ticks: no_ticks,
            y_ticks: colour_ticks,
            y_area: 0,
            m,
        };
        let strip = bar_built.chart.plotting_area().strip_coord_spec();
        let (w, h) = strip.dim_in_pixel();
        let column: Vec<(u8, u8, u8)> = (0..h)
            .map(|r| viridis(1.0 - (f64::from(r) + 0.5) / f64::from(h)))
            .collect();
        let pixels = (0..h as usize).flat_map(|r| std::iter::repeat_n(column[r], w as usize));
        blit(&strip, w, h, pixels)?;
        let bar_frame = Frame {
            x_label: "",
            y_label: "",
            ..frame
        };
        draw_mesh(&mut bar_built, &bar_frame, false)?;
        // plotters centres a right-hand axis description on the outer edge, cutting it in half;
        // write it ourselves, reading upwards like the y description.
        let (bar_w, _) = bar.dim_in_pixel();
        let style = font(m.label)
            .transform(FontTransform::Rotate270)
            .pos(Pos::new(HPos::Center, VPos::Top));
        let at = (
            bar_w as i32 - desc as i32,
            (rows.start + rows.end) / 2 - bar_top,
        );
        bar.draw_text(&self.colour_label, &style, at)
            .map_err(draw_error)
    }
}

/// Width in nominal pixels of the colour bar itself.
const COLOUR_BAR: f64 = 26.0;

impl HeatMap {
    /// Rasterises the cells into the plotting area.
    fn draw_cells<DB: DrawingBackend>(
        &self,
        built: &Built<'_, DB>,
        xe: &[f64],
        ye: &[f64],
        colour: &Axis,
    ) -> Result<(), PlotError> {
        let plot = built.chart.plotting_area().strip_coord_spec();
        let (w, h) = plot.dim_in_pixel();
        let cols = pixel_cells(&built.x, xe, w, false);
        let rows = pixel_cells(&built.y, ye, h, true);
        let span = colour.hi - colour.lo;
        let shade = |i: Option<usize>, j: Option<usize>| -> Option<(u8, u8, u8)> {
            let z = *self.z.get(j?)?.get(i?)?;
            let c = to_chart(z, colour.log).map_or(f64::NAN, |c| (c - colour.lo) / span);
            Some(viridis(c))
        };
        let pixels = rows
            .iter()
            .flat_map(|j| cols.iter().map(move |i| (*i, *j)))
            .map(|(i, j)| shade(i, j).unwrap_or(MISSING));
        blit(&plot, w, h, pixels)
    }
}

/// Draws `w` x `h` RGB pixels (row by row from the top) at the origin of `area`.
fn blit<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    w: u32,
    h: u32,
    pixels: impl Iterator<Item = (u8, u8, u8)>,
) -> Result<(), PlotError> {
    if w == 0 || h == 0 {
        return Ok(());
    }
    let buffer: Vec<u8> = pixels.flat_map(|(r, g, b)| [r, g, b]).collect();
    let element = BitMapElement::with_owned_buffer((0, 0), (w, h), buffer).ok_or_else(|| {
        PlotError::Draw {
            path: PathBuf::new(),
            message: "bitmap buffer does not match its size".into(),
        }
    })?;
    area.draw(&element).map_err(draw_error)
}
