//! `shape = "rectangle"`: a flat face with a regular heightfield (a wall, a slab, a floor),
//! with openings cut out of it (`[[target.opening]]`).

use super::{Edges, RasterChart, SplatRadius, TargetGeometry, heightfield_storage, resolution, splat_radius};
use crate::budget::Storage;
use crate::params::v3;
use crate::reader::{Check, Read, Section, bad, choices, not_parallel};
use crate::sanity::EnclosingBox;
use glam::DVec3;
use serde::Serialize;
use spraysim_engine::collision::Face;
use spraysim_engine::deposit::{Opening, RectangleSurface, Surface};
use std::path::Path;

/// A rectangle with a regular heightfield, optionally with openings.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RectangleTarget {
    /// Centre, m.
    pub center: [f64; 3],
    /// Normal, towards the side that receives spray.
    pub normal: [f64; 3],
    /// A direction in the face (made perpendicular to `normal`); rows grow along it.
    pub up: [f64; 3],
    /// `[width, height]`, m; width along `up × normal`, height along `up`.
    pub size: [f64; 2],
    /// Heightfield cells `[cols, rows]`.
    pub resolution: [u32; 2],
    /// Radius over which each stuck particle's volume is spread, m (0: one cell), as the file
    /// gives it or derived from the particles expected per cell.
    pub splat_radius: SplatRadius,
    /// `"free"`: a slumping layer runs off over the edges; `"held"`: formwork (or a floor
    /// under a wall) holds it.
    pub edges: Edges,
    /// Openings cut out of the face (`[[target.opening]]`).
    #[serde(rename = "opening", skip_serializing_if = "Vec::is_empty")]
    pub openings: Vec<OpeningParams>,
}

impl TargetGeometry for RectangleTarget {
    fn read(s: &Section<'_>, _base: &Path) -> Read<Self> {
        let center = s.point("center", None)?;
        let normal = s.direction("normal", None)?;
        let up = s.direction("up", None)?;
        not_parallel(&s.key("up"), up, normal, "normal")?;
        let size = s.numbers("size", None, Check::Positive(1e3), "m")?;
        let resolution = resolution(s, [1024.0, 1024.0])?;
        let splat_radius = splat_radius(s, size, resolution)?;
        let edges = s.choice("edges", Some(Edges::Free))?;
        let openings =
            s.tables("opening")?.iter().map(|o| read_opening(o, size)).collect::<Read<Vec<_>>>()?;
        Ok(RectangleTarget { center, normal, up, size, resolution, splat_radius, edges, openings })
    }

    fn size(&self) -> [f64; 2] {
        self.size
    }

    fn surface(&self) -> Surface {
        let [cols, rows] = self.resolution.map(|r| r as usize);
        let rect = RectangleSurface::new(self.face(), cols, rows, self.splat_radius.radius)
            .with_held_edges(self.edges == Edges::Held)
            .with_openings(self.openings.iter().map(opening).collect());
        Surface::Rectangle(rect)
    }

    fn raster_chart(&self) -> Option<RasterChart> {
        Some(RasterChart::Face(self.face()))
    }

    fn reach(&self) -> (Vec<[f64; 3]>, f64) {
        (vec![self.center], self.size[0].hypot(self.size[1]) / 2.0)
    }

    fn enclosing_box(&self) -> EnclosingBox {
        let f = self.face();
        EnclosingBox {
            center: f.center,
            axes: [f.right, f.up, f.normal],
            half: [f.half_width, f.half_height, 0.0],
        }
    }

    fn splat_radius(&self) -> f64 {
        self.splat_radius.radius
    }

    fn cells(&self) -> u64 {
        u64::from(self.resolution[0]) * u64::from(self.resolution[1])
    }

    fn storage(&self) -> Storage {
        heightfield_storage(self.resolution)
    }

