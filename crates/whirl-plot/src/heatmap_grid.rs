//! Several colour maps in one figure, laid out in rows and columns: the cascades of a
//! parameter study, one small map per point.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::font::Metrics;
use crate::grid::{check_shape, grid_size, titled_cells};
use crate::heatmap::HeatMap;
use crate::render::{save, Render};
use crate::PlotError;

/// Panels of [`HeatMap`] in `rows` x `cols`, row by row; `None` leaves a cell blank (a
/// sweep with fewer values than the longest). Each panel keeps its own title, labels,
/// colour scale and overlays; its `size` is ignored. Give the panels one `z_range` to
/// compare their colours.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HeatMapGrid {
    /// Title above all panels; empty for none.
    pub title: String,
    /// Number of rows.
    pub rows: usize,
    /// Number of columns.
    pub cols: usize,
    /// The panels, row by row; at most `rows * cols`.
    pub panels: Vec<Option<HeatMap>>,
    /// Size of the whole figure in pixels.
    pub size: (u32, u32),
}

impl HeatMapGrid {
    /// An empty grid of `rows` x `cols` cells, sized about 520 x 400 pixels per panel and at
    /// least 1000 x 700 in all (room for the title however few the panels).
    pub fn new(title: impl Into<String>, rows: usize, cols: usize) -> Self {
        HeatMapGrid {
            title: title.into(),
            rows,
            cols,
            panels: Vec::new(),
            size: grid_size(rows, cols, (520, 400)),
        }
    }

    /// Writes `stem.png` and `stem.svg` (creating the parent directory if needed) and returns
    /// their paths, PNG first.
    pub fn save(&self, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
        save(self, stem)
    }
}

impl Render for HeatMapGrid {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn check(&self) -> Result<(), PlotError> {
        check_shape(self.rows, self.cols, self.panels.len(), self.size)?;
        self.panels.iter().flatten().try_for_each(Render::check)
    }

    fn render<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        scale: f64,
    ) -> Result<(), PlotError> {
        let cells = titled_cells(root, &self.title, (self.rows, self.cols), scale)?;
        for (panel, cell) in self.panels.iter().zip(&cells) {
            if let Some(panel) = panel {
                panel.draw_on(cell, Metrics::PANEL.scaled(scale))?;
            }
        }
        Ok(())
    }
}
