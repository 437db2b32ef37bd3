//! Writing a figure to `stem.png` and `stem.svg`.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::chart::draw_error;
use crate::{font, PlotError};

/// Smallest width and height in pixels of a figure (or of one grid panel) that leaves room for
/// axes and labels.
pub(crate) const MIN_SIZE: (u32, u32) = (200, 150);

/// A figure that can draw itself on any plotters backend.
pub(crate) trait Render {
    /// Size of the whole figure in pixels.
    fn size(&self) -> (u32, u32);
    /// Checks the data before any file is created.
    fn check(&self) -> Result<(), PlotError>;
    /// Draws the figure on `root`, which covers the whole figure at `scale` device pixels per
    /// nominal pixel.
    fn render<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        scale: f64,
    ) -> Result<(), PlotError>;
}

/// Writes `stem.png` and `stem.svg` (creating the parent directory if needed) and returns their
/// paths, PNG first.
pub(crate) fn save<R: Render>(figure: &R, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
    font::ensure_registered()?;
    figure.check()?;
    let (w, h) = figure.size();
    if w < MIN_SIZE.0 || h < MIN_SIZE.1 {
        return Err(PlotError::TooSmall(w, h));
    }
    if let Some(dir) = stem.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|source| PlotError::Io {
            path: dir.to_path_buf(),
            source,
        })?;
    }
    let png = with_suffix(stem, "png");
    let svg = with_suffix(stem, "svg");
    write_png(figure, &png, (w, h)).map_err(|e| at_path(e, &png))?;
    write_svg(figure, &svg, (w, h)).map_err(|e| at_path(e, &svg))?;
    Ok(vec![png, svg])
}

fn write_svg<R: Render>(figure: &R, svg: &Path, size: (u32, u32)) -> Result<(), PlotError> {
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size).into_drawing_area();
        draw(figure, &root, 1.0)?;
    }
    // plotters-svg 0.3.7 labels embedded bitmaps `data:png`, which browsers reject; the media
    // type is `image/png`.
    let text = text.replace("href=\"data:png;base64,", "href=\"data:image/png;base64,");
    std::fs::write(svg, text).map_err(|source| PlotError::Io {
        path: svg.to_path_buf(),
        source,
    })
}

/// Supersampling factor of PNG files: plotters' raster lines are not anti-aliased (and wide ones
/// have visibly stepped joints), so the figure is drawn at this many times the size and averaged
/// down.
const SUPERSAMPLE: u32 = 2;

fn write_png<R: Render>(figure: &R, png: &Path, (w, h): (u32, u32)) -> Result<(), PlotError> {
    let (big_w, big_h) = (w * SUPERSAMPLE, h * SUPERSAMPLE);
    let mut big = vec![0u8; big_w as usize * big_h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut big, (big_w, big_h)).into_drawing_area();
        draw(figure, &root, f64::from(SUPERSAMPLE))?;
    }
    let small = downsample(&big, (w, h), SUPERSAMPLE);
    let root = BitMapBackend::new(png, (w, h)).into_drawing_area();
    let image =
        BitMapElement::with_owned_buffer((0, 0), (w, h), small).ok_or_else(|| PlotError::Draw {
            path: PathBuf::new(),
            message: "downsampled image does not match the figure size".into(),
        })?;
    root.draw(&image).map_err(draw_error)?;
    root.present().map_err(draw_error)
}

/// Averages blocks of `f` x `f` RGB pixels of an image `f` times larger than `(w, h)`.
fn downsample(big: &[u8], (w, h): (u32, u32), f: u32) -> Vec<u8> {
    let (w, h, f) = (w as usize, h as usize, f as usize);
    let big_w = w * f;
    let mut out = vec![0u8; w * h * 3];
    for (i, px) in out.chunks_exact_mut(3).enumerate() {
        let (x, y) = (i % w, i / w);
        for (c, value) in px.iter_mut().enumerate() {
            let mut sum = 0u32;
            for dy in 0..f {
                let row = (y * f + dy) * big_w;
                for dx in 0..f {
                    sum += u32::from(big.get((row + x * f + dx) * 3 + c).copied().unwrap_or(255));
                }
            }
            *value = ((sum + (f * f / 2) as u32) / (f * f) as u32) as u8;
        }
    }
    out
}

fn draw<R: Render, DB: DrawingBackend>(
    figure: &R,
    root: &DrawingArea<DB, Shift>,
    scale: f64,
) -> Result<(), PlotError> {
    root.fill(&WHITE).map_err(draw_error)?;
    figure.render(root, scale)?;
    root.present().map_err(draw_error)
}

/// `stem` with `.ext` appended (not replacing an existing extension: `run.v2` -> `run.v2.png`).
fn with_suffix(stem: &Path, ext: &str) -> PathBuf {
    let mut name = stem.as_os_str().to_owned();
    name.push(".");
    name.push(ext);
    PathBuf::from(name)
}

fn at_path(e: PlotError, file: &Path) -> PlotError {
    match e {
        PlotError::Draw { message, .. } => PlotError::Draw {
            path: file.to_path_buf(),
            message,
        },
        other => other,
    }
}
