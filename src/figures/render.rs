//! Drawing a [`Figure`] with plotters, to PNG and SVG alike.
//!
//! Text uses DejaVu Sans, compiled into the binary (`assets/fonts`, license beside it), so
//! figures render the same on a fresh machine without system fonts or libraries.

use std::path::{Path, PathBuf};
use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::colors::colormaps::ViridisRGB;

use super::{Figure, Panel};

static FONT: Once = Once::new();

fn register_font() {
    FONT.call_once(|| {
        let bytes: &'static [u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
        let registered = plotters::style::register_font("sans-serif", FontStyle::Normal, bytes);
        assert!(registered.is_ok(), "the bundled font parses");
    });
}

/// Series colours: blue, red, green, orange, purple, brown, black.
pub const PALETTE: [RGBColor; 7] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(0, 0, 0),
];

fn err(e: impl std::fmt::Display) -> String {
    e.to_string()
}

/// Axis ranges covering everything a panel draws (or its explicit ranges), with a little room.
fn ranges(p: &Panel) -> ((f64, f64), (f64, f64)) {
    let mut xs: Vec<f64> = Vec::new();
    let mut ys: Vec<f64> = vec![];
    for b in &p.bars {
        xs.extend([b.0, b.1]);
        ys.extend([0.0, b.2]);
    }
    for c in &p.heat {
        xs.extend([c[0], c[1]]);
        ys.extend([c[2], c[3]]);
    }
    for s in p.lines.iter().chain(&p.points) {
        for &(x, y) in &s.points {
            xs.push(x);
            ys.push(y);
        }
    }
    xs.extend(&p.vlines);
    let span = |v: &[f64], pad: f64| {
        let lo = v.iter().copied().filter(|x| x.is_finite()).fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().filter(|x| x.is_finite()).fold(f64::NEG_INFINITY, f64::max);
        if !(lo <= hi) {
            return (0.0, 1.0);
        }
        let d = if hi > lo { (hi - lo) * pad } else { 0.5 };
        (lo - if lo == 0.0 { 0.0 } else { d }, hi + d)
    };
    (p.x_range.unwrap_or_else(|| span(&xs, 0.02)), p.y_range.unwrap_or_else(|| span(&ys, 0.05)))
}

fn draw_panel<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, p: &Panel) -> Result<(), String> {
    let ((x0, x1), (y0, y1)) = ranges(p);
    let mut chart = ChartBuilder::on(area)
        .caption(&p.title, ("sans-serif", 17))
        .margin(8)
        .x_label_area_size(36)
        .y_label_area_size(52)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(p.x_label.as_str())
        .y_desc(p.y_label.as_str())
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 14))
        .x_labels(6)
        .y_labels(6)
        .draw()
        .map_err(err)?;
    if !p.heat.is_empty() {
        let max = p.heat_max.unwrap_or_else(|| p.heat.iter().map(|c| c[4]).fold(0.0, f64::max)).max(f64::MIN_POSITIVE);
        chart
            .draw_series(p.heat.iter().map(|c| {
                let color = ViridisRGB.get_color((c[4] / max).clamp(0.0, 1.0).sqrt() as f32);
                Rectangle::new([(c[0], c[2]), (c[1], c[3])], color.filled())
            }))
            .map_err(err)?;
    }
    chart
        .draw_series(p.bars.iter().map(|&(lo, hi, h)| Rectangle::new([(lo, 0.0), (hi, h)], PALETTE[0].mix(0.55).filled())))
        .map_err(err)?;
    for &x in &p.vlines {
        chart.draw_series(LineSeries::new([(x, y0), (x, y1)], RGBColor(170, 170, 170).stroke_width(1))).map_err(err)?;
    }
    let mut labelled = false;
    for s in &p.lines {
        let color = PALETTE[s.color % PALETTE.len()];
        // the bitmap rasterizer joins many short thick segments raggedly: dense lines are thin
        let width = if s.points.len() > 200 { 1 } else { 2 };
        let series = chart.draw_series(LineSeries::new(s.points.iter().copied(), color.stroke_width(width))).map_err(err)?;
        if !s.label.is_empty() {
            labelled = true;
            series.label(s.label.as_str()).legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], color.stroke_width(2)));
        }
    }
    for s in &p.points {
        let color = PALETTE[s.color % PALETTE.len()];
        let series = chart
            .draw_series(s.points.iter().map(|&(x, y)| Circle::new((x, y), 3, color.filled())))
            .map_err(err)?;
        if !s.label.is_empty() {
            labelled = true;
            series.label(s.label.as_str()).legend(move |(x, y)| Circle::new((x + 8, y), 3, color.filled()));
        }
    }
    if labelled {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.3))
            .label_font(("sans-serif", 12))
            .draw()
            .map_err(err)?;
    }
    Ok(())
}

fn draw<DB: DrawingBackend>(root: DrawingArea<DB, Shift>, f: &Figure) -> Result<(), String> {
    root.fill(&WHITE).map_err(err)?;
    let body = if f.title.is_empty() {
        root.clone()
    } else {
        root.titled(&f.title, ("sans-serif", 20)).map_err(err)?
    };
    for (area, panel) in body.split_evenly((f.rows, f.cols)).iter().zip(&f.panels) {
        draw_panel(area, panel)?;
    }
    root.present().map_err(err)
}

/// Write `dir/NAME.png` and `dir/NAME.svg`; returns both paths.
pub fn save(f: &Figure, dir: &Path) -> Result<[PathBuf; 2], String> {
    register_font();
    let (w, h) = f.size;
    let png = dir.join(format!("{}.png", f.name));
    let svg = dir.join(format!("{}.svg", f.name));
    draw(BitMapBackend::new(&png, (w, h)).into_drawing_area(), f)?;
    draw(SVGBackend::new(&svg, (w, h)).into_drawing_area(), f)?;
    Ok([png, svg])
}
