//! Text drawn into images in an anti-aliased TrueType face (DejaVu Sans, embedded, so no system
//! font is needed): the titles, tick labels and legends of the heatmaps and the captions and
//! legends drawn over the 3D views, so that both read alike.
//!
//! Text is laid out in lines of [`LINE`] × `s` pixels: a line drawn at `y` has its capitals
//! between `y` and `y + LINE × s`, and its descenders a little below.

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};
use image::{ImageBuffer, Pixel};
use std::sync::OnceLock;

/// Height of a capital letter at text scale 1, px: the height of a line of text, without its
/// descenders.
pub const LINE: i64 = 8;

/// Size of the face's em at text scale 1, px: DejaVu Sans's capitals are 0.73 em tall, so
/// this makes them [`LINE`] px.
const EM: f32 = 11.0;

/// The embedded face, parsed once; `None` only if the embedded file could not be read (then
/// text is left out rather than failing a run).
fn face() -> Option<&'static FontRef<'static>> {
    static FACE: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    FACE.get_or_init(|| FontRef::try_from_slice(dejavu::sans::regular()).ok()).as_ref()
}

/// The face's scale at text scale `s`: ab_glyph scales a face by its whole height (ascent
/// less descent), which is more than its em.
fn scale(face: &FontRef<'_>, s: i64) -> PxScale {
    let height_in_ems = face.height_unscaled() / face.units_per_em().unwrap_or(1.0).max(1.0);
    PxScale::from(EM * s as f32 * height_in_ems)
}

/// Width of `text` drawn at text scale `s`, px (its advances, kerning included).
pub fn width(text: &str, s: i64) -> i64 {
    let Some(face) = face() else { return 0 };
    let font = face.as_scaled(scale(face, s));
    let mut x = 0.0f32;
    let mut previous = None;
    for ch in text.chars() {
        let id = font.glyph_id(ch);
        if let Some(p) = previous {
            x += font.kern(p, id);
        }
        x += font.h_advance(id);
        previous = Some(id);
    }
    x.ceil() as i64
}

/// Draws `text` in `ink` at text scale `s`, its capitals between `y` and `y + LINE × s` and its
/// first letter starting at `x` (px); each pixel is blended with the ink by how much of it the
/// glyph covers, and what falls outside `img` is left out. Characters the face lacks are drawn
/// as its replacement box.
pub fn draw<P: Pixel<Subpixel = u8>>(
    img: &mut ImageBuffer<P, Vec<u8>>,
    x: i64,
    y: i64,
    s: i64,
    text: &str,
    ink: P,
) {
    let Some(face) = face() else { return };
    let scale = scale(face, s);
    let font = face.as_scaled(scale);
    let baseline = (y + LINE * s) as f32;
    let mut pen = x as f32;
    let mut previous = None;
    let (w, h) = (i64::from(img.width()), i64::from(img.height()));
    for ch in text.chars() {
        let id = font.glyph_id(ch);
        if let Some(p) = previous {
            pen += font.kern(p, id);
        }
        let glyph = id.with_scale_and_position(scale, ab_glyph::point(pen, baseline));
        pen += font.h_advance(id);
        previous = Some(id);
        let Some(outline) = face.outline_glyph(glyph) else { continue };
        let bounds = outline.px_bounds();
        outline.draw(|gx, gy, coverage| {
            let (px, py) = (bounds.min.x as i64 + i64::from(gx), bounds.min.y as i64 + i64::from(gy));
            if coverage <= 0.0 || px < 0 || py < 0 || px >= w || py >= h {
                return;
            }
            let c = coverage.min(1.0);
            let under = img.get_pixel_mut(px as u32, py as u32);
            under.apply2(&ink, |b, i| (f32::from(b) + (f32::from(i) - f32::from(b)) * c).round() as u8);
        });
    }
}

/// Fills a `w × h` px rectangle with its top-left corner at `(x, y)` px with `color`, clipped to
/// `img`.
pub fn fill<P: Pixel>(img: &mut ImageBuffer<P, Vec<P::Subpixel>>, x: i64, y: i64, w: i64, h: i64, color: P) {
    for py in y.max(0)..(y + h).min(i64::from(img.height())) {
        for px in x.max(0)..(x + w).min(i64::from(img.width())) {
            img.put_pixel(px as u32, py as u32, color);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{Rgb, RgbImage};

    const INK: Rgb<u8> = Rgb([0, 0, 0]);
    const PAPER: Rgb<u8> = Rgb([255, 255, 255]);

    /// The rows and columns of `img` with any ink on them: (first row, last row, first column,
    /// last column), or `None` on a blank image.
    fn inked_box(img: &RgbImage) -> Option<(u32, u32, u32, u32)> {
        let inked: Vec<(u32, u32)> =
            img.enumerate_pixels().filter(|(_, _, p)| **p != PAPER).map(|(x, y, _)| (x, y)).collect();
        let rows = inked.iter().map(|p| p.1);
        let cols = inked.iter().map(|p| p.0);
        Some((rows.clone().min()?, rows.max()?, cols.clone().min()?, cols.max()?))
    }

    #[test]
    fn capitals_fill_the_line_and_scale_with_it() {
        for s in [1, 2, 3] {
            let mut img = RgbImage::from_pixel(200, 60, PAPER);
            draw(&mut img, 10, 10, s, "HEH", INK);
            let (top, bottom, left, right) = inked_box(&img).expect("ink");
            // The capitals stand on the baseline and reach LINE × s above it, within a pixel of
            // anti-aliasing.
            let height = i64::from(bottom) - i64::from(top) + 1;
            assert!((height - LINE * s).abs() <= 1, "scale {s}: capitals {height} px tall");
            assert!((i64::from(bottom) - (10 + LINE * s - 1)).abs() <= 1, "scale {s}: bottom {bottom}");
            // And the ink spans what `width` says, less the side bearings.
            let drawn = i64::from(right) - i64::from(left) + 1;
            let w = width("HEH", s);
            assert!(drawn <= w && drawn >= w - 4 * s, "scale {s}: {drawn} px drawn, width {w}");
            assert!(i64::from(left) >= 10);
        }
    }

    #[test]
    fn glyphs_are_anti_aliased_and_blend_with_what_is_under_them() {
        let mut img = RgbImage::from_pixel(80, 30, PAPER);
        draw(&mut img, 2, 5, 2, "ox", INK);
        let greys = img.pixels().filter(|p| **p != PAPER && **p != INK).count();
        assert!(greys > 10, "{greys} partly covered pixels");
        // Every channel between the paper and the ink.
        assert!(img.pixels().all(|p| p.0[0] == p.0[1] && p.0[1] == p.0[2]));
    }

    #[test]
    fn text_past_the_edges_is_clipped_and_units_are_drawn() {
        let mut img = RgbImage::from_pixel(12, 6, PAPER);
        // Starts left of and above the image, runs past its right edge.
        draw(&mut img, -3, -2, 1, "µm²x", INK);
        assert!(inked_box(&img).is_some());
        // The units' characters are in the face (not its replacement box), and each adds to
        // the width.
        let face = face().expect("the embedded face");
        for ch in ['µ', '²', '³', '°', '×', '–'] {
            assert_ne!(face.glyph_id(ch).0, 0, "{ch} is missing");
            assert!(width(&format!("m{ch}"), 1) > width("m", 1), "{ch}");
        }
        assert_eq!(width("", 3), 0);
    }
}
