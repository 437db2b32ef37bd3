//! The embedded font.
//!
//! plotters' `ab_glyph` backend draws text only with fonts registered at run time through
//! [`plotters::style::register_font`]. We register DejaVu Sans (embedded with `include_bytes!`,
//! licence in `assets/README.md`) under the family name `sans-serif`, which is plotters' default
//! family and also what the SVG files name, so SVG viewers fall back to their own sans-serif font.

use std::sync::OnceLock;

use plotters::style::{register_font, FontStyle};

use crate::PlotError;

/// DejaVu Sans 2.37, the font every PNG is drawn with.
pub const FONT_BYTES: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Family name the embedded font is registered under (and written into SVG files).
pub const FONT_FAMILY: &str = "sans-serif";

/// Register the embedded font once per process; later calls return the first outcome.
pub(crate) fn ensure_registered() -> Result<(), PlotError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        // Bold titles and the like fall back to the normal face: one font file is enough.
        register_font(FONT_FAMILY, FontStyle::Normal, FONT_BYTES).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(PlotError::Font)
    }
}

/// Text sizes and the pixel scale for one panel.
///
/// All lengths in the drawing code are written for a figure at its nominal size (1000 x 700 for
/// a single figure) and pass through [`Metrics::px`], so the same code draws the SVG at scale 1
/// and the supersampled PNG at scale 2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Metrics {
    /// Figure or panel title, pixels.
    pub title: f64,
    /// Axis descriptions (`"Speed [rpm]"`), pixels.
    pub label: f64,
    /// Tick labels, pixels.
    pub tick: f64,
    /// Legend entries, annotations and reference line labels, pixels.
    pub legend: f64,
    /// Device pixels per nominal pixel.
    pub scale: f64,
}

impl Metrics {
    /// Sizes for a figure of its own, about 1000 x 700 pixels.
    pub const FULL: Metrics = Metrics {
        title: 26.0,
        label: 20.0,
        tick: 16.0,
        legend: 16.0,
        scale: 1.0,
    };
    /// Sizes for one panel of a [`crate::Grid`].
    pub const PANEL: Metrics = Metrics {
        title: 19.0,
        label: 16.0,
        tick: 14.0,
        legend: 14.0,
        scale: 1.0,
    };

    /// The same metrics drawn `scale` times larger.
    pub fn scaled(self, scale: f64) -> Metrics {
        Metrics {
            title: self.title * scale,
            label: self.label * scale,
            tick: self.tick * scale,
            legend: self.legend * scale,
            scale: self.scale * scale,
        }
    }

    /// A nominal length in device pixels.
    pub fn px(&self, nominal: f64) -> i32 {
        (nominal * self.scale).round() as i32
    }

    /// A nominal length in device pixels, unsigned.
    pub fn upx(&self, nominal: f64) -> u32 {
        (nominal * self.scale).round().max(0.0) as u32
    }

    /// A nominal line width in device pixels, at least 1 (and at most 50 nominal).
    pub fn stroke(&self, nominal: u32) -> u32 {
        self.upx(f64::from(nominal.min(50))).max(1)
    }
}
