//! # spraysim-plot
//!
//! Line charts as PNG, for calibration and validation reports: simulated against measured or
//! closed-form curves. The charts are drawn with plotters into an RGB buffer and encoded as PNG.

use plotters::prelude::*;
use spraysim_output::OutputError;
use std::path::Path;
use std::sync::Once;

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mark {
    /// A continuous line (closed forms, models).
    Line,
    /// Circles at the points (samples, measurements).
    Points,
    /// Circles joined by a thin line.
    LinePoints,
    /// Ranges: the points in pairs `(x, low), (x, high)`, each drawn as a vertical bar with caps
    /// (published ranges, bands of acceptance).
    Ranges,
}

/// One labelled series of `(x, y)` points.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// Points, in drawing order.
    pub points: Vec<(f64, f64)>,
    /// How to draw them.
    pub mark: Mark,
}

impl Series {
    /// A series from its label, points and mark.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, mark: Mark) -> Series {
        Series { label: label.into(), points, mark }
    }
}

/// Where the legend sits, clear of the data.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Legend {
    /// Upper right corner.
    #[default]
    UpperRight,
    /// Upper left corner.
    UpperLeft,
    /// Middle of the right edge.
    MiddleRight,
}

/// A chart: title, axis labels (with units) and series.
#[derive(Clone, Debug, Default)]
pub struct Chart {
    /// Title above the plot.
    pub title: String,
    /// Label of the x axis, with its unit.
    pub x_label: String,
    /// Label of the y axis, with its unit.
    pub y_label: String,
    /// The series, drawn in order, coloured by position.
    pub series: Vec<Series>,
    /// Legend placement.
    pub legend: Legend,
}

/// Chart size in pixels.
const SIZE: (u32, u32) = (800, 500);

/// Registers the embedded font once: the renderer needs no system fonts.
fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The embedded face is a valid TrueType font; should it ever fail, text is simply absent.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular());
    });
}

/// Colours of successive series: black first (references), then distinguishable hues.
const COLORS: [RGBColor; 5] = [
    RGBColor(20, 20, 20),
    RGBColor(214, 39, 40),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
];

/// Axis range covering every finite point with a 5 % margin (a unit range when empty or flat).
fn bounds(chart: &Chart) -> ((f64, f64), (f64, f64)) {
    let pts = chart.series.iter().flat_map(|s| &s.points).filter(|(x, y)| x.is_finite() && y.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) =
        (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    for &(x, y) in pts {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    let pad = |lo: f64, hi: f64| {
        if lo.is_nan() || hi.is_nan() || lo > hi {
            (0.0, 1.0)
        } else if hi - lo < 1e-300 {
            (lo - 0.5 * lo.abs().max(1.0), hi + 0.5 * hi.abs().max(1.0))
        } else {
            let m = 0.05 * (hi - lo);
            (lo - m, hi + m)
        }
    };
    (pad(x0, x1), pad(y0, y1))
}

/// Renders `chart` as an RGB image.
pub fn render(chart: &Chart) -> Result<image::RgbImage, String> {
    register_font();
    let mut buf = vec![255u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, SIZE).into_drawing_area();
        let ((x0, x1), (y0, y1)) = bounds(chart);
        let mut ctx = ChartBuilder::on(&root)
            .caption(&chart.title, ("sans-serif", 22))
            .margin(14)
            .x_label_area_size(46)
            .y_label_area_size(72)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| e.to_string())?;
        ctx.configure_mesh()
            .x_desc(chart.x_label.as_str())
            .y_desc(chart.y_label.as_str())
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 17))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(|e| e.to_string())?;
        for (i, s) in chart.series.iter().enumerate() {
            let color = COLORS[i % COLORS.len()];
            let pts: Vec<(f64, f64)> =
                s.points.iter().copied().filter(|(x, y)| x.is_finite() && y.is_finite()).collect();
            let width = if s.mark == Mark::Line { 2 } else { 1 };
            let cap = 0.01 * (x1 - x0);
            let drawn = match s.mark {
                Mark::Points => ctx.draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled()))),
                Mark::Line | Mark::LinePoints => {
                    ctx.draw_series(LineSeries::new(pts.iter().copied(), color.stroke_width(width)))
                }
                Mark::Ranges => ctx.draw_series(pts.chunks_exact(2).flat_map(|pair| {
                    let ((x, lo), (_, hi)) = (pair[0], pair[1]);
                    [
                        PathElement::new(vec![(x, lo), (x, hi)], color.stroke_width(3)),
                        PathElement::new(vec![(x - cap, lo), (x + cap, lo)], color.stroke_width(2)),
                        PathElement::new(vec![(x - cap, hi), (x + cap, hi)], color.stroke_width(2)),
                    ]
                })),
            }
            .map_err(|e| e.to_string())?;
            drawn
                .label(s.label.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2)));
            if s.mark == Mark::LinePoints {
                ctx.draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))
                    .map_err(|e| e.to_string())?;
            }
        }
        ctx.configure_series_labels()
            .position(match chart.legend {
                Legend::UpperRight => SeriesLabelPosition::UpperRight,
                Legend::UpperLeft => SeriesLabelPosition::UpperLeft,
                Legend::MiddleRight => SeriesLabelPosition::MiddleRight,
            })
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(180, 180, 180))
            .label_font(("sans-serif", 15))
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    image::RgbImage::from_raw(SIZE.0, SIZE.1, buf).ok_or_else(|| "chart buffer has the wrong size".into())
}

/// `chart` as PNG bytes; `at` names the file in errors.
pub fn png(chart: &Chart, at: &Path) -> Result<Vec<u8>, OutputError> {
    let img = render(chart).map_err(|message| OutputError::Image { path: at.to_path_buf(), message })?;
    spraysim_output::png_bytes(&img, at)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chart_draws_its_series_and_text() {
        let chart = Chart {
            title: "t".into(),
            x_label: "x [m]".into(),
            y_label: "y [m]".into(),
            series: vec![
                Series::new("line", vec![(0.0, 0.0), (1.0, 1.0)], Mark::Line),
                Series::new("points", vec![(0.5, 0.2), (f64::NAN, 1.0)], Mark::Points),
            ],
            legend: Legend::UpperLeft,
        };
        let img = render(&chart).expect("renders");
        let red = img.pixels().filter(|p| p.0 == [214, 39, 40]).count();
        let dark = img.pixels().filter(|p| p.0.iter().all(|&c| c < 60)).count();
        assert!(red > 20, "the point series is drawn ({red} pixels)");
        // The line, the axes and the text are dark; text alone adds hundreds of pixels.
        assert!(dark > 2000, "{dark} dark pixels");
    }
}
