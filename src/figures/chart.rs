//! The chart model every figure is described in (series, panels, figures), apart from how the
//! figures are drawn ([`super::render`]) and which ones the paper has ([`super`]): `tradeoff` and
//! `sensitivity` describe their plots in it too.

/// A series of (x, y) points, drawn as a line, as markers or as stems.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
    pub label: String,
    /// index into [`super::render::PALETTE`]
    pub color: usize,
    pub points: Vec<(f64, f64)>,
    /// half-widths of vertical error bars, one per point (empty: none)
    pub errors: Vec<f64>,
}

/// One chart.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    /// (lo, hi, height) bars from 0
    pub bars: Vec<(f64, f64, f64)>,
    /// (x0, x1, y0, y1, value) cells of a heat map, coloured by √(value / heat_max), with a
    /// colour bar labelled `heat_label`
    pub heat: Vec<[f64; 5]>,
    /// the value of the top colour (default: the panel's largest cell)
    pub heat_max: Option<f64>,
    pub heat_label: String,
    /// write each cell's value in it (for small grids)
    pub heat_values: bool,
    /// colour linear in the value from the smallest to the largest cell (for maps of statistics
    /// that may be negative), instead of √(value / heat_max) from 0 (for densities)
    pub heat_linear: bool,
    /// contour segments drawn over the heat map
    pub contours: Vec<[(f64, f64); 2]>,
    pub lines: Vec<Series>,
    pub points: Vec<Series>,
    /// probability mass functions: a stem from 0 to each point, with a marker
    pub stems: Vec<Series>,
    /// logarithmic axes (the data must be positive)
    pub x_log: bool,
    pub y_log: bool,
    /// vertical guide lines
    pub vlines: Vec<f64>,
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
    /// ticks at these data values with these labels (a sweep's grid values, a category's name)
    /// instead of round numbers chosen by the axis (empty: round numbers)
    pub x_ticks: Vec<(f64, String)>,
    pub y_ticks: Vec<(f64, String)>,
}

/// A figure: panels on a `rows × cols` grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub name: String,
    pub title: String,
    pub rows: usize,
    pub cols: usize,
    pub size: (u32, u32),
    pub panels: Vec<Panel>,
}
