//! Heatmap images of a heightfield-sized grid, with a title and a labelled colour scale.

use image::{Rgb, RgbImage};
use spraysim_scenario::Colormap;

/// Largest side of the data area in pixels; finer grids are averaged down to it.
const MAX_SIDE: usize = 2048;
/// Smallest side of the data area in pixels; coarser grids are enlarged to it.
const MIN_SIDE: usize = 512;

const WHITE: Rgb<u8> = Rgb([255, 255, 255]);
const BLACK: Rgb<u8> = Rgb([0, 0, 0]);

/// A grid to draw: `values[row * cols + col]`, row 0 at the bottom (drawn at the bottom, so the
/// face's `up` is at the top of the image).
pub struct Grid<'a> {
    /// Values, row-major from the bottom row.
    pub values: &'a [f64],
    /// Columns.
    pub cols: usize,
    /// Rows.
    pub rows: usize,
    /// Optional per-cell marks drawn over the colours: 1 at risk (orange), 2 failed (red).
    pub marks: Option<&'a [u8]>,
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

/// Draws `text` with its top-left corner at `(x, y)`, each font pixel `s × s`.
fn draw_text(img: &mut RgbImage, x: i64, y: i64, s: i64, text: &str) {
    for (k, ch) in text.chars().enumerate() {
        let code = ch as usize;
        let glyph = match code {
            0..=127 => font8x8::legacy::BASIC_LEGACY[code],
            0xA0..=0xFF => font8x8::legacy::LATIN_LEGACY[code - 0xA0],
            _ => font8x8::legacy::BASIC_LEGACY[b'?' as usize],
        };
        for (gy, bits) in glyph.iter().enumerate() {
            for gx in 0..8 {
                if bits >> gx & 1 == 0 {
                    continue;
                }
                for dy in 0..s {
                    for dx in 0..s {
                        let px = x + (k as i64 * 8 + gx) * s + dx;
                        let py = y + gy as i64 * s + dy;
                        if px >= 0 && py >= 0 && (px as u32) < img.width() && (py as u32) < img.height() {
                            img.put_pixel(px as u32, py as u32, BLACK);
                        }
                    }
                }
            }
        }
    }
}

/// A tick value with as many decimals as its range needs.
fn tick_label(v: f64, max: f64) -> String {
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
    let width = margin + w + margin + ticks_w.max(scale.label.chars().count() * 8 * s as usize) + margin;
    let height = margin + title_h + title_h + h + margin;
    let mut img = RgbImage::from_pixel(width as u32, height as u32, WHITE);
    draw_text(&mut img, margin as i64, margin as i64, s, title);

    // Data area: averages of down × down blocks; image row 0 is the grid's top row.
    let (x0, y0) = (margin, margin + 2 * title_h);
    for by in 0..rows.div_ceil(down) {
        for bx in 0..cols.div_ceil(down) {
            let (mut sum, mut n, mut mark) = (0.0, 0.0, 0u8);
            for r in by * down..((by + 1) * down).min(rows) {
                for c in bx * down..((bx + 1) * down).min(cols) {
                    sum += grid.values[r * cols + c];
                    n += 1.0;
                    mark = mark.max(grid.marks.map_or(0, |m| m[r * cols + c]));
                }
            }
            let base = color(map, sum / n * scale.factor / top);
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

    // Colour bar with five ticks, its label above it.
    let bx = x0 + w + margin;
    draw_text(&mut img, bx as i64, (margin + title_h) as i64, s, &scale.label);
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
        let ty = (y as i64 - 4 * s).clamp(y0 as i64, (y0 + h) as i64 - 8 * s);
        draw_text(&mut img, (bx + bar_w + 6 * s as usize) as i64, ty, s, label);
    }
    img
}
