//! Layout of one set of axes: label areas sized to their text, ticks from [`crate::axis`], and
//! optionally equal scales on x and y.
//!
//! Every figure kind draws on the same concrete plotters chart type, [`Chart`]: both axes are
//! `f64` in chart space (log10 of the data on a logarithmic axis) with tick positions chosen by
//! us, so linear and logarithmic axes share all drawing code.

use std::error::Error;
use std::ops::Range;
use std::path::PathBuf;

use plotters::coord::cartesian::Cartesian2d;
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::axis::{Axis, Ticks};
use crate::clip::Rect;
use crate::font::{Metrics, FONT_FAMILY};
use crate::PlotError;

/// The coordinate system of every chart: linear `f64` in chart space on both axes.
pub(crate) type Coord2 = Cartesian2d<TickedRange, TickedRange>;
/// A plotters chart on that coordinate system.
pub(crate) type Chart<'a, DB> = ChartContext<'a, DB, Coord2>;

/// A linear `f64` range whose tick positions are given, not computed by plotters.
///
/// (plotters' own `WithKeyPoints<RangedCoordf64>` cannot be used: it inherits
/// `NoDefaultFormatting` from `RangedCoordf64`, and `configure_mesh` then requires a
/// `ValueFormatter` impl that it lacks, even when custom label formatters are set.)
pub(crate) struct TickedRange {
    lo: f64,
    hi: f64,
    bold: Vec<f64>,
    light: Vec<f64>,
}

impl TickedRange {
    pub fn new(axis: &Axis, ticks: &Ticks) -> Self {
        TickedRange {
            lo: axis.lo,
            hi: axis.hi,
            bold: ticks.bold.clone(),
            light: ticks.light.clone(),
        }
    }
}

impl Ranged for TickedRange {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        // Same rounding as plotters' own f64 ranges, so grid lines and data agree.
        let fraction = (value - self.lo) / (self.hi - self.lo);
        let pixels = f64::from(limit.1 - limit.0);
        if !fraction.is_finite() || pixels == 0.0 {
            return limit.0;
        }
        // Far outside values only occur for unclipped elements; keep them off-screen but finite.
        let offset = (pixels * fraction).clamp(-1e6, 1e6);
        if pixels > 0.0 {
            limit.0 + (offset + 1e-3).floor() as i32
        } else {
            limit.0 + (offset - 1e-3).ceil() as i32
        }
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.light.clone()
        } else {
            self.bold.clone()
        }
    }

    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

/// Converts a plotters drawing error; the file name is filled in by [`crate::render::save`].
pub(crate) fn draw_error<E: Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> PlotError {
    PlotError::Draw {
        path: PathBuf::new(),
        message: e.to_string(),
    }
}

/// The embedded font at `size` pixels.
pub(crate) fn font(size: f64) -> TextStyle<'static> {
    (FONT_FAMILY, size).into_font().into()
}

/// Width in pixels of `text` in `style`, with a generous guess if the font cannot measure it.
pub(crate) fn text_width<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    style: &TextStyle,
) -> u32 {
    area.estimate_text_size(text, style)
        .map(|(w, _)| w)
        .unwrap_or((text.chars().count() as f64 * style.font.get_size() * 0.65) as u32)
}

/// What a set of axes shows, before it is laid out on an area.
pub(crate) struct Frame<'s> {
    pub x: Axis,
    pub y: Axis,
    pub x_label: &'s str,
    pub y_label: &'s str,
    pub m: Metrics,
    /// Same data units per pixel on x and y (ignored if either axis is logarithmic).
    pub equal_aspect: bool,
    /// Least width of the y label area in device pixels, to line up the panels of a grid column.
    pub min_y_area: u32,
}

/// A chart laid out on its area, with the axes and ticks it ended up with.
pub(crate) struct Built<'a, DB: DrawingBackend> {
    pub chart: Chart<'a, DB>,
    pub x: Axis,
    pub y: Axis,
    pub x_ticks: Ticks,
    pub y_ticks: Ticks,
    /// Width of the y label area in device pixels.
    pub y_area: u32,
    pub m: Metrics,
}

