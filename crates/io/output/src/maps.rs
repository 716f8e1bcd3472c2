//! The heatmaps of one target, by what they show: its thickness, its impacts per cm², its wear
//! and coating, its sag risk and its failures. A grid target is drawn cell for cell; a mesh
//! target is drawn as a flat projection along its mean normal. Impact and wear maps are
//! coloured up to their 99th percentile, so that a few outlying cells do not darken the rest,
//! and say so under the map with the largest value. A horizontal target says which of its edges
//! faces the nearest other target (the wall a collector catches the rebound of).

use crate::heatmap::{self, Edge, Grid, Scale};
use glam::DVec3;
use image::RgbImage;
use spraysim_engine::deposit::{DepositSurface, Layout, MapAxis};
use spraysim_engine::world::{ErosionMaps, Target};
use spraysim_scenario::Scenario;

/// Share of the cells below the top of a robust colour scale.
const ROBUST_QUANTILE: f64 = 0.99;

/// Pixels along the longer side of a mesh target's projection.
const PROJECTION_SIDE: usize = 512;

/// A target's normal within this angle of vertical (degrees) makes it horizontal: a floor or
/// a ceiling, whose map says which edge faces the nearest other target.
const HORIZONTAL_WITHIN: f64 = 30.0;

/// The heatmaps of `t` (`all`: every target of the run), by what they show; a map with nothing
/// to show (no deposit, no wear, nothing at risk) is not drawn. `thickness` is per cell, NaN
/// where the surface is cut away.
pub(crate) fn target_maps(
    t: &Target,
    all: &[Target],
    sc: &Scenario,
    thickness: &[f64],
) -> Vec<(&'static str, RgbImage)> {
    match t.surface.layout() {
        Layout::Grid { rows, cols, axes, .. } => {
            let note = facing_note(t, all, rows, cols);
            let edge_note = note.as_ref().map(|(e, n)| (*e, n.as_str()));
            let draw = |values: &[f64], marks: Option<&[u8]>, title: &str, scale: &Scale, top: f64| {
                let grid = Grid { values, cols, rows, marks, axes: Some(&axes), edge_note };
                heatmap::render_range(&grid, title, scale, sc.output().colormap, top)
            };
            maps_of(t, sc, thickness, &draw)
        }
        Layout::Cells { .. } => {
            let Some(projection) = Projection::of(t) else { return Vec::new() };
            let axes = projection.axes();
            let draw = |values: &[f64], marks: Option<&[u8]>, title: &str, scale: &Scale, top: f64| {
                let values = projection.pixels(values);
                let marks = marks.map(|m| projection.marks(m));
                let grid = Grid {
                    values: &values,
                    cols: projection.cols,
                    rows: projection.rows,
                    marks: marks.as_deref(),
                    axes: Some(&axes),
                    edge_note: None,
                };
                let title = format!("{title} (projected along the mean normal)");
                heatmap::render_range(&grid, &title, scale, sc.output().colormap, top)
            };
            maps_of(t, sc, thickness, &draw)
        }
    }
}

/// Draws a map: its values per cell, marks per cell, title, scale and top (in the values' unit).
type Draw<'a> = dyn Fn(&[f64], Option<&[u8]>, &str, &Scale, f64) -> RgbImage + 'a;

/// Every map of `t`, drawn by `draw`.
fn maps_of(t: &Target, sc: &Scenario, thickness: &[f64], draw: &Draw<'_>) -> Vec<(&'static str, RgbImage)> {
    let max = thickness.iter().copied().filter(|v| v.is_finite()).fold(0.0, f64::max);
    let scale = Scale::thickness(max);
    let mut out = Vec::new();
    if max > 0.0 {
        let title = match sc.process().volume_solids {
            Some(_) => format!("{}: wet film", t.name),
            None => format!("{}: thickness", t.name),
        };
        out.push(("thickness", draw(thickness, None, &title, &scale, max)));
        if let Some(solids) = sc.process().volume_solids {
            // The dry film: the wet film times the paint's volume solids, in µm.
            let dry: Vec<f64> = thickness.iter().map(|x| x * solids).collect();
            let scale = Scale { label: "dry film [\u{b5}m]".into(), factor: 1e6, footnote: None };
            let title = format!("{}: dry film ({:.0} % solids by volume)", t.name, solids * 100.0);
            out.push(("dry_thickness", draw(&dry, None, &title, &scale, max * solids)));
        }
    }
    // Impacts per cm², the map a blasting jet leaves.
    let hits: Vec<f64> = (0..thickness.len())
        .map(|c| {
            let area = t.surface.cell_area(c as u32);
            if area > 0.0 { f64::from(t.surface.hits()[c]) / (area * 1e4) } else { f64::NAN }
        })
        .collect();
    let (top, scale_hits) = robust(&hits, Scale::count("impacts [1/cm²]"), "");
    out.push(("hits", draw(&hits, None, &format!("{}: impacts", t.name), &scale_hits, top)));
    if let Some(e) = &t.erosion {
        out.extend(erosion_maps(t, e, thickness, draw));
    }
    let process = sc.process();
    if max > 0.0 && process.sag_threshold > 0.0 {
        let risk = t.sag_risk(process.sag_threshold);
        if risk.iter().any(|&r| r > 0) {
            let title = format!("{}: sag risk (orange)", t.name);
            out.push(("sag", draw(thickness, Some(&risk), &title, &scale, max)));
        }
    }
    if max > 0.0 && process.cohesion.interval > 0.0 && t.failure_mask.iter().any(|&m| m > 0) {
        let title = format!("{}: failed (red), at risk (orange)", t.name);
        out.push(("failure", draw(thickness, Some(&t.failure_mask), &title, &scale, max)));
    }
    out
}

