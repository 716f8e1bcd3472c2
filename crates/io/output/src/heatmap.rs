//! Heatmap images of a heightfield-sized grid, with a title and a labelled colour scale.

use crate::text;
use image::{Rgb, RgbImage};
use spraysim_engine::deposit::MapAxis;
use spraysim_scenario::Colormap;

/// Largest side of the data area in pixels; finer grids are averaged down to it.
const MAX_SIDE: usize = 2048;
/// Smallest side of the data area in pixels; coarser grids are enlarged to it.
const MIN_SIDE: usize = 512;

const WHITE: Rgb<u8> = Rgb([255, 255, 255]);
const BLACK: Rgb<u8> = Rgb([0, 0, 0]);
/// Where the surface is cut away (an opening): no value.
const NO_SURFACE: Rgb<u8> = Rgb([205, 205, 205]);

/// A grid to draw: `values[row * cols + col]`, row 0 at the bottom (drawn at the bottom, so the
/// face's `up` is at the top of the image).
pub struct Grid<'a> {
    /// Values, row-major from the bottom row.
    pub values: &'a [f64],
    /// Cells across, drawn left to right.
    pub cols: usize,
    /// Cells up, drawn bottom to top.
    pub rows: usize,
    /// Optional per-cell marks drawn over the colours: 1 at risk (orange), 2 failed (red).
    pub marks: Option<&'a [u8]>,
    /// What the columns and rows run along, labelled under and beside the map.
    pub axes: Option<&'a [MapAxis; 2]>,
}

/// How to label the colour scale.
pub struct Scale {
    /// Quantity and unit, e.g. `"thickness [mm]"`.
    pub label: String,
    /// Factor from the grid's values to the labelled unit.
    pub factor: f64,
}

impl Scale {
    /// A thickness scale in mm, or in µm when the largest value (m) is under 1 mm.
    pub fn thickness(max: f64) -> Scale {
        if max >= 1e-3 {
            Scale { label: "thickness [mm]".into(), factor: 1e3 }
        } else {
            Scale { label: "thickness [\u{b5}m]".into(), factor: 1e6 }
        }
    }

    /// A plain count scale.
    pub fn count(label: &str) -> Scale {
        Scale { label: label.into(), factor: 1.0 }
    }
}

/// The colour of `t` (0..1, clamped) on colour map `map`: the scale of every heatmap, for
/// anything that must match it (a 3D view, an exported mesh).
pub fn color(map: Colormap, t: f64) -> Rgb<u8> {
    let g = match map {
        Colormap::Viridis => colorous::VIRIDIS,
        Colormap::Turbo => colorous::TURBO,
        Colormap::Inferno => colorous::INFERNO,
        Colormap::Blues => colorous::BLUES,
    };
    let c = g.eval_continuous(t.clamp(0.0, 1.0));
    Rgb([c.r, c.g, c.b])
}

/// A tick value with as many decimals as its range needs (`max`: the scale's top).
pub fn tick_label(v: f64, max: f64) -> String {
    let decimals = if max >= 100.0 {
        0
    } else if max >= 10.0 {
        1
    } else if max >= 1.0 {
        2
    } else {
        3
    };
    format!("{v:.decimals$}")
}

/// `v` moved into `[lo, hi]` (px), or `lo` when that range is empty: a label wider or taller
/// than the map it labels starts at the map's start.
fn within(v: i64, lo: i64, hi: i64) -> i64 {
    v.min(hi).max(lo)
}

/// Three ticks of an axis: (fraction along it, label).
fn axis_ticks(a: &MapAxis) -> Vec<(f64, String)> {
    let span = (a.to - a.from).abs().max(1e-12);
    [0.0, 0.5, 1.0].iter().map(|&f| (f, tick_label(a.from + f * (a.to - a.from), span))).collect()
}