impl<DB: DrawingBackend> Built<'_, DB> {
    /// The visible rectangle in chart space.
    pub fn rect(&self) -> Rect {
        Rect {
            x0: self.x.lo,
            x1: self.x.hi,
            y0: self.y.lo,
            y1: self.y.hi,
        }
    }
}

impl Frame<'_> {
    /// Lays the axes out on `area`. Tick count and label area widths depend on the size of the
    /// plotting area and the other way round, so this settles them in a few passes.
    pub fn build<'a, DB: DrawingBackend>(
        &self,
        area: &'a DrawingArea<DB, Shift>,
    ) -> Result<Built<'a, DB>, PlotError> {
        let (aw, ah) = area.dim_in_pixel();
        let mut plot = (
            aw.saturating_sub(self.m.upx(120.0)),
            ah.saturating_sub(self.m.upx(90.0)),
        );
        let (mut x, mut y) = (self.x, self.y);
        let tick = self.m.tick;
        let mut pass = 0;
        loop {
            let x_ticks = self.fit_x_ticks(area, &x, plot.0);
            let y_ticks = y.ticks((f64::from(plot.1) / (4.5 * tick)) as usize);
            let (chart, y_area) = self.build_once(area, x, y, &x_ticks, &y_ticks)?;
            let dims = chart.plotting_area().dim_in_pixel();
            let (nx, ny) = self.aspect_adjusted(dims);
            pass += 1;
            if (dims == plot && nx == x && ny == y) || pass == 4 {
                return Ok(Built {
                    chart,
                    x,
                    y,
                    x_ticks,
                    y_ticks,
                    y_area,
                    m: self.m,
                });
            }
            plot = dims;
            (x, y) = (nx, ny);
        }
    }

    /// About one x tick per 7 characters' width, fewer if the labels would touch.
    fn fit_x_ticks<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        x: &Axis,
        plot_width: u32,
    ) -> Ticks {
        let style = font(self.m.tick);
        let gap = 1.5 * self.m.tick;
        let mut wanted = (f64::from(plot_width) / (7.0 * self.m.tick)) as usize;
        loop {
            let ticks = x.ticks(wanted);
            let widest = ticks
                .bold
                .iter()
                .map(|c| text_width(area, &ticks.label(*c), &style))
                .max()
                .unwrap_or(0);
            let needed = (f64::from(widest) + gap) * ticks.bold.len() as f64;
            if wanted <= 2 || needed <= f64::from(plot_width) {
                return ticks;
            }
            wanted -= 1;
        }
    }

    /// The requested axes, widened so that one data unit spans as many pixels on x as on y.
    fn aspect_adjusted(&self, (w, h): (u32, u32)) -> (Axis, Axis) {
        let (mut x, mut y) = (self.x, self.y);
        if self.equal_aspect && !x.log && !y.log && w > 0 && h > 0 {
            let per_pixel = ((x.hi - x.lo) / f64::from(w)).max((y.hi - y.lo) / f64::from(h));
            x.widen_to(per_pixel * f64::from(w));
            y.widen_to(per_pixel * f64::from(h));
        }
        (x, y)
    }

    fn build_once<'a, DB: DrawingBackend>(
        &self,
        area: &'a DrawingArea<DB, Shift>,
        x: Axis,
        y: Axis,
        x_ticks: &Ticks,
        y_ticks: &Ticks,
    ) -> Result<(Chart<'a, DB>, u32), PlotError> {
        let m = self.m;
        let tick_style = font(m.tick);
        let widest_y = y_ticks
            .bold
            .iter()
            .map(|c| text_width(area, &y_ticks.label(*c), &tick_style))
            .max()
            .unwrap_or(0);
        let desc = |text: &str| if text.is_empty() { 0.0 } else { 1.3 * m.label };
        // plotters puts tick labels 2 x tick length (TICK) from the axis.
        let y_area =
            (widest_y + m.upx(2.0 * TICK + 4.0) + desc(self.y_label) as u32).max(self.min_y_area);
        let x_area =
            (f64::from(m.upx(2.0 * TICK + 4.0)) + 1.2 * m.tick + desc(self.x_label)) as u32;
        let last_x = x_ticks
            .bold
            .last()
            .map(|c| text_width(area, &x_ticks.label(*c), &tick_style))
            .unwrap_or(0);
        let chart = ChartBuilder::on(area)
            .margin_top((0.6 * m.tick) as u32 + m.upx(8.0))
            .margin_right((last_x / 2 + m.upx(8.0)).max(m.upx(20.0)))
            .margin_left(m.upx(8.0))
            .margin_bottom(m.upx(6.0))
            .x_label_area_size(x_area)
            .y_label_area_size(y_area)
            .build_cartesian_2d(TickedRange::new(&x, x_ticks), TickedRange::new(&y, y_ticks))
            .map_err(draw_error)?;
        Ok((chart, y_area))
    }
}

