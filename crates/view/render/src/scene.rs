//! What a view shows, built on the CPU from a running simulation: triangles (targets with their
//! deposit, obstacles, the nozzle), lines (spray axis and cone, the nozzle's path) and points
//! (particles), each vertex with its colour. Plain data: the GPU side only uploads it.

use crate::shapes;
use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use spraysim::Simulation;
use spraysim::collision::{Primitive, Shape};
use spraysim::deposit::DepositSurface;
use spraysim::output::heatmap;
use spraysim::particles::flags;
use spraysim::scenario::{Colormap, ParticleColoring, RenderParams, Scenario};
use spraysim::world::Target;
use std::borrow::Cow;

/// Background of every view (RGBA).
pub const BACKGROUND: [u8; 4] = [244, 245, 247, 255];
/// A target's surface where nothing lies on it.
pub const BARE: [u8; 4] = [196, 196, 190, 255];
/// Particles in flight from the nozzle, not yet rebounded.
pub const FLYING: [u8; 4] = [20, 80, 200, 255];
/// Particles that have rebounded from a substrate.
pub const REBOUNDED: [u8; 4] = [240, 120, 0, 255];
/// Material released by a cohesive failure (or a drip).
pub const RELEASED: [u8; 4] = [200, 0, 30, 255];
/// Rebar and other cylinders.
const STEEL: [u8; 4] = [112, 96, 84, 255];
/// Other obstacles.
const OBSTACLE: [u8; 4] = [150, 152, 160, 255];
/// The nozzle's body.
const NOZZLE: [u8; 4] = [45, 45, 50, 255];
/// The spray axis while spraying, and the spray cone.
const AXIS_ON: [u8; 4] = [220, 30, 30, 255];
const CONE: [u8; 4] = [240, 175, 175, 255];
/// The spray axis while the nozzle does not spray.
const AXIS_OFF: [u8; 4] = [120, 120, 120, 255];
/// The nozzle's path: travelled (grey), and still to come (green); lighter where the nozzle
/// does not spray.
const PATH_PAST: [u8; 4] = [95, 95, 100, 255];
const PATH_PAST_IDLE: [u8; 4] = [170, 170, 175, 255];
const PATH_PLANNED: [u8; 4] = [40, 160, 80, 255];
const PATH_PLANNED_IDLE: [u8; 4] = [150, 210, 165, 255];
/// Tints of at-risk and failed cells, blended over the colour as on the heatmaps.
const AT_RISK: [u8; 3] = [255, 150, 0];
const FAILED: [u8; 3] = [220, 0, 0];

/// A vertex of a lit triangle.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct MeshVertex {
    /// Position, m.
    pub position: [f32; 3],
    /// Unit normal.
    pub normal: [f32; 3],
    /// RGBA colour.
    pub color: [u8; 4],
}

/// A vertex of a line or a particle.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct ColorVertex {
    /// Position, m.
    pub position: [f32; 3],
    /// RGBA colour.
    pub color: [u8; 4],
}

impl ColorVertex {
    /// A vertex at `p` (m) in `color`.
    pub fn new(p: DVec3, color: [u8; 4]) -> Self {
        ColorVertex { position: p.as_vec3().to_array(), color }
    }
}

/// Indexed triangles.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// The corners the triangles index: position (m), normal and colour each.
    pub vertices: Vec<MeshVertex>,
    /// Triangles as vertex indices, three a triangle.
    pub indices: Vec<u32>,
}

impl Mesh {
    /// Adds a vertex at `p` (m) with normal `n`.
    pub fn push_vertex(&mut self, p: DVec3, n: DVec3, color: [u8; 4]) {
        let n = n.normalize_or(DVec3::Z);
        self.vertices.push(MeshVertex {
            position: p.as_vec3().to_array(),
            normal: n.as_vec3().to_array(),
            color,
        });
    }
}

/// What the targets' colours show.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Field {
    /// Erosion when some target has an erosion law (blasting), else thickness.
    #[default]
    Auto,
    /// Deposit thickness.
    Thickness,
    /// Depth eroded by abrasive impacts.
    Erosion,
    /// Coating left on the surface (bare where blasted clean).
    Coating,
}

