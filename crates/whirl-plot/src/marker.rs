//! Point markers and legend samples, drawn directly in pixels.
//!
//! These are small custom plotters elements rather than compositions of plotters' own shapes:
//! one type covers every marker kind, which keeps the series code free of per-kind branches.

use plotters::element::{Drawable, PointCollection};
use plotters::prelude::*;
use plotters_backend::{BackendCoord, DrawingErrorKind};

use crate::style::{Line, Marker, Style};

/// A marker of some kind at a point of type `C` (chart coordinates or pixels).
pub(crate) struct MarkerElement<C> {
    pub at: C,
    pub marker: Marker,
    /// Radius in nominal pixels.
    pub size: u32,
    pub colour: RGBColor,
    /// Device pixels per nominal pixel.
    pub scale: f64,
}

impl<'a, C: 'a> PointCollection<'a, C> for &'a MarkerElement<C> {
    type Point = &'a C;
    type IntoIter = std::iter::Once<&'a C>;
    fn point_iter(self) -> Self::IntoIter {
        std::iter::once(&self.at)
    }
}

impl<C, DB: DrawingBackend> Drawable<DB> for MarkerElement<C> {
    fn draw<I: Iterator<Item = BackendCoord>>(
        &self,
        mut pos: I,
        backend: &mut DB,
        _: (u32, u32),
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        match pos.next() {
            Some(p) => draw_marker(backend, p, self.marker, self.size, self.colour, self.scale),
            None => Ok(()),
        }
    }
}

/// Draws one marker centred on pixel `p`.
fn draw_marker<DB: DrawingBackend>(
    backend: &mut DB,
    (x, y): BackendCoord,
    marker: Marker,
    size: u32,
    colour: RGBColor,
    scale: f64,
) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
    // Radius in device pixels; a silly size must not overflow the corner arithmetic below.
    let r = (f64::from(size.min(1000)) * scale).round() as i32;
    let outline = colour.stroke_width((2.0 * scale).round().max(1.0) as u32);
    let filled = colour.filled();
    match marker {
        Marker::None => Ok(()),
        Marker::Circle => backend.draw_circle((x, y), r as u32, &filled, true),
        Marker::OpenCircle => backend.draw_circle((x, y), r as u32, &outline, false),
        Marker::Triangle => {
            // Equilateral, centred on the point, a little larger than the circle of radius r.
            let s = r + scale.round() as i32;
            let h = (f64::from(s) * 0.5) as i32;
            let half_base = (f64::from(s) * 0.866) as i32;
            let corners = [(x, y - s), (x - half_base, y + h), (x + half_base, y + h)];
            backend.fill_polygon(corners, &filled)
        }
        Marker::Square => backend.draw_rect((x - r, y - r), (x + r, y + r), &outline, false),
        Marker::Cross => {
            backend.draw_line((x - r, y - r), (x + r, y + r), &outline)?;
            backend.draw_line((x - r, y + r), (x + r, y - r), &outline)
        }
    }
}

/// Width in nominal pixels of the line sample in a legend entry.
pub(crate) const LEGEND_SAMPLE: i32 = 32;

/// The legend sample of a series: a short piece of its line with its marker in the middle.
/// `at` is the left end, vertically centred on the legend text.
pub(crate) struct LegendSample {
    pub at: BackendCoord,
    pub style: Style,
    pub colour: RGBColor,
    /// Device pixels per nominal pixel.
    pub scale: f64,
}

impl<'a> PointCollection<'a, BackendCoord> for &'a LegendSample {
    type Point = &'a BackendCoord;
    type IntoIter = std::iter::Once<&'a BackendCoord>;
    fn point_iter(self) -> Self::IntoIter {
        std::iter::once(&self.at)
    }
}

impl<DB: DrawingBackend> Drawable<DB> for LegendSample {
    fn draw<I: Iterator<Item = BackendCoord>>(
        &self,
        mut pos: I,
        backend: &mut DB,
        _: (u32, u32),
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        let Some((x, y)) = pos.next() else {
            return Ok(());
        };
        let px = |nominal: f64| (nominal * self.scale).round() as i32;
        let width = px(f64::from(self.style.line_width.min(100))).max(1);
        let stroke = self.colour.stroke_width(width as u32);
        let length = px(f64::from(LEGEND_SAMPLE));
        // (dash, gap) in device pixels; a solid line is one dash as long as the sample.
        let pattern = match self.style.line {
            Line::None => None,
            Line::Solid => Some((length, 0)),
            Line::Dashed => Some((px(7.0), px(4.0))),
            Line::Dotted => Some((width, px(4.0))),
        };
        if let Some((dash, gap)) = pattern {
            let mut start = 0;
            while start < length {
                let end = (start + dash).min(length);
                backend.draw_line((x + start, y), (x + end, y), &stroke)?;
                start = end + gap.max(1);
            }
        }
        let centre = (x + length / 2, y);
        let s = self.style;
        draw_marker(
            backend,
            centre,
            s.marker,
            s.marker_size,
            self.colour,
            self.scale,
        )
    }
}
