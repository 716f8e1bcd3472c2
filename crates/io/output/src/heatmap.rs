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
    /// A note written along one edge of the map (say, which edge faces another target).
    pub edge_note: Option<(Edge, &'a str)>,
}

/// An edge of a map as drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edge {
    /// The first column's edge.
    Left,
    /// The last column's edge.
    Right,
    /// Row 0's edge.
    Bottom,
    /// The last row's edge.
    Top,
}

/// How to label the colour scale.
pub struct Scale {
    /// Quantity and unit, e.g. `"thickness [mm]"`.
    pub label: String,
    /// Factor from the grid's values to the labelled unit.
    pub factor: f64,
    /// A line written under the map, e.g. how the top of the scale was chosen.
    pub footnote: Option<String>,
}

impl Scale {
    /// A thickness scale in mm, or in µm when the largest value (m) is under 1 mm.
    pub fn thickness(max: f64) -> Scale {
        if max >= 1e-3 {
            Scale { label: "thickness [mm]".into(), factor: 1e3, footnote: None }
        } else {
            Scale { label: "thickness [\u{b5}m]".into(), factor: 1e6, footnote: None }
        }
    }

    /// A plain count scale.
    pub fn count(label: &str) -> Scale {
        Scale { label: label.into(), factor: 1.0, footnote: None }
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

/// Round tick values between `lo` and `hi` (in either order), about `about` of them: the
/// multiples in that range of a step of 1, 2, 2.5 or 5 times a power of ten, each with its
/// label, written with as many decimals as the step needs. An empty or non-finite range gives
/// its one end.
pub fn ticks(lo: f64, hi: f64, about: usize) -> Vec<(f64, String)> {
    let (lo, hi) = (lo.min(hi), lo.max(hi));
    let span = hi - lo;
    if !(span.is_finite() && span > 0.0) {
        return if lo.is_finite() { vec![(lo, format!("{lo}"))] } else { Vec::new() };
    }
    let raw = span / about.max(1) as f64;
    let power = 10f64.powf(raw.log10().floor());
    let step =
        [1.0, 2.0, 2.5, 5.0, 10.0].iter().map(|m| m * power).find(|&st| st >= raw).unwrap_or(10.0 * power);
    // Decimals of the step: 2.5 × 10^k needs one more than 10^k.
    let decimals =
        (-(step.log10().floor()) as i64 + i64::from((step / power - 2.5).abs() < 1e-9)).max(0) as usize;
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last)
        .map(|k| {
            let v = k as f64 * step;
            // No "-0".
            let v = if v == 0.0 { 0.0 } else { v };
            (v, format!("{v:.decimals$}"))
        })
        .collect()
}

/// The `q`-quantile (0..1) of the finite values above 0 in `values`, or 0 when there are none:
/// the top of a robust colour scale, which single-cell outliers do not set.
pub fn quantile_of_positive(values: &[f64], q: f64) -> f64 {
    let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite() && *x > 0.0).collect();
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    let k = ((v.len() - 1) as f64 * q.clamp(0.0, 1.0)).round() as usize;
    v[k]
}

/// `v` moved into `[lo, hi]` (px), or `lo` when that range is empty: a label wider or taller
/// than the map it labels starts at the map's start.
fn within(v: i64, lo: i64, hi: i64) -> i64 {
    v.min(hi).max(lo)
}

/// Round ticks of an axis, about five: (fraction along it from its start, label).
fn axis_ticks(a: &MapAxis) -> Vec<(f64, String)> {
    let span = a.to - a.from;
    if span == 0.0 || !span.is_finite() {
        return vec![(0.0, format!("{}", a.from))];
    }
    ticks(a.from, a.to, 5).into_iter().map(|(v, label)| ((v - a.from) / span, label)).collect()
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
/// is not above 0), titled `title`. Values above `max` take the colour of the scale's top.
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
    let su = s as usize;
    let margin = 10 * su;
    let title_h = 14 * su;
    let bar_w = 12 * su;
    let bar_ticks = ticks(0.0, top, 5);
    let label_w = bar_ticks.iter().map(|(_, l)| text::width(l, s)).max().unwrap_or(0) as usize;
    let ticks_w = bar_w + 6 * su + label_w;
    // Room for the axes' ticks and labels: numbers left of the map, below it, and the labels.
    let axis_ticks = grid.axes.map(|a| [axis_ticks(&a[0]), axis_ticks(&a[1])]);
    let left = axis_ticks
        .as_ref()
        .map_or(0, |t| t[1].iter().map(|l| text::width(&l.1, s)).max().unwrap_or(0) as usize + 8 * su);
    let edge = grid.edge_note.map(|(e, note)| (e, note, text::width(note, s) as usize));
    // An edge note beside the map takes a column; one above or below it, a line.
    let (note_left, note_right) = match edge {
        Some((Edge::Left, _, nw)) => (nw + 6 * su, 0),
        Some((Edge::Right, _, nw)) => (0, nw + 6 * su),
        _ => (0, 0),
    };
    let note_lines = usize::from(matches!(edge, Some((Edge::Top | Edge::Bottom, _, _))));
    let bottom = if grid.axes.is_some() { 2 * title_h + 4 * su } else { 0 };
    let foot = usize::from(scale.footnote.is_some()) * title_h;
    let label_width = text::width(&scale.label, s) as usize;
    let width = margin + note_left + left + w + note_right + margin + ticks_w.max(label_width) + margin;
    let height = margin + 2 * title_h + note_lines * title_h + h + bottom + foot + margin;
    let width = width.max(margin + text::width(title, s) as usize + margin);
    let mut img = RgbImage::from_pixel(width as u32, height as u32, WHITE);
    text::draw(&mut img, margin as i64, margin as i64, s, title, BLACK);

    // Data area: averages of down × down blocks; image row 0 is the grid's top row.
    let top_note = usize::from(matches!(edge, Some((Edge::Top, _, _)))) * title_h;
    let (x0, y0) = (margin + note_left + left, margin + 2 * title_h + top_note);
    if let (Some(axes), Some(ticks)) = (grid.axes, &axis_ticks) {
        draw_axes(&mut img, axes, ticks, (x0, y0, w, h), s);
    }
    draw_cells(&mut img, grid, scale.factor / top, map, (x0, y0), (down, up));
    if let Some((e, note, nw)) = edge {
        let (nx, ny) = match e {
            Edge::Left => (x0 - left - nw - 6 * su, y0 + h / 2),
            Edge::Right => (x0 + w + 6 * su, y0 + h / 2),
            Edge::Top => (x0 + w.saturating_sub(nw) / 2, y0 - title_h),
            Edge::Bottom => (x0 + w.saturating_sub(nw) / 2, y0 + h + bottom),
        };
        text::draw(&mut img, nx as i64, ny as i64, s, note, BLACK);
    }
    let bar_x = x0 + w + note_right + margin;
    text::draw(&mut img, bar_x as i64, (margin + title_h) as i64, s, &scale.label, BLACK);
    draw_color_bar(&mut img, (bar_x, y0, bar_w, h), s, map, top, &bar_ticks);
    if let Some(f) = &scale.footnote {
        text::draw(&mut img, margin as i64, (height - margin - foot + 2 * su) as i64, s, f, BLACK);
    }
    img
}