/// The top of a robust colour scale for `values` (their 99th percentile above 0) and `scale`
/// with a footnote saying so and giving the largest value, when that lies above the top;
/// `unit` follows the values in the footnote.
fn robust(values: &[f64], mut scale: Scale, unit: &str) -> (f64, Scale) {
    let largest = values.iter().copied().filter(|v| v.is_finite()).fold(0.0, f64::max);
    let top = heatmap::quantile_of_positive(values, ROBUST_QUANTILE);
    if top > 0.0 && largest > top {
        let shown = heatmap::ticks(0.0, largest * scale.factor, 50);
        let step = shown.get(1).map_or(0.0, |t| t.0);
        let digits = if step > 0.0 { (-(step.log10().floor())).max(0.0) as usize } else { 0 };
        scale.footnote = Some(format!(
            "colours up to the 99th percentile, {:.digits$}{unit}; largest {:.digits$}{unit}",
            top * scale.factor,
            largest * scale.factor,
        ));
        (top, scale)
    } else {
        (largest, scale)
    }
}

/// The substrate's wear and the coating left, where there is something to show, on the cells
/// of `thickness` (NaN where cut away).
fn erosion_maps(
    t: &Target,
    e: &ErosionMaps,
    thickness: &[f64],
    draw: &Draw<'_>,
) -> Vec<(&'static str, RgbImage)> {
    let mut out = Vec::new();
    let cut = |v: &[f64]| -> Vec<f64> {
        v.iter().zip(thickness).map(|(&x, &t)| if t.is_nan() { f64::NAN } else { x }).collect()
    };
    let deepest = e.substrate.iter().copied().fold(0.0, f64::max);
    if deepest > 0.0 {
        let values = cut(&e.substrate);
        let mut scale = Scale::thickness(heatmap::quantile_of_positive(&values, ROBUST_QUANTILE));
        scale.label = scale.label.replace("thickness", "substrate worn");
        let unit = if scale.factor == 1e3 { " mm" } else { " µm" };
        let (top, scale) = robust(&values, scale, unit);
        out.push(("erosion", draw(&values, None, &format!("{}: substrate wear", t.name), &scale, top)));
    }
    if e.initial_coating > 0.0 {
        let mut scale = Scale::thickness(e.initial_coating);
        scale.label = scale.label.replace("thickness", "coating left");
        let values = cut(&e.coating);
        out.push((
            "coating",
            draw(&values, None, &format!("{}: coating left", t.name), &scale, e.initial_coating),
        ));
    }
    out
}

/// For a horizontal grid target of `rows × cols` cells, the edge of its map nearest to the
/// centre of the nearest other target, and a note naming that target; `None` for a target that
/// is not horizontal or alone.
fn facing_note(t: &Target, all: &[Target], rows: usize, cols: usize) -> Option<(Edge, String)> {
    let s = &t.surface;
    let cell = |r: usize, c: usize| (r * cols + c) as u32;
    let centre = s.point_above(cell(rows / 2, cols / 2), 0.0);
    if s.normal(cell(rows / 2, cols / 2)).z.abs() < HORIZONTAL_WITHIN.to_radians().cos() {
        return None;
    }
    let other = all
        .iter()
        .filter(|o| o.name != t.name)
        .map(|o| (o, surface_centre(&o.surface)))
        .min_by(|a, b| a.1.distance(centre).total_cmp(&b.1.distance(centre)))?;
    let edges = [
        (Edge::Left, s.point_above(cell(rows / 2, 0), 0.0)),
        (Edge::Right, s.point_above(cell(rows / 2, cols - 1), 0.0)),
        (Edge::Bottom, s.point_above(cell(0, cols / 2), 0.0)),
        (Edge::Top, s.point_above(cell(rows - 1, cols / 2), 0.0)),
    ];
    let (edge, _) =
        edges.into_iter().min_by(|a, b| a.1.distance(other.1).total_cmp(&b.1.distance(other.1)))?;
    let arrow = match edge {
        Edge::Left => "\u{2190}",
        Edge::Right => "\u{2192}",
        Edge::Bottom => "\u{2193}",
        Edge::Top => "\u{2191}",
    };
    Some((edge, format!("{arrow} {}", other.0.name)))
}