/// Ticks and labels of the map's axes around the data area `(x0, y0, w, h)`.
fn draw_axes(
    img: &mut RgbImage,
    axes: &[MapAxis; 2],
    ticks: &[Vec<(f64, String)>; 2],
    area: (usize, usize, usize, usize),
    s: i64,
) {
    let (x0, y0, w, h) = area;
    let tick = 4 * s as usize;
    for (f, label) in &ticks[0] {
        let x = x0 + ((w - 1) as f64 * f) as usize;
        for dy in 0..tick {
            img.put_pixel(x as u32, (y0 + h + dy) as u32, BLACK);
        }
        let tx = within(
            x as i64 - text::width(label, s) / 2,
            x0 as i64 - 8 * s,
            (x0 + w) as i64 - text::width(label, s) + 8 * s,
        );
        text::draw(img, tx, (y0 + h + tick + s as usize) as i64, s, label, BLACK);
    }
    let label_x = x0 as i64 + (w as i64 - text::width(axes[0].label, s)) / 2;
    text::draw(
        img,
        label_x.max(x0 as i64),
        (y0 + h + tick + 10 * s as usize + s as usize) as i64,
        s,
        axes[0].label,
        BLACK,
    );
    for (f, label) in &ticks[1] {
        let y = y0 + h - 1 - ((h - 1) as f64 * f) as usize;
        for dx in 0..tick {
            img.put_pixel((x0 - 1 - dx) as u32, y as u32, BLACK);
        }
        let ty = within(y as i64 - 4 * s, y0 as i64, (y0 + h) as i64 - 8 * s);
        text::draw(img, x0 as i64 - tick as i64 - 2 - text::width(label, s), ty, s, label, BLACK);
    }
    // The vertical axis's label above the map, at its left.
    text::draw(img, x0 as i64, y0 as i64 - 10 * s, s, axes[1].label, BLACK);
}

/// Renders `grid` as a heatmap from 0 to its maximum, titled `title`.
pub fn render(grid: &Grid<'_>, title: &str, scale: &Scale, map: Colormap) -> RgbImage {
    let max = grid.values.iter().copied().fold(0.0_f64, f64::max);
    render_range(grid, title, scale, map, max)
}

/// Renders `grid` as a heatmap from 0 to `max` (in the grid's unit; the largest value when it
/// is not above 0), titled `title`.
pub fn render_range(grid: &Grid<'_>, title: &str, scale: &Scale, map: Colormap, max: f64) -> RgbImage {
    let (cols, rows) = (grid.cols, grid.rows);
    // Pixels per cell (enlarge) or cells per pixel (shrink), keeping the aspect ratio.
    let side = cols.max(rows);
    let down = side.div_ceil(MAX_SIDE).max(1);
    let up = (MIN_SIDE / side).max(1);
    let (w, h) = (cols.div_ceil(down) * up, rows.div_ceil(down) * up);
    let max = max * scale.factor;
    let top = if max > 0.0 { max } else { 1.0 };

    let s: i64 = if h >= 400 { 2 } else { 1 };
    let margin = 10 * s as usize;
    let title_h = 12 * s as usize;
    let bar_w = 12 * s as usize;
    let labels = (0..=4).map(|i| tick_label(top * i as f64 / 4.0, top)).collect::<Vec<_>>();
    let label_w = labels.iter().map(|l| l.len()).max().unwrap_or(1) * 8 * s as usize;
    let ticks_w = bar_w + 6 * s as usize + label_w;
    // Room for the axes' ticks and labels: numbers left of the map, below it, and the labels.
    let axis_ticks = grid.axes.map(|a| [axis_ticks(&a[0]), axis_ticks(&a[1])]);
    let left = axis_ticks
        .as_ref()
        .map_or(0, |t| t[1].iter().map(|l| l.1.len()).max().unwrap_or(0) * 8 * s as usize + 8 * s as usize);
    let bottom = if grid.axes.is_some() { 2 * title_h + 4 * s as usize } else { 0 };
    let width =
        margin + left + w + margin + ticks_w.max(scale.label.chars().count() * 8 * s as usize) + margin;
    let height = margin + title_h + title_h + h + bottom + margin;
    let mut img = RgbImage::from_pixel(width as u32, height as u32, WHITE);
    text::draw(&mut img, margin as i64, margin as i64, s, title, BLACK);

    // Data area: averages of down × down blocks; image row 0 is the grid's top row.
    let (x0, y0) = (margin + left, margin + 2 * title_h);
    if let (Some(axes), Some(ticks)) = (grid.axes, &axis_ticks) {
        draw_axes(&mut img, axes, ticks, (x0, y0, w, h), s);
    }
    for by in 0..rows.div_ceil(down) {
        for bx in 0..cols.div_ceil(down) {
            let (mut sum, mut n, mut mark) = (0.0, 0.0, 0u8);
            for r in by * down..((by + 1) * down).min(rows) {
                for c in bx * down..((bx + 1) * down).min(cols) {
                    let v = grid.values[r * cols + c];
                    if v.is_finite() {
                        sum += v;
                        n += 1.0;
                    }
                    mark = mark.max(grid.marks.map_or(0, |m| m[r * cols + c]));
                }
            }
            let base = if n > 0.0 { color(map, sum / n * scale.factor / top) } else { NO_SURFACE };
            // Marks are blended over the colour, so the thickness still reads through.
            let px = match mark {
                0 => base,
                m => {
                    let tint = if m == 1 { [255u16, 150, 0] } else { [220, 0, 0] };
                    Rgb(std::array::from_fn(|k| ((u16::from(base.0[k]) + 3 * tint[k]) / 4) as u8))
                }
            };
            let img_row = rows.div_ceil(down) - 1 - by;
            for dy in 0..up {
                for dx in 0..up {
                    img.put_pixel((x0 + bx * up + dx) as u32, (y0 + img_row * up + dy) as u32, px);
                }
            }
        }
    }

    text::draw(&mut img, (x0 + w + margin) as i64, (margin + title_h) as i64, s, &scale.label, BLACK);
    draw_color_bar(&mut img, (x0 + w + margin, y0, bar_w, h), s, map, &labels);
    img
}

