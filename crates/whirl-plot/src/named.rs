//! Any figure as one value, and a figure with the name its files take: what a list of an
//! analysis's figures holds. Both serialise (serde) to a specification another renderer can
//! read: `kind` says which figure it is, the rest are the figure's own fields.

use std::path::{Path, PathBuf};

use crate::rpm::{SpeedAxis, SpeedInRpm};
use crate::{Figure2d, Grid, HeatMap, HeatMapGrid, PlotError};

/// One of the figures this crate draws.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Figure {
    /// x-y lines and markers.
    Plot(Figure2d),
    /// Panels in rows and columns.
    Grid(Grid),
    /// A colour map with overlays.
    HeatMap(HeatMap),
    /// Colour maps in rows and columns.
    HeatMapGrid(HeatMapGrid),
}

impl Figure {
    /// Writes `stem.png` and `stem.svg` and returns their paths, PNG first.
    pub fn save(&self, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
        match self {
            Figure::Plot(f) => f.save(stem),
            Figure::Grid(f) => f.save(stem),
            Figure::HeatMap(f) => f.save(stem),
            Figure::HeatMapGrid(f) => f.save(stem),
        }
    }
}

impl From<Figure2d> for Figure {
    fn from(f: Figure2d) -> Self {
        Figure::Plot(f)
    }
}

impl From<Grid> for Figure {
    fn from(f: Grid) -> Self {
        Figure::Grid(f)
    }
}

impl From<HeatMap> for Figure {
    fn from(f: HeatMap) -> Self {
        Figure::HeatMap(f)
    }
}

impl From<HeatMapGrid> for Figure {
    fn from(f: HeatMapGrid) -> Self {
        Figure::HeatMapGrid(f)
    }
}

impl SpeedInRpm for Figure {
    fn speed_in_rpm(self, axis: SpeedAxis) -> Self {
        match self {
            Figure::Plot(f) => Figure::Plot(f.speed_in_rpm(axis)),
            Figure::Grid(f) => Figure::Grid(f.speed_in_rpm(axis)),
            Figure::HeatMap(f) => Figure::HeatMap(f.speed_in_rpm(axis)),
            Figure::HeatMapGrid(mut f) => {
                f.panels = f
                    .panels
                    .into_iter()
                    .map(|p| p.map(|h| h.speed_in_rpm(axis)))
                    .collect();
                Figure::HeatMapGrid(f)
            }
        }
    }

    fn speed_texts_in_rpm(self) -> Self {
        match self {
            Figure::Plot(f) => Figure::Plot(f.speed_texts_in_rpm()),
            Figure::Grid(f) => Figure::Grid(f.speed_texts_in_rpm()),
            // A heat map's texts are its axis labels and its overlays' legend entries.
            other => other,
        }
    }
}

/// Where a figure shows speeds (in Hz), which [`NamedFigure::in_rpm`] rewrites in rpm.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SpeedMarks {
    /// Nowhere.
    #[default]
    None,
    /// Along an axis, and in the texts at points and lines on it.
    Axis(SpeedAxis),
    /// Only in the texts of its marks (a polar plot's peaks).
    Texts,
}

/// A figure and the stem of its files (`campbell` for campbell.png and campbell.svg).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct NamedFigure {
    /// The files' stem.
    pub name: String,
    /// Where it shows speeds.
    pub speeds: SpeedMarks,
    /// The figure.
    pub figure: Figure,
}

impl NamedFigure {
    /// `figure` named `name`, showing no speeds.
    pub fn new(name: impl Into<String>, figure: impl Into<Figure>) -> Self {
        NamedFigure {
            name: name.into(),
            speeds: SpeedMarks::None,
            figure: figure.into(),
        }
    }

    /// The same figure, with speeds (Hz) along `axis`.
    pub fn speed_axis(self, axis: SpeedAxis) -> Self {
        NamedFigure {
            speeds: SpeedMarks::Axis(axis),
            ..self
        }
    }

    /// The same figure, whose marks' texts name speeds (Hz).
    pub fn speed_texts(self) -> Self {
        NamedFigure {
            speeds: SpeedMarks::Texts,
            ..self
        }
    }

    /// The same figure with its speeds in rpm.
    pub fn in_rpm(self) -> Self {
        let figure = match self.speeds {
            SpeedMarks::None => self.figure,
            SpeedMarks::Axis(axis) => self.figure.speed_in_rpm(axis),
            SpeedMarks::Texts => self.figure.speed_texts_in_rpm(),
        };
        NamedFigure { figure, ..self }
    }

    /// Writes `<dir>/<name>.png` and `.svg` and returns their paths, PNG first.
    pub fn save_in(&self, dir: &Path) -> Result<Vec<PathBuf>, PlotError> {
        self.figure.save(&dir.join(&self.name))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Colour, Series, Style};

    #[test]
    fn a_specification_reads_back_as_the_figure_it_was() {
        let mut fig = Figure2d::new("t", "Speed [Hz]", "y");
        fig.series.push(
            Series::new(vec![1.0, 2.0], vec![3.0, 4.0])
                .label("a")
                .style(Style::dashed(Colour::Palette(1))),
        );
        fig.x_range = Some((0.0, 3.0));
        let named = NamedFigure::new("fig", fig).speed_axis(SpeedAxis::X);
        let text = serde_json::to_string(&named).unwrap();
        // The palette entry is written as the RGB it stands for.
        assert!(text.contains("\"#d55e00\""), "{text}");
        assert!(text.contains("\"kind\":\"plot\""), "{text}");
        let back: NamedFigure = serde_json::from_str(&text).unwrap();
        let Figure::Plot(back_fig) = &back.figure else {
            panic!("not a plot: {back:?}")
        };
        assert_eq!(back_fig.series[0].y, vec![3.0, 4.0]);
        assert_eq!(back.speeds, SpeedMarks::Axis(SpeedAxis::X));
        assert_eq!(back_fig.series[0].style.colour.unwrap().rgb(), (213, 94, 0));
        assert_eq!(back_fig.x_range, Some((0.0, 3.0)));
    }
}