/// Draws axes, tick labels, axis descriptions and (if `grid_lines`) the grid.
pub(crate) fn draw_mesh<DB: DrawingBackend>(
    built: &mut Built<'_, DB>,
    frame: &Frame<'_>,
    grid_lines: bool,
) -> Result<(), PlotError> {
    let x_ticks = &built.x_ticks;
    let y_ticks = &built.y_ticks;
    let fx = |c: &f64| x_ticks.label(*c);
    let fy = |c: &f64| y_ticks.label(*c);
    let m = built.m;
    let thin = m.stroke(1);
    let mut mesh = built.chart.configure_mesh();
    mesh.x_desc(frame.x_label)
        .y_desc(frame.y_label)
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .label_style(font(m.tick))
        .axis_desc_style(font(m.label))
        .set_all_tick_mark_size(m.px(TICK))
        .axis_style(BLACK.mix(0.8).stroke_width(thin))
        .bold_line_style(BLACK.mix(0.14).stroke_width(thin))
        .light_line_style(BLACK.mix(0.05).stroke_width(thin));
    if !grid_lines {
        mesh.disable_mesh();
    }
    mesh.draw().map_err(draw_error)?;
    // plotters draws only the left and bottom axis lines; close the box.
    let plot = built.chart.plotting_area().strip_coord_spec();
    let (w, h) = plot.dim_in_pixel();
    let corner = (w as i32 - 1, h as i32 - 1);
    plot.draw(&Rectangle::new(
        [(0, 0), corner],
        BLACK.mix(0.8).stroke_width(thin),
    ))
    .map_err(draw_error)
}

/// Length of tick marks in nominal pixels.
const TICK: f64 = 5.0;

/// Splits a title strip off the top of `area` (when `title` is not empty) without drawing it:
/// returns the strip and the rest.
pub(crate) fn split_title<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    m: Metrics,
) -> (Option<DrawingArea<DB, Shift>>, DrawingArea<DB, Shift>) {
    if title.is_empty() {
        return (None, area.clone());
    }
    let (strip, rest) = area.split_vertically((1.6 * m.title) as u32);
    (Some(strip), rest)
}

/// Writes `title` centred in `strip`.
pub(crate) fn draw_title<DB: DrawingBackend>(
    strip: &DrawingArea<DB, Shift>,
    title: &str,
    m: Metrics,
) -> Result<(), PlotError> {
    let (w, h) = strip.dim_in_pixel();
    let style = font(m.title).pos(Pos::new(HPos::Center, VPos::Center));
    strip
        .draw_text(title, &style, (w as i32 / 2, h as i32 / 2))
        .map_err(draw_error)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_aspect_widens_the_narrower_axis() {
        let frame = Frame {
            x: Axis {
                lo: 0.0,
                hi: 2.0,
                log: false,
            },
            y: Axis {
                lo: -0.5,
                hi: 0.5,
                log: false,
            },
            x_label: "",
            y_label: "",
            m: Metrics::FULL,
            equal_aspect: true,
            min_y_area: 0,
        };
        let (x, y) = frame.aspect_adjusted((800, 600));
        // 2 units over 800 px sets the scale; y becomes 1.5 units over 600 px, about its centre.
        assert_eq!((x.lo, x.hi), (0.0, 2.0));
        assert!((y.lo + 0.75).abs() < 1e-12 && (y.hi - 0.75).abs() < 1e-12);
        let logarithmic = Frame {
            y: Axis {
                log: true,
                ..frame.y
            },
            ..frame
        };
        assert_eq!(logarithmic.aspect_adjusted((800, 600)).1, logarithmic.y);
    }
}