/// The area-weighted mean of a surface's cell centres, m.
fn surface_centre(s: &impl DepositSurface) -> DVec3 {
    let (mut sum, mut area) = (DVec3::ZERO, 0.0);
    for c in 0..s.thickness().len() as u32 {
        let a = s.cell_area(c);
        sum += s.point_above(c, 0.0) * a;
        area += a;
    }
    if area > 0.0 { sum / area } else { DVec3::ZERO }
}

/// A mesh target seen along its area-weighted mean normal: which triangle (cell) lies in front
/// at each pixel of a `cols × rows` grid over its extent.
struct Projection {
    cols: usize,
    rows: usize,
    /// Per pixel, row-major from the bottom row, the cell seen there.
    cell: Vec<Option<u32>>,
    /// The grid's extent along its two in-plane axes, m: (from, to) across and up.
    across: (f64, f64),
    up: (f64, f64),
}

impl Projection {
    /// The projection of `t`'s triangles, or `None` for a target with no area.
    fn of(t: &Target) -> Option<Projection> {
        let mesh = t.surface.mesh(false, usize::MAX);
        let normal: DVec3 = mesh
            .triangles
            .iter()
            .map(|tri| {
                let [a, b, c] = tri.map(|i| mesh.positions[i as usize]);
                (b - a).cross(c - a)
            })
            .sum::<DVec3>()
            .try_normalize()?;
        // In-plane axes: `up` as near the world's z as the normal allows.
        let seed = if normal.z.abs() < 0.9 { DVec3::Z } else { DVec3::Y };
        let up = (seed - normal * seed.dot(normal)).normalize();
        let across = up.cross(normal);
        let flat = |p: DVec3| (p.dot(across), p.dot(up), p.dot(normal));
        let points: Vec<(f64, f64, f64)> = mesh.positions.iter().map(|&p| flat(p)).collect();
        let (mut lo, mut hi) = ((f64::INFINITY, f64::INFINITY), (f64::NEG_INFINITY, f64::NEG_INFINITY));
        for p in &points {
            lo = (lo.0.min(p.0), lo.1.min(p.1));
            hi = (hi.0.max(p.0), hi.1.max(p.1));
        }
        let (wide, tall) = (hi.0 - lo.0, hi.1 - lo.1);
        if !(wide > 0.0 || tall > 0.0) || !wide.is_finite() || !tall.is_finite() {
            return None;
        }
        let pixel = wide.max(tall) / PROJECTION_SIDE as f64;
        let (cols, rows) = (((wide / pixel).ceil() as usize).max(1), ((tall / pixel).ceil() as usize).max(1));
        let mut cell = vec![None; cols * rows];
        let mut depth = vec![f64::NEG_INFINITY; cols * rows];
        for (tri, &c) in mesh.triangles.iter().zip(&mesh.cell) {
            let [a, b, d] = tri.map(|i| points[i as usize]);
            let to_px = |p: (f64, f64, f64)| ((p.0 - lo.0) / pixel, (p.1 - lo.1) / pixel, p.2);
            let (a, b, d) = (to_px(a), to_px(b), to_px(d));
            let area = (b.0 - a.0) * (d.1 - a.1) - (d.0 - a.0) * (b.1 - a.1);
            if area.abs() < 1e-12 {
                continue;
            }
            let (x0, x1) =
                (a.0.min(b.0).min(d.0).floor().max(0.0) as usize, a.0.max(b.0).max(d.0).ceil() as usize);
            let (y0, y1) =
                (a.1.min(b.1).min(d.1).floor().max(0.0) as usize, a.1.max(b.1).max(d.1).ceil() as usize);
            for y in y0..y1.min(rows) {
                for x in x0..x1.min(cols) {
                    let (px, py) = (x as f64 + 0.5, y as f64 + 0.5);
                    // Barycentric weights of the pixel's centre.
                    let w1 = ((b.0 - px) * (d.1 - py) - (d.0 - px) * (b.1 - py)) / area;
                    let w2 = ((d.0 - px) * (a.1 - py) - (a.0 - px) * (d.1 - py)) / area;
                    let w3 = 1.0 - w1 - w2;
                    if w1 < 0.0 || w2 < 0.0 || w3 < 0.0 {
                        continue;
                    }
                    // The nearest to a viewer on the normal's side is seen.
                    let z = w1 * a.2 + w2 * b.2 + w3 * d.2;
                    let k = y * cols + x;
                    if z > depth[k] {
                        depth[k] = z;
                        cell[k] = Some(c);
                    }
                }
            }
        }
        Some(Projection { cols, rows, cell, across: (lo.0, hi.0), up: (lo.1, hi.1) })
    }