    /// Held and facing sideways or down (more than 45° from up).
    fn piles_at_held_foot(&self, gravity: DVec3) -> bool {
        self.edges == Edges::Held && -gravity.dot(v3(self.normal).normalize()) < 0.5f64.sqrt()
    }
}

impl RectangleTarget {
    /// The engine's face of the rectangle.
    fn face(&self) -> Face {
        Face::new(v3(self.center), v3(self.normal), v3(self.up), self.size)
    }
}

/// An opening cut out of a rectangle target, in the face's coordinates: m right of and up from
/// its centre.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "shape", rename_all = "snake_case")]
pub enum OpeningParams {
    /// A rectangle (a window, a door).
    Rectangle {
        /// Centre, `[right, up]` from the face's centre, m.
        center: [f64; 2],
        /// `[width, height]`, m.
        size: [f64; 2],
    },
    /// A polygon (a box-out), corners in order.
    Polygon {
        /// Corners, `[right, up]` from the face's centre, m.
        corners: Vec<[f64; 2]>,
    },
}

/// The shapes of an opening, by the word of its `shape` key.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum OpeningKind {
    Rectangle,
    Polygon,
}

choices!(OpeningKind { "rectangle" => OpeningKind::Rectangle, "polygon" => OpeningKind::Polygon });

/// Reads one `[[target.opening]]` of a face of `size` (m).
fn read_opening(s: &Section<'_>, size: [f64; 2]) -> Read<OpeningParams> {
    let o = match s.choice("shape", Some(OpeningKind::Rectangle))? {
        OpeningKind::Rectangle => OpeningParams::Rectangle {
            center: s.numbers("center", None, Check::Within(-1e3, 1e3), "m")?,
            size: s.numbers("size", None, Check::Positive(1e3), "m")?,
        },
        OpeningKind::Polygon => {
            let corners = s.pairs("corners", None, 1024)?;
            if corners.len() < 3 {
                return bad(&s.key("corners"), "must list at least 3 corners");
            }
            OpeningParams::Polygon { corners }
        }
    };
    let polygon = opening(&o);
    let is_rectangle = matches!(o, OpeningParams::Rectangle { .. });
    if polygon.area() <= 1e-12 {
        return bad(&s.key(if is_rectangle { "size" } else { "corners" }), "must enclose an area");
    }
    // Some of the opening must lie on the face: a corner on it, a face corner in it, or an
    // edge across it (a slot from side to side).
    let (hw, hh) = (size[0] / 2.0, size[1] / 2.0);
    let n = polygon.corners.len();
    let on_face = polygon.corners.iter().any(|&(u, v)| u.abs() < hw && v.abs() < hh)
        || [(-hw, -hh), (hw, -hh), (hw, hh), (-hw, hh)].iter().any(|&(u, v)| polygon.contains(u, v))
        || (0..n).any(|k| crosses_box(polygon.corners[k], polygon.corners[(k + 1) % n], hw, hh));
    if !on_face {
        return bad(
            &s.key(if is_rectangle { "center" } else { "corners" }),
            "puts the opening outside the face",
        );
    }
    s.finish("an opening")?;
    Ok(o)
}

/// True if the segment `a → b` passes through the open box |u| < `hw`, |v| < `hh`
/// (Liang–Barsky clipping).
fn crosses_box(a: (f64, f64), b: (f64, f64), hw: f64, hh: f64) -> bool {
    let (du, dv) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (p, q) in [(-du, a.0 + hw), (du, hw - a.0), (-dv, a.1 + hh), (dv, hh - a.1)] {
        if p == 0.0 {
            if q <= 0.0 {
                return false;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    t0 < t1
}

/// The engine's polygon of an opening.
pub fn opening(o: &OpeningParams) -> Opening {
    match o {
        OpeningParams::Rectangle { center, size } => {
            Opening::rectangle((center[0], center[1]), (size[0], size[1]))
        }
        OpeningParams::Polygon { corners } => {
            Opening { corners: corners.iter().map(|c| (c[0], c[1])).collect() }
        }
    }
}
