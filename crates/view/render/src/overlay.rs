//! Text and legends drawn over a rendered image: a caption (scenario, time, particles in
//! flight), the targets' colour scale and the particles' key, as on the heatmaps.

use crate::scene::{FLYING, REBOUNDED, RELEASED, Scene};
use image::{Rgba, RgbaImage};
use spraysim::output::heatmap;
use spraysim::output::text::{self, fill};
use spraysim::scenario::{Colormap, ParticleColoring};

const INK: Rgba<u8> = Rgba([20, 20, 20, 255]);

/// Lightens a rectangle behind text so that it reads over the scene.
fn veil(img: &mut RgbaImage, x: i64, y: i64, w: i64, h: i64) {
    for py in y.max(0)..(y + h).min(i64::from(img.height())) {
        for px in x.max(0)..(x + w).min(i64::from(img.width())) {
            let p = img.get_pixel_mut(px as u32, py as u32);
            for c in 0..3 {
                p.0[c] = ((u16::from(p.0[c]) + 3 * 250) / 4) as u8;
            }
        }
    }
}

fn rgba(c: image::Rgb<u8>) -> Rgba<u8> {
    Rgba([c.0[0], c.0[1], c.0[2], 255])
}

/// The caption's text: scenario, time, particles in flight (and drawn, when sampled).
pub fn caption(scene: &Scene) -> String {
    let c = &scene.caption;
    let mut line = format!("{}  t = {:.3} s  {} particles in flight", c.title, c.time, c.in_flight);
    if c.drawn < c.in_flight && scene.point_size > 0.0 && c.drawn > 0 {
        line.push_str(&format!(" (drawing a sample of {})", c.drawn));
    }
    line.trim().to_string()
}

/// Draws the caption, the targets' colour scale and the particles' key over `img`, a render
/// of `scene`.
pub fn annotate(img: &mut RgbaImage, scene: &Scene) {
    let s: i64 = if img.height() >= 600 { 2 } else { 1 };
    let m = 8 * s;
    let line = caption(scene);
    veil(img, 0, 0, (line.chars().count() as i64 * 8 + 2) * s + 2 * m, 8 * s + 2 * m);
    text::draw(img, m, m, s, &line, INK);
    if let Some(legend) = &scene.legend {
        colour_bar(img, s, &legend.label, legend.colormap, legend.max);
    }
    match scene.particle_legend {
        (ParticleColoring::State, _) => state_key(img, s),
        (ParticleColoring::Speed, vmax) => speed_bar(img, s, vmax),
    }
}

/// A vertical colour bar at the right edge, from 0 to `max`, with round ticks and its label above it.
fn colour_bar(img: &mut RgbaImage, s: i64, label: &str, map: Colormap, max: f64) {
    let (w, h) = (i64::from(img.width()), i64::from(img.height()));
    let ticks = heatmap::ticks(0.0, max, 5);
    let label_w = ticks.iter().map(|(_, l)| text::width(l, s)).max().unwrap_or(0);
    let bar_w = 12 * s;
    let box_w = (bar_w + 6 * s + label_w).max(text::width(label, s)) + 16 * s;
    let bar_h = (h * 2 / 5).max(40);
    let (x0, y0) = (w - box_w, 8 * s + 24 * s);
    veil(img, x0 - 4 * s, y0 - 14 * s, box_w + 4 * s, bar_h + 24 * s);
    text::draw(img, x0, y0 - 12 * s, s, label, INK);
    let bar_x = x0 + 4 * s;
    let bar_y = y0 + 4 * s;
    for y in 0..bar_h {
        let c = rgba(heatmap::color(map, 1.0 - y as f64 / (bar_h - 1) as f64));
        fill(img, bar_x, bar_y + y, bar_w, 1, c);
    }
    for (v, l) in &ticks {
        let f = if max > 0.0 { (v / max).clamp(0.0, 1.0) } else { 0.0 };
        let y = bar_y + (bar_h - 1) - ((bar_h - 1) as f64 * f).round() as i64;
        fill(img, bar_x, y, bar_w + 3 * s, s.max(1), INK);
        text::draw(img, bar_x + bar_w + 6 * s, (y - 4 * s).clamp(bar_y, bar_y + bar_h - 8 * s), s, l, INK);
    }
}

/// The particle colours by state, in the bottom-left corner.
fn state_key(img: &mut RgbaImage, s: i64) {
    let h = i64::from(img.height());
    let entries = [(FLYING, "in flight"), (REBOUNDED, "rebounded"), (RELEASED, "released")];
    let y = h - 8 * s - 12 * s;
    let width: i64 = entries.iter().map(|(_, t)| (t.len() as i64 * 8 + 24) * s).sum();
    veil(img, 0, y - 6 * s, width + 16 * s, 20 * s);
    let mut x = 8 * s;
    for (color, label) in entries {
        fill(img, x, y, 8 * s, 8 * s, Rgba(color));
        text::draw(img, x + 12 * s, y, s, label, INK);
        x += (label.len() as i64 * 8 + 24) * s;
    }
}

/// The speed scale of the particles, in the bottom-left corner.
fn speed_bar(img: &mut RgbaImage, s: i64, vmax: f64) {
    let h = i64::from(img.height());
    let bar_w = 160 * s;
    let y = h - 8 * s - 20 * s;
    veil(img, 0, y - 14 * s, bar_w + 80 * s, 34 * s);
    text::draw(img, 8 * s, y - 12 * s, s, "particle speed [m/s]", INK);
    for x in 0..bar_w {
        fill(
            img,
            8 * s + x,
            y,
            1,
            8 * s,
            rgba(heatmap::color(Colormap::Turbo, x as f64 / (bar_w - 1) as f64)),
        );
    }
    text::draw(img, 8 * s, y + 10 * s, s, "0", INK);
    let top = heatmap::tick_label(vmax, vmax);
    text::draw(img, 8 * s + bar_w - text::width(&top, s), y + 10 * s, s, &top, INK);
}