/// A vertical colour bar at `(x, y)`, `bar_w` × `h` px, with five ticks labelled `labels`
/// from the bottom up; `s` is the text scale.
fn draw_color_bar(
    img: &mut RgbImage,
    (bx, y0, bar_w, h): (usize, usize, usize, usize),
    s: i64,
    map: Colormap,
    labels: &[String],
) {
    for y in 0..h {
        let px = color(map, 1.0 - y as f64 / (h - 1).max(1) as f64);
        for x in 0..bar_w {
            img.put_pixel((bx + x) as u32, (y0 + y) as u32, px);
        }
    }
    for (i, label) in labels.iter().enumerate() {
        let y = y0 + (h - 1) - (h - 1) * i / 4;
        for x in 0..(bar_w + 3 * s as usize) {
            img.put_pixel((bx + x) as u32, y as u32, BLACK);
        }
        let ty = within(y as i64 - 4 * s, y0 as i64, (y0 + h) as i64 - 8 * s);
        text::draw(img, (bx + bar_w + 6 * s as usize) as i64, ty, s, label, BLACK);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_narrower_or_lower_than_their_labels_are_drawn_whole() {
        let axes =
            [MapAxis { label: "y [m]", from: -1.0, to: 1.0 }, MapAxis { label: "z [m]", from: 0.0, to: 2.0 }];
        let top = color(Colormap::Viridis, 1.0);
        for (cols, rows) in [(4, 1024), (1024, 4), (2, 3000), (1, 1)] {
            let values = vec![1e-3; cols * rows];
            let grid = Grid { values: &values, cols, rows, marks: None, axes: Some(&axes) };
            let img = render(&grid, "narrow", &Scale::thickness(1e-3), Colormap::Viridis);
            // Every pixel of the data area in the colour of the scale's top.
            let side = cols.max(rows);
            let (down, up) = (side.div_ceil(MAX_SIDE), (MIN_SIDE / side).max(1));
            let area = cols.div_ceil(down) * rows.div_ceil(down) * up * up;
            let painted = img.pixels().filter(|p| **p == top).count();
            assert!(painted >= area, "{cols} × {rows}: {painted} px of {area}");
        }
    }
}