/// What a view draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Show {
    /// Particles in flight.
    pub particles: bool,
    /// The obstacles (bars, boxes, meshes) in the particles' way.
    pub obstacles: bool,
    /// The deposit on the targets (else the bare targets).
    pub deposit: bool,
    /// The nozzle, its spray axis and cone.
    pub nozzle: bool,
    /// The nozzle's path.
    pub path: bool,
}

impl Default for Show {
    fn default() -> Self {
        Show { particles: true, obstacles: true, deposit: true, nozzle: true, path: true }
    }
}

/// How a scene is built.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneOptions {
    /// What is drawn.
    pub show: Show,
    /// What colours the particles.
    pub particles: ParticleColoring,
    /// Particle size, px.
    pub point_size: f32,
    /// Most particles drawn; more are drawn as an even sample (by particle id, so the same
    /// particles stay drawn from frame to frame).
    pub max_particles: usize,
    /// What the targets' colours show.
    pub field: Field,
    /// Colour scale of the targets (the heatmaps').
    pub colormap: Colormap,
    /// Factor on the thickness by which the deposit is raised off its surface (1: true scale).
    pub exaggeration: f64,
    /// Most cells per target mesh; finer fields are averaged down.
    pub max_cells: usize,
    /// Shade triangles by their angle to the eye (else flat colours, exactly the legend's).
    pub lighting: bool,
    /// Name shown in the caption.
    pub title: String,
}

impl Default for SceneOptions {
    fn default() -> Self {
        SceneOptions {
            show: Show::default(),
            particles: ParticleColoring::State,
            point_size: 3.0,
            max_particles: 2_000_000,
            field: Field::Auto,
            colormap: Colormap::Viridis,
            exaggeration: 1.0,
            max_cells: 256 * 256,
            lighting: true,
            title: String::new(),
        }
    }
}

impl SceneOptions {
    /// Options for a run of `scenario`: its colour map, its process's particle size and its
    /// name; with its `[output] render` settings when it has them.
    pub fn for_scenario(scenario: &Scenario) -> SceneOptions {
        let defaults = RenderParams::defaults(scenario.process().preset);
        let params = scenario.output().render.as_ref().unwrap_or(&defaults);
        SceneOptions {
            colormap: scenario.output().colormap,
            title: scenario_name(scenario),
            ..SceneOptions::default()
        }
        .with_render(params)
    }

    /// These options with the particle and deposit settings of `params`.
    pub fn with_render(self, params: &RenderParams) -> SceneOptions {
        SceneOptions {
            particles: params.color_by,
            point_size: params.point_size as f32,
            max_particles: params.max_particles.min(usize::MAX as u64) as usize,
            exaggeration: params.exaggeration,
            ..self
        }
    }
}

/// A scenario's name for captions: its file's stem, or what it was called.
pub fn scenario_name(scenario: &Scenario) -> String {
    let origin = scenario.origin();
    std::path::Path::new(origin)
        .file_stem()
        .map_or_else(|| origin.to_string(), |s| s.to_string_lossy().into_owned())
        .trim_matches(|c| c == '<' || c == '>')
        .to_string()
}

/// The colour scale of the targets.
#[derive(Clone, Debug, PartialEq)]
pub struct Legend {
    /// Quantity and unit, e.g. `thickness [mm]`.
    pub label: String,
    /// Colour map.
    pub colormap: Colormap,
    /// Value at the top of the scale, in the label's unit.
    pub max: f64,
}

/// What frames a view: the bounds of what matters and the directions presets are taken from.
#[derive(Clone, Debug, PartialEq)]
pub struct Framing {
    /// Lower corner of the targets, the bounded obstacles and the nozzle's path, m.
    pub min: DVec3,
    /// Upper corner, m.
    pub max: DVec3,
    /// Points whose hull is what a preset must show, m: the targets' outlines, the bounded
    /// obstacles' box corners and the nozzle's path (a sample of it, for long paths).
    pub points: Vec<DVec3>,
    /// Unit normal of the first target, towards the side sprayed from (the front view's eye
    /// is on that side).
    pub front: DVec3,
    /// Nozzle position now, m.
    pub nozzle: DVec3,
    /// Unit spray axis now.
    pub axis: DVec3,
    /// Distance from the nozzle to the first surface along its axis, m.
    pub aim: f64,
}

