//! Several x-y panels in one figure, laid out in rows and columns.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::chart::{draw_title, split_title};
use crate::figure::Figure2d;
use crate::font::Metrics;
use crate::render::{save, Render, MIN_SIZE};
use crate::PlotError;

/// Panels of [`Figure2d`] in `rows` x `cols`, filled row by row (mode shapes of six modes in
/// 2 x 3, Bode magnitude above phase in 2 x 1). Cells without a panel stay blank. Each panel
/// keeps its own title, labels, ranges and legend; its `size` is ignored.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Grid {
    /// Title above all panels; empty for none.
    pub title: String,
    /// Number of rows.
    pub rows: usize,
    /// Number of columns.
    pub cols: usize,
    /// The panels, row by row; at most `rows * cols`.
    pub panels: Vec<Figure2d>,
    /// Size of the whole figure in pixels.
    pub size: (u32, u32),
}

impl Grid {
    /// An empty grid of `rows` x `cols` cells, sized about 500 x 360 pixels per panel and at
    /// least 1000 x 700 in all.
    pub fn new(title: impl Into<String>, rows: usize, cols: usize) -> Self {
        Grid {
            title: title.into(),
            rows,
            cols,
            panels: Vec::new(),
            size: grid_size(rows, cols, (500, 360)),
        }
    }

    /// The same grid with one more panel.
    pub fn with_panel(mut self, panel: Figure2d) -> Self {
        self.panels.push(panel);
        self
    }

    /// Writes `stem.png` and `stem.svg` (creating the parent directory if needed) and returns
    /// their paths, PNG first.
    pub fn save(&self, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
        save(self, stem)
    }
}

impl Render for Grid {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn check(&self) -> Result<(), PlotError> {
        check_shape(self.rows, self.cols, self.panels.len(), self.size)?;
        self.panels.iter().try_for_each(|p| p.axes().map(|_| ()))
    }

    fn render<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        scale: f64,
    ) -> Result<(), PlotError> {
        let cells = titled_cells(root, &self.title, (self.rows, self.cols), scale)?;
        let m = Metrics::PANEL.scaled(scale);
        // Line up the plotting areas of each column: give all its panels the widest y labels.
        let mut y_area = vec![0; self.cols];
        for (k, (panel, cell)) in self.panels.iter().zip(&cells).enumerate() {
            let column = &mut y_area[k % self.cols];
            *column = (*column).max(panel.y_area_on(cell, m)?);
        }
        for (k, (panel, cell)) in self.panels.iter().zip(&cells).enumerate() {
            panel.draw_on(cell, m, y_area[k % self.cols])?;
        }
        Ok(())
    }
}

/// Fails unless `panels` fit in `rows` x `cols` cells and each cell of a figure of `size`
/// pixels leaves room for axes and labels.
pub(crate) fn check_shape(
    rows: usize,
    cols: usize,
    panels: usize,
    size: (u32, u32),
) -> Result<(), PlotError> {
    let cells = rows.checked_mul(cols).unwrap_or(0);
    if cells == 0 || cells < panels {
        return Err(PlotError::GridShape { rows, cols, panels });
    }
    let (w, h) = size;
    let too_small =
        |total: u32, n: usize, least: u32| u32::try_from(n).map_or(true, |n| total / n < least);
    if too_small(w, cols, MIN_SIZE.0) || too_small(h, rows, MIN_SIZE.1) {
        return Err(PlotError::TooSmall(w, h));
    }
    Ok(())
}

/// Size of a figure of `rows` x `cols` panels of about `panel` pixels each, at least
/// 1000 x 700 in all (room for the title however few the panels).
pub(crate) fn grid_size(rows: usize, cols: usize, panel: (u32, u32)) -> (u32, u32) {
    let per = |n: usize, each: u32, least: u32| {
        u32::try_from(n).map_or(u32::MAX, |n| n.saturating_mul(each).max(least))
    };
    (per(cols, panel.0, 1000), per(rows, panel.1, 700))
}

/// Draws `title` across the top of `root` and splits the rest into `rows` x `cols` cells,
/// row by row.
pub(crate) fn titled_cells<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    (rows, cols): (usize, usize),
    scale: f64,
) -> Result<Vec<DrawingArea<DB, Shift>>, PlotError> {
    let (strip, area) = split_title(root, title, Metrics::FULL.scaled(scale));
    if let Some(strip) = strip {
        draw_title(&strip, title, Metrics::FULL.scaled(scale))?;
    }
    Ok(area.split_evenly((rows, cols)))
}