/// Paints `grid`'s cells into `img` with the data area's top-left corner at `(x0, y0)` px: the
/// mean of each `down × down` block of cells (its finite values), times `to_unit` (from the
/// grid's values to the colour scale's 0..1), as an `up × up` px square.
fn draw_cells(
    img: &mut RgbImage,
    grid: &Grid<'_>,
    to_unit: f64,
    map: Colormap,
    (x0, y0): (usize, usize),
    (down, up): (usize, usize),
) {
    let (cols, rows) = (grid.cols, grid.rows);
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
            let base = if n > 0.0 { color(map, sum / n * to_unit) } else { NO_SURFACE };
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
}

/// A vertical colour bar at `(x, y)`, `bar_w` × `h` px, for the scale from 0 to `top`, with a
/// tick at each of `ticks` (value, label); `s` is the text scale.
fn draw_color_bar(
    img: &mut RgbImage,
    (bx, y0, bar_w, h): (usize, usize, usize, usize),
    s: i64,
    map: Colormap,
    top: f64,
    ticks: &[(f64, String)],
) {
    for y in 0..h {
        let px = color(map, 1.0 - y as f64 / (h - 1).max(1) as f64);
        for x in 0..bar_w {
            img.put_pixel((bx + x) as u32, (y0 + y) as u32, px);
        }
    }
    for (v, label) in ticks {
        let f = (v / top).clamp(0.0, 1.0);
        let y = y0 + (h - 1) - ((h - 1) as f64 * f).round() as usize;
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
            let grid = Grid { values: &values, cols, rows, marks: None, axes: Some(&axes), edge_note: None };
            let img = render(&grid, "narrow", &Scale::thickness(1e-3), Colormap::Viridis);
            // Every pixel of the data area in the colour of the scale's top.
            let side = cols.max(rows);
            let (down, up) = (side.div_ceil(MAX_SIDE), (MIN_SIDE / side).max(1));
            let area = cols.div_ceil(down) * rows.div_ceil(down) * up * up;
            let painted = img.pixels().filter(|p| **p == top).count();
            assert!(painted >= area, "{cols} × {rows}: {painted} px of {area}");
        }
    }

    #[test]
    fn ticks_are_round_multiples_of_one_step_inside_the_range() {
        for (lo, hi) in
            [(0.0, 50.6), (0.0, 37.9), (-1.0, 1.0), (2.0, -2.0), (0.0, 0.0126), (0.3, 4.1), (0.0, 210.0)]
        {
            let t = ticks(lo, hi, 5);
            assert!((3..=11).contains(&t.len()), "{lo}..{hi}: {t:?}");
            let step = t[1].0 - t[0].0;
            let power = 10f64.powf(step.log10().floor());
            let mantissa = step / power;
            assert!(
                [1.0, 2.0, 2.5, 5.0].iter().any(|m| (m - mantissa).abs() < 1e-9),
                "{lo}..{hi}: step {step}"
            );
            for (k, (v, label)) in t.iter().enumerate() {
                assert!(*v >= lo.min(hi) - 1e-12 && *v <= lo.max(hi) + 1e-12, "{v} outside {lo}..{hi}");
                assert!((v / step - (v / step).round()).abs() < 1e-9, "{v} is not a multiple of {step}");
                assert!(k == 0 || (v - t[k - 1].0 - step).abs() < 1e-9 * step.max(1.0));
                // The label is the value, with no float noise and no "-0".
                assert_eq!(
                    label.parse::<f64>().ok().map(|x| (x - v).abs() < 1e-9 * step.max(1.0)),
                    Some(true)
                );
                assert!(label.len() <= 6 && label != "-0", "{label}");
            }
        }
        assert_eq!(
            ticks(0.0, 37.9, 5).iter().map(|t| t.1.as_str()).collect::<Vec<_>>(),
            ["0", "10", "20", "30"]
        );
        assert_eq!(
            ticks(-1.0, 1.0, 5).iter().map(|t| t.1.as_str()).collect::<Vec<_>>(),
            ["-1.0", "-0.5", "0.0", "0.5", "1.0"]
        );
        assert_eq!(ticks(1.0, 1.0, 5).len(), 1);
    }
}