/// Facts about the view for its caption.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Caption {
    /// First line of the caption: the scenario's name.
    pub title: String,
    /// Simulated time, s.
    pub time: f64,
    /// Particles in flight.
    pub in_flight: usize,
    /// Particles drawn (fewer than in flight when sampled).
    pub drawn: usize,
}

/// Everything one view draws.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Lit triangles: targets, obstacles, nozzle.
    pub mesh: Mesh,
    /// Line segments, two vertices each: spray axis and cone, path, custom shapes' boxes.
    pub lines: Vec<ColorVertex>,
    /// The particles drawn, one point each at its position (m), coloured by the particle legend.
    pub points: Vec<ColorVertex>,
    /// Particle size, px.
    pub point_size: f32,
    /// Whether triangles are shaded.
    pub lighting: bool,
    /// Bounds and directions for cameras.
    pub framing: Framing,
    /// Colour scale of the targets, when anything is coloured.
    pub legend: Option<Legend>,
    /// What colours the particles, and for speeds the top of the scale (m/s).
    pub particle_legend: (ParticleColoring, f64),
    /// Facts for the caption.
    pub caption: Caption,
}

impl Scene {
    /// The view of `sim` now.
    pub fn build(sim: &Simulation, opts: &SceneOptions) -> Scene {
        let mut mesh = Mesh::default();
        let mut lines = Vec::new();
        let legend = add_targets(&mut mesh, sim, opts);
        let framing = framing(sim);
        if opts.show.obstacles {
            let extent = (framing.max - framing.min).length().max(1.0);
            for o in &sim.config().obstacles {
                for s in &o.shapes {
                    let color = if matches!(s, Shape::Cylinder(_)) { STEEL } else { OBSTACLE };
                    shapes::add_shape(
                        &mut mesh,
                        &mut lines,
                        s,
                        color,
                        ((framing.min + framing.max) / 2.0, extent),
                    );
                }
            }
        }
        if opts.show.path {
            add_path(&mut lines, sim);
        }
        if opts.show.nozzle {
            add_nozzle(&mut mesh, &mut lines, sim, &framing);
        }
        let vmax = sim.config().emitter.speed[1].max(1e-9);
        let (points, in_flight) = particles(sim, opts, vmax);
        let caption = Caption { title: opts.title.clone(), time: sim.time(), in_flight, drawn: points.len() };
        Scene {
            mesh,
            lines,
            points,
            point_size: opts.point_size,
            lighting: opts.lighting,
            framing,
            legend,
            particle_legend: (opts.particles, vmax),
            caption,
        }
    }
}

/// The values a target's colours show, per cell, if it has them.
fn field_values(t: &Target, field: Field) -> Option<Cow<'_, [f64]>> {
    match field {
        Field::Thickness | Field::Auto => Some(Cow::Borrowed(t.surface.thickness())),
        // Coating and substrate together.
        Field::Erosion => {
            t.erosion.as_ref().map(|e| Cow::Owned((0..e.coating.len()).map(|c| e.eroded(c)).collect()))
        }
        Field::Coating => t.erosion.as_ref().map(|e| Cow::Borrowed(e.coating.as_slice())),
    }
}

/// Adds every target with its deposit; returns the colour scale used.
fn add_targets(mesh: &mut Mesh, sim: &Simulation, opts: &SceneOptions) -> Option<Legend> {
    let field = match opts.field {
        Field::Auto if sim.targets().iter().any(|t| t.erosion.is_some()) => Field::Erosion,
        Field::Auto => Field::Thickness,
        f => f,
    };
    let max = sim
        .targets()
        .iter()
        .filter_map(|t| match field {
            Field::Coating => t.erosion.as_ref().map(|e| e.initial_coating),
            _ => field_values(t, field).map(|v| v.iter().copied().fold(0.0, f64::max)),
        })
        .fold(0.0, f64::max);
    let scale = heatmap::Scale::thickness(max);
    let word = match field {
        Field::Erosion => "eroded",
        Field::Coating => "coating",
        _ => "thickness",
    };
    for t in sim.targets() {
        add_target(mesh, t, field, max, opts);
    }
    (opts.show.deposit && max > 0.0).then(|| Legend {
        label: scale.label.replace("thickness", word),
        colormap: opts.colormap,
        max: max * scale.factor,
    })
}