    /// Per-cell `values` as the projection's pixels (NaN where no triangle is seen).
    fn pixels(&self, values: &[f64]) -> Vec<f64> {
        self.cell
            .iter()
            .map(|c| c.and_then(|c| values.get(c as usize).copied()).unwrap_or(f64::NAN))
            .collect()
    }

    /// Per-cell `marks` as the projection's pixels (0 where no triangle is seen).
    fn marks(&self, marks: &[u8]) -> Vec<u8> {
        self.cell.iter().map(|c| c.and_then(|c| marks.get(c as usize).copied()).unwrap_or(0)).collect()
    }

    /// The projection's axes, in metres along the in-plane directions.
    fn axes(&self) -> [MapAxis; 2] {
        [
            MapAxis { label: "across [m]", from: self.across.0, to: self.across.1 },
            MapAxis { label: "up [m]", from: self.up.0, to: self.up.1 },
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The repository's examples folder.
    const EXAMPLES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../examples");

    #[test]
    fn the_default_floor_map_names_the_wall_along_the_edge_that_faces_it() {
        let sim = Scenario::default_scene().build().expect("the default scene builds");
        let all = sim.targets();
        let floor = all.iter().find(|t| t.name == "floor").expect("a floor");
        let wall = all.iter().find(|t| t.name == "wall").expect("a wall");
        let Layout::Grid { rows, cols, .. } = floor.surface.layout() else { panic!("a grid floor") };
        // The floor's rows run towards the wall (its `up` is +x, the wall at x = 0): its last
        // row's edge, drawn at the top, faces the wall.
        let note = facing_note(floor, all, rows, cols);
        assert_eq!(note, Some((Edge::Top, "\u{2191} wall".to_string())));
        // The wall stands upright: it gets no note.
        let Layout::Grid { rows, cols, .. } = wall.surface.layout() else { panic!("a grid wall") };
        assert_eq!(facing_note(wall, all, rows, cols), None);
    }

    #[test]
    fn impacts_are_coloured_to_their_99th_percentile_and_the_largest_is_stated() {
        // 1000 cells at 1 to 10 impacts per cm², one outlier at 500.
        let mut hits: Vec<f64> = (0..1000).map(|k| 1.0 + f64::from(k % 10)).collect();
        hits.push(500.0);
        hits.push(f64::NAN);
        let (top, scale) = robust(&hits, Scale::count("impacts [1/cm²]"), "");
        assert_eq!(top, 10.0);
        let note = scale.footnote.expect("a footnote");
        assert!(note.contains("99th percentile, 10") && note.contains("largest 500"), "{note}");
        // Without outliers the scale tops at the largest value and says nothing.
        let (top, scale) = robust(&[1.0, 2.0, 3.0], Scale::count("impacts [1/cm²]"), "");
        assert_eq!((top, scale.footnote), (3.0, None));
    }

    #[test]
    fn a_mesh_target_is_drawn_as_a_projection_in_which_its_coat_shows() {
        let sc = Scenario::from_path(std::path::Path::new(&format!("{EXAMPLES}/door_panel.toml")))
            .expect("the door panel example")
            .with_all(&[("simulation.duration".into(), 1.0.into())])
            .expect("a shorter run");
        let mut sim = sc.build().expect("builds");
        sim.run(|_| {});
        let door = &sim.targets()[0];
        let thickness: Vec<f64> = door.surface.thickness().to_vec();
        let maps = target_maps(door, sim.targets(), &sc, &thickness);
        let names: Vec<&str> = maps.iter().map(|m| m.0).collect();
        assert!(names.contains(&"thickness") && names.contains(&"hits"), "{names:?}");
        let (_, img) = maps.iter().find(|m| m.0 == "thickness").expect("a thickness map");
        // The projection fills much of its 512 px side with the panel, coated or bare.
        let colour = img.pixels().filter(|p| p.0[0] != p.0[1] || p.0[1] != p.0[2]).count();
        assert!(colour > 512 * 100, "{colour} coloured pixels");
        let projection = Projection::of(door).expect("a projection");
        assert_eq!(projection.cols.max(projection.rows), PROJECTION_SIDE);
        let seen = projection.cell.iter().filter(|c| c.is_some()).count();
        assert!(seen * 2 > projection.cols * projection.rows / 2, "{seen} pixels show the panel");
    }
}
