//! How a series looks: colour, line kind, marker, widths.

use plotters::style::RGBColor;

/// The default colours, in order: the Okabe-Ito palette (Okabe and Ito, "Color Universal
/// Design", 2008), which stays distinguishable for the common forms of colour blindness. Its
/// yellow is left out because it is hard to see on white. Indices wrap around.
pub const PALETTE: [(u8, u8, u8); 7] = [
    (0, 114, 178),   // blue
    (213, 94, 0),    // vermillion
    (0, 158, 115),   // bluish green
    (204, 121, 167), // reddish purple
    (230, 159, 0),   // orange
    (86, 180, 233),  // sky blue
    (0, 0, 0),       // black
];

/// A colour: an entry of [`PALETTE`] (index taken modulo its length) or explicit RGB.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Colour {
    /// Entry `i % PALETTE.len()` of [`PALETTE`].
    Palette(usize),
    /// Red, green, blue in 0..=255.
    Rgb(u8, u8, u8),
}

impl Colour {
    /// Black, for reference lines and annotations.
    pub const BLACK: Colour = Colour::Rgb(0, 0, 0);
    /// Mid grey.
    pub const GREY: Colour = Colour::Rgb(110, 110, 110);

    /// The RGB triple this colour stands for.
    pub fn rgb(self) -> (u8, u8, u8) {
        match self {
            Colour::Palette(i) => PALETTE[i % PALETTE.len()],
            Colour::Rgb(r, g, b) => (r, g, b),
        }
    }

    /// The colour as `#rrggbb`, as a figure's specification writes it.
    pub fn hex(self) -> String {
        let (r, g, b) = self.rgb();
        format!("#{r:02x}{g:02x}{b:02x}")
    }

    pub(crate) fn to_plotters(self) -> RGBColor {
        let (r, g, b) = self.rgb();
        RGBColor(r, g, b)
    }
}

/// A colour is written as `#rrggbb` in a figure's specification (what a renderer other than
/// this crate's, such as matplotlib, reads): a palette entry as the RGB it stands for.
impl serde::Serialize for Colour {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(&self.hex())
    }
}

impl<'de> serde::Deserialize<'de> for Colour {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let text = String::deserialize(deserializer)?;
        let channel = |i: usize| {
            text.get(i..i + 2)
                .and_then(|h| u8::from_str_radix(h, 16).ok())
        };
        match (
            text.len(),
            text.starts_with('#'),
            channel(1),
            channel(3),
            channel(5),
        ) {
            (7, true, Some(r), Some(g), Some(b)) => Ok(Colour::Rgb(r, g, b)),
            _ => Err(serde::de::Error::custom(format!(
                "colour {text:?} is not of the form #rrggbb"
            ))),
        }
    }
}

impl Default for Colour {
    fn default() -> Self {
        Colour::Palette(0)
    }
}

/// How consecutive points are joined.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Line {
    /// Not joined: markers only.
    None,
    /// A continuous line.
    #[default]
    Solid,
    /// A dashed line.
    Dashed,
    /// A dotted line (short dashes).
    Dotted,
}

/// The symbol drawn at each point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Marker {
    /// No symbol.
    #[default]
    None,
    /// Filled circle.
    Circle,
    /// Circle outline.
    OpenCircle,
    /// Filled upward triangle.
    Triangle,
    /// Square outline.
    Square,
    /// Diagonal cross.
    Cross,
}

/// The look of one series.
///
/// A series with `line: Line::None` and `marker: Marker::None` draws nothing but may still
/// appear in the legend.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Style {
    /// Colour of line and markers. `None` takes the palette entry of the series' index.
    pub colour: Option<Colour>,
    /// How points are joined.
    pub line: Line,
    /// Symbol at each point.
    pub marker: Marker,
    /// Line width in pixels (at least 1 is drawn).
    pub line_width: u32,
    /// Marker radius in pixels.
    pub marker_size: u32,
}

impl Default for Style {
    fn default() -> Self {
        Style {
            colour: None,
            line: Line::Solid,
            marker: Marker::None,
            line_width: 2,
            marker_size: 4,
        }
    }
}

impl Style {
    /// Solid line in `colour`.
    pub fn solid(colour: Colour) -> Self {
        Style {
            colour: Some(colour),
            ..Style::default()
        }
    }

    /// Dashed line in `colour`.
    pub fn dashed(colour: Colour) -> Self {
        Style {
            colour: Some(colour),
            line: Line::Dashed,
            ..Style::default()
        }
    }

    /// Markers only, not joined.
    pub fn markers(colour: Colour, marker: Marker) -> Self {
        Style {
            colour: Some(colour),
            line: Line::None,
            marker,
            ..Style::default()
        }
    }

    /// Solid line with a marker at each point.
    pub fn line_markers(colour: Colour, marker: Marker) -> Self {
        Style {
            colour: Some(colour),
            marker,
            ..Style::default()
        }
    }

    /// The same style with another line width in pixels.
    pub fn width(self, line_width: u32) -> Self {
        Style { line_width, ..self }
    }

    /// The same style with another marker radius in pixels.
    pub fn marker_size(self, marker_size: u32) -> Self {
        Style {
            marker_size,
            ..self
        }
    }

    /// The colour to draw with when this is the series number `index` of its figure.
    pub(crate) fn colour_for(&self, index: usize) -> Colour {
        self.colour.unwrap_or(Colour::Palette(index))
    }
}