/// Adds one target: its surface raised by its deposit, coloured by `field` on a scale from 0
/// to `max`.
fn add_target(mesh: &mut Mesh, t: &Target, field: Field, max: f64, opts: &SceneOptions) {
    let m = t.surface.mesh(false, opts.max_cells);
    let n = m.positions.len();
    // Per vertex: the mean value of the cells around it and the worst failure mark.
    let values = field_values(t, field);
    let (mut sum, mut count, mut mark) = (vec![0.0; n], vec![0u32; n], vec![0u8; n]);
    for (tri, &cell) in m.triangles.iter().zip(&m.cell) {
        for &v in tri {
            let v = v as usize;
            sum[v] += values.as_ref().map_or(0.0, |x| x[cell as usize]);
            count[v] += 1;
            mark[v] = mark[v].max(t.failure_mask.get(cell as usize).copied().unwrap_or(0));
        }
    }
    let lift = if opts.show.deposit { opts.exaggeration } else { 0.0 };
    let positions: Vec<DVec3> =
        (0..n).map(|v| m.positions[v] + m.normals[v] * m.thickness[v] * lift).collect();
    let normals = smooth_normals(&positions, &m.triangles, &m.normals);
    let base = mesh.vertices.len() as u32;
    for v in 0..n {
        let value = match field {
            Field::Thickness | Field::Auto => m.thickness[v],
            _ => sum[v] / f64::from(count[v].max(1)),
        };
        let mut color = BARE;
        if opts.show.deposit && max > 0.0 && values.is_some() && (value > 0.0 || field == Field::Coating) {
            let c = heatmap::color(opts.colormap, value / max).0;
            color = [c[0], c[1], c[2], 255];
        }
        // Failed cells may have lost their layer: they are tinted whatever their colour.
        if opts.show.deposit && mark[v] > 0 {
            let tint = if mark[v] == 1 { AT_RISK } else { FAILED };
            for (c, t) in color.iter_mut().zip(tint) {
                *c = ((u16::from(*c) + 3 * u16::from(t)) / 4) as u8;
            }
        }
        mesh.push_vertex(positions[v], normals[v], color);
    }
    mesh.indices.extend(m.triangles.iter().flat_map(|tri| tri.map(|v| base + v)));
}

/// Vertex normals of a triangle mesh (area-weighted face normals), each on the side of the
/// given `bare` normal.
fn smooth_normals(positions: &[DVec3], triangles: &[[u32; 3]], bare: &[DVec3]) -> Vec<DVec3> {
    let mut acc = vec![DVec3::ZERO; positions.len()];
    for tri in triangles {
        let [a, b, c] = tri.map(|v| positions[v as usize]);
        let face = (b - a).cross(c - a);
        for &v in tri {
            acc[v as usize] += face;
        }
    }
    acc.iter()
        .zip(bare)
        .map(|(&n, &b)| {
            let n = n.normalize_or(b);
            if n.dot(b) < 0.0 { -n } else { n }
        })
        .collect()
}

/// Bounds of the targets, bounded obstacles and nozzle path, and the directions views take.
fn framing(sim: &Simulation) -> Framing {
    let mut points = Vec::new();
    for t in sim.targets() {
        // A coarse mesh is enough: its outline is the surface's.
        points.extend(t.surface.mesh(false, 256).positions);
    }
    for o in &sim.config().obstacles {
        for s in &o.shapes {
            if let Some(b) = s.aabb() {
                let c = |i: usize, lo: f64, hi: f64| if i == 0 { lo } else { hi };
                for i in 0..8 {
                    points.push(DVec3::new(
                        c(i & 1, b.min.x, b.max.x),
                        c(i & 2, b.min.y, b.max.y),
                        c(i & 4, b.min.z, b.max.z),
                    ));
                }
            }
        }
    }
    let w = sim.nozzle().waypoints();
    points.extend(w.iter().step_by(w.len().div_ceil(500).max(1)).map(|w| w.position));
    points.extend(w.last().map(|w| w.position));
    let (mut min, mut max) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for &p in &points {
        min = min.min(p);
        max = max.max(p);
    }
    if !(min.is_finite() && max.is_finite()) {
        (min, max) = (sim.config().domain.min, sim.config().domain.max);
        points = vec![min, max];
    }
    let (frame, _) = sim.nozzle().at(sim.time());
    let front = sim
        .targets()
        .iter()
        .find_map(|t| {
            t.surface.uniform_normal().or_else(|| {
                let m = t.surface.mesh(false, 64);
                m.normals.iter().copied().sum::<DVec3>().try_normalize()
            })
        })
        .unwrap_or(-frame.axis);
    let reach = (sim.config().domain.max - sim.config().domain.min).length();
    let aim = aim_distance(sim, frame.position, frame.axis, reach);
    Framing { min, max, points, front, nozzle: frame.position, axis: frame.axis, aim }
}

