//! The chart model every figure is described in (series, panels, figures), apart from how the
//! figures are drawn ([`super::render`]) and which ones the paper has ([`super`]): `tradeoff` and
//! `sensitivity` describe their plots in it too.

/// A series of (x, y) points, drawn as a line, as markers or as stems.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
    /// legend entry (empty: none)
    pub label: String,
    /// index into [`super::render::PALETTE`]
    pub color: usize,
    /// (x, y) in data units
    pub points: Vec<(f64, f64)>,
    /// half-widths of vertical error bars, one per point (empty: none)
    pub errors: Vec<f64>,
}

/// One chart.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Panel {
    /// caption above the chart
    pub title: String,
    /// x-axis label
    pub x_label: String,
    /// y-axis label
    pub y_label: String,
    /// (lo, hi, height) bars from 0
    pub bars: Vec<(f64, f64, f64)>,
    /// (x0, x1, y0, y1, value) cells of a heat map, coloured by √(value / heat_max), with a
    /// colour bar labelled `heat_label`
    pub heat: Vec<[f64; 5]>,
    /// the value of the top colour (default: the panel's largest cell)
    pub heat_max: Option<f64>,
    /// label of the heat map's colour bar
    pub heat_label: String,
    /// write each cell's value in it (for small grids)
    pub heat_values: bool,
    /// colour linear in the value from the smallest to the largest cell (for maps of statistics
    /// that may be negative), instead of √(value / heat_max) from 0 (for densities)
    pub heat_linear: bool,
    /// contour segments drawn over the heat map
    pub contours: Vec<[(f64, f64); 2]>,
    /// series drawn as lines
    pub lines: Vec<Series>,
    /// series drawn as markers
    pub points: Vec<Series>,
    /// probability mass functions: a stem from 0 to each point, with a marker
    pub stems: Vec<Series>,
    /// logarithmic axes (the data must be positive)
    pub x_log: bool,
    /// logarithmic y axis (as `x_log`)
    pub y_log: bool,
    /// vertical guide lines
    pub vlines: Vec<f64>,
    /// x-axis range in data units (default: the data's span, padded)
    pub x_range: Option<(f64, f64)>,
    /// y-axis range in data units (default: the data's span, padded)
    pub y_range: Option<(f64, f64)>,
    /// ticks at these data values with these labels (a sweep's grid values, a category's name)
    /// instead of round numbers chosen by the axis (empty: round numbers)
    pub x_ticks: Vec<(f64, String)>,
    /// y-axis ticks (as `x_ticks`)
    pub y_ticks: Vec<(f64, String)>,
}

/// A figure: panels on a `rows × cols` grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// file name without extension (`NAME.png`, `NAME.svg`)
    pub name: String,
    /// title above the panels (empty: none)
    pub title: String,
    /// rows of the panel grid
    pub rows: usize,
    /// columns of the panel grid
    pub cols: usize,
    /// (width, height) in pixels
    pub size: (u32, u32),
    /// the panels, row by row
    pub panels: Vec<Panel>,
}
