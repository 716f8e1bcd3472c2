//! Text drawn into images in an 8 × 8 pixel bitmap font (ASCII and Latin-1; other characters
//! as `?`), scaled by whole pixels: the titles and labels of the heatmaps and the captions and
//! legends drawn over the 3D views, so that both read alike.

use image::{ImageBuffer, Pixel};

/// Width and height of one character, in font pixels (a font pixel is `s × s` image pixels).
pub const GLYPH: i64 = 8;

/// The bitmap of `ch`: eight rows from the top, bit `k` of a row its `k`-th pixel from the left.
fn glyph(ch: char) -> [u8; 8] {
    let code = ch as usize;
    match code {
        0..=127 => font8x8::legacy::BASIC_LEGACY[code],
        0xA0..=0xFF => font8x8::legacy::LATIN_LEGACY[code - 0xA0],
        _ => font8x8::legacy::BASIC_LEGACY[usize::from(b'?')],
    }
}

/// Width of `text` drawn with font pixels of `s × s`, px.
pub fn width(text: &str, s: i64) -> i64 {
    text.chars().count() as i64 * GLYPH * s
}

/// Draws `text` in `ink` with its top-left corner at `(x, y)` px, each font pixel `s × s` px;
/// what falls outside `img` is left out.
pub fn draw<P: Pixel>(
    img: &mut ImageBuffer<P, Vec<P::Subpixel>>,
    x: i64,
    y: i64,
    s: i64,
    text: &str,
    ink: P,
) {
    for (k, ch) in text.chars().enumerate() {
        for (gy, bits) in glyph(ch).iter().enumerate() {
            for gx in 0..GLYPH {
                if bits >> gx & 1 == 1 {
                    fill(img, x + (k as i64 * GLYPH + gx) * s, y + gy as i64 * s, s, s, ink);
                }
            }
        }
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

    /// The inked pixels of `img`, as (x, y).
    fn inked(img: &RgbImage) -> Vec<(u32, u32)> {
        img.enumerate_pixels().filter(|(_, _, p)| **p == INK).map(|(x, y, _)| (x, y)).collect()
    }

    #[test]
    fn a_character_is_its_glyph_scaled_by_whole_pixels() {
        let mut one = RgbImage::from_pixel(8, 8, Rgb([255, 255, 255]));
        draw(&mut one, 0, 0, 1, "A", INK);
        let mut two = RgbImage::from_pixel(16, 16, Rgb([255, 255, 255]));
        draw(&mut two, 0, 0, 2, "A", INK);
        let glyph = font8x8::legacy::BASIC_LEGACY[usize::from(b'A')];
        let expected: Vec<(u32, u32)> = (0..8u32)
            .flat_map(|y| (0..8u32).map(move |x| (x, y)))
            .filter(|&(x, y)| glyph[y as usize] >> x & 1 == 1)
            .collect();
        let mut found = inked(&one);
        found.sort_by_key(|&(x, y)| (y, x));
        assert_eq!(found, expected);
        // Each font pixel a 2 × 2 block.
        assert_eq!(inked(&two).len(), 4 * expected.len());
        assert!(inked(&two).iter().all(|&(x, y)| glyph[(y / 2) as usize] >> (x / 2) & 1 == 1));
    }

    #[test]
    fn text_past_the_edges_is_clipped_and_unknown_characters_read_as_a_question_mark() {
        let mut img = RgbImage::from_pixel(12, 6, Rgb([255, 255, 255]));
        // Starts left of and above the image, runs past its right edge.
        draw(&mut img, -3, -2, 1, "µ€x", INK);
        assert!(!inked(&img).is_empty());
        let mut q = RgbImage::from_pixel(8, 8, Rgb([255, 255, 255]));
        draw(&mut q, 0, 0, 1, "€", INK);
        let mut mark = RgbImage::from_pixel(8, 8, Rgb([255, 255, 255]));
        draw(&mut mark, 0, 0, 1, "?", INK);
        assert_eq!(q, mark);
        assert_eq!(width("µm", 2), 32);
    }
}