/// Distance from `p` along `axis` to the first target or obstacle within `reach` (m), or half
/// of `reach` when nothing is there.
fn aim_distance(sim: &Simulation, p: DVec3, axis: DVec3, reach: f64) -> f64 {
    let end = p + axis * reach;
    let targets = sim.targets().iter().filter_map(|t| t.surface.intersect(p, end));
    let obstacles =
        sim.config().obstacles.iter().flat_map(|o| o.shapes.iter().filter_map(|s| s.intersect(p, end)));
    targets
        .chain(obstacles)
        .map(|h| h.t * reach)
        .filter(|&d| d > 1e-6)
        .fold(None, |best: Option<f64>, d| Some(best.map_or(d, |b| b.min(d))))
        .unwrap_or(0.5 * reach)
}

/// The nozzle's body, its spray axis to the first surface and, while spraying, its cone.
fn add_nozzle(mesh: &mut Mesh, lines: &mut Vec<ColorVertex>, sim: &Simulation, framing: &Framing) {
    let (frame, spraying) = sim.nozzle().at(sim.time());
    let (p, axis) = (frame.position, frame.axis);
    let body = spraysim::collision::Cylinder { a: p - axis * 0.15, b: p, radius: 0.02 };
    shapes::add_cylinder(mesh, &body, NOZZLE);
    let hit = p + axis * framing.aim;
    lines.push(ColorVertex::new(p, if spraying { AXIS_ON } else { AXIS_OFF }));
    lines.push(ColorVertex::new(hit, if spraying { AXIS_ON } else { AXIS_OFF }));
    if spraying {
        let half = sim.config().emitter.cone_half_angle.min(1.4);
        let r = framing.aim * half.tan();
        let (u, v) = (frame.width_axis, frame.height_axis);
        for k in 0..8 {
            let a = std::f64::consts::TAU * f64::from(k) / 8.0;
            lines.push(ColorVertex::new(p, CONE));
            lines.push(ColorVertex::new(hit + (u * a.cos() + v * a.sin()) * r, CONE));
        }
    }
}

/// The nozzle's path through its waypoints: travelled and still to come, lighter where it
/// does not spray.
fn add_path(lines: &mut Vec<ColorVertex>, sim: &Simulation) {
    let now = sim.time();
    let w = sim.nozzle().waypoints();
    for pair in w.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let (past, planned) =
            if a.spray { (PATH_PAST, PATH_PLANNED) } else { (PATH_PAST_IDLE, PATH_PLANNED_IDLE) };
        if b.time <= now {
            lines.extend([ColorVertex::new(a.position, past), ColorVertex::new(b.position, past)]);
        } else if a.time >= now {
            lines.extend([ColorVertex::new(a.position, planned), ColorVertex::new(b.position, planned)]);
        } else {
            let mid = a.position.lerp(b.position, (now - a.time) / (b.time - a.time));
            lines.extend([ColorVertex::new(a.position, past), ColorVertex::new(mid, past)]);
            lines.extend([ColorVertex::new(mid, planned), ColorVertex::new(b.position, planned)]);
        }
    }
}

/// Whether the particle with emission index `id` belongs to a sample of the share `keep`
/// (0..1): a hash of the id against the share, so a particle stays in or out for its life.
fn sampled(id: u32, keep: f64) -> bool {
    let mut z = u64::from(id).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    ((z >> 11) as f64 / (1u64 << 53) as f64) < keep
}

/// The particles in flight as points (a sample when there are more than the options allow),
/// and how many are in flight.
fn particles(sim: &Simulation, opts: &SceneOptions, vmax: f64) -> (Vec<ColorVertex>, usize) {
    let s = sim.swarm();
    let in_flight = s.alive();
    if !opts.show.particles || in_flight == 0 {
        return (Vec::new(), in_flight);
    }
    let keep = opts.max_particles as f64 / in_flight as f64;
    let speed_map = Colormap::Turbo;
    let mut out = Vec::with_capacity(in_flight.min(opts.max_particles));
    for (i, p) in s.particles.iter().enumerate() {
        let f = p.flags();
        if f & flags::ALIVE == 0 || (keep < 1.0 && !sampled(p.id, keep)) {
            continue;
        }
        let (position, velocity, _) = sim.particle_now(i);
        let color = match opts.particles {
            ParticleColoring::State if f & flags::RELEASED != 0 => RELEASED,
            ParticleColoring::State if f & flags::HIT_SUBSTRATE != 0 || p.impacts() > 0 => REBOUNDED,
            ParticleColoring::State => FLYING,
            ParticleColoring::Speed => {
                let c = heatmap::color(speed_map, velocity.length() / vmax).0;
                [c[0], c[1], c[2], 255]
            }
        };
        out.push(ColorVertex::new(position, color));
    }
    (out, in_flight)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sim(scenario: &Scenario, duration: f64) -> Simulation {
        let sc = scenario.with("simulation.duration", duration).expect("valid");
        let mut sim = sc.build().expect("builds");
        sim.run(|_| {});
        sim
    }

    #[test]
    fn failed_and_at_risk_cells_are_tinted_red_and_orange() {
        let sc = Scenario::default_scene().with("target[0].resolution", vec![64.0, 64.0]).expect("valid");
        let s = sim(&sc, 0.05);
        let mut wall = s.targets()[0].clone();
        let cells = wall.failure_mask.len();
        wall.failure_mask = (0..cells).map(|c| if c < cells / 2 { 2 } else { 1 }).collect();
        let mut mesh = Mesh::default();
        let opts = SceneOptions::default();
        add_target(&mut mesh, &wall, Field::Thickness, 1e-3, &opts);
        // Bare cells blended with the tints: reddish in the lower half, orange in the upper.
        let first = mesh.vertices[0].color;
        let last = mesh.vertices[mesh.vertices.len() - 1].color;
        assert!(first[0] > 200 && first[1] < 80, "{first:?}");
        assert!(last[0] > 200 && (100..180).contains(&last[1]), "{last:?}");
        let hidden = SceneOptions { show: Show { deposit: false, ..Show::default() }, ..opts };
        let mut bare = Mesh::default();
        add_target(&mut bare, &wall, Field::Thickness, 1e-3, &hidden);
        assert!(bare.vertices.iter().all(|v| v.color == BARE));
    }

    #[test]
    fn blasting_colours_the_erosion_and_says_so_in_the_legend() {
        let text = spraysim::scenario::DEFAULT_SCENE
            .replace("preset = \"shotcrete\"", "preset = \"blasting\"\n[process.erosion]\nmodel = \"oka\"")
            .replace("cone_angle = 18.0", "cone_angle = 15.0")
            .replace("resolution = [1024, 1024]", "resolution = [64, 64]\ncoating = 0.0001");
        let sc = Scenario::from_toml(&text, "blasting").expect("valid");
        let s = sim(&sc, 0.05);
        let scene = Scene::build(&s, &SceneOptions::default());
        let legend = scene.legend.expect("a legend");
        assert!(legend.label.starts_with("eroded ["), "{}", legend.label);
        let coating = Scene::build(&s, &SceneOptions { field: Field::Coating, ..SceneOptions::default() });
        assert!(coating.legend.expect("a legend").label.starts_with("coating ["));
    }

    #[test]
    fn a_sample_keeps_about_its_share_and_the_same_particles() {
        let kept = (0..100_000u32).filter(|&id| sampled(id, 0.25)).count();
        assert!((24_000..26_000).contains(&kept), "{kept}");
        assert!((0..1000u32).all(|id| sampled(id, 0.25) == sampled(id, 0.25)));
    }
}
