//! The job of a call laid out as the kernel reads it (see `flight.wgsl`, whose layouts these
//! constants mirror): the parameters of an epoch, a member's words (its physics and where it
//! lies in a dispatch), its own table of words for the impact models, targets, shapes and
//! released volumes, the layers' thicknesses, and the particles.

use crate::bounds::{box_words, shapes_box};
use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use spraysim_engine::collision::{Face, Primitive, Shape};
use spraysim_engine::config::ErosionConfig;
use spraysim_engine::deposit::{Chart, CylinderSurface, DepositSurface, GridSurface, Surface, WEAR_QUANTUM};
use spraysim_engine::motion::Integrator;
use spraysim_engine::particles::{Particle, flags};
use spraysim_engine::pipeline::FlightJob;
use spraysim_engine::process::{ErosionForm, ImpactModel, ReboundForm};
use spraysim_engine::world::Role;

/// Words of one impact model.
pub const MODEL_WORDS: usize = 64;
/// Words of one target.
pub const TARGET_WORDS: usize = 32;
/// A target's kind (word 29) when it is a cylindrical shell (0: a rectangle).
const SHELL: u32 = 1;
/// Words of one obstacle shape: its kind, its obstacle, its geometry (words 2 to 15), then its
/// bounding box ([`crate::bounds::BOX_WORDS`]) from word 16.
pub const SHAPE_WORDS: usize = 24;
/// A member's counter words before its per-target slots: particle-steps, two spare words, then
/// 7 fates of 4 words.
pub const TALLY_WORDS: usize = 4 + 4 * 7;
/// Counter words per target (8 slots of 4) and per obstacle (3 slots of 4).
pub const TARGET_COUNTER_WORDS: usize = 32;
/// Counter words per obstacle.
pub const OBSTACLE_COUNTER_WORDS: usize = 12;
/// Invocations of one workgroup.
pub const WORKGROUP: u32 = 64;
/// Workgroups per dispatch row (the default limit per dimension is 65 535).
pub const ROW_GROUPS: u32 = 32_768;

/// The parameters of one epoch of a dispatch, for all its members (the WGSL `Params`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Params {
    /// First step, step after the last, particle slots of all members, invocations per
    /// dispatch row.
    pub steps: [u32; 4],
    /// Members, targets of all members, cells of all grids, whether any target erodes.
    pub sizes: [u32; 4],
}

/// Words of one member at the start of the scene's words (the WGSL `Member`).
pub const MEMBER_WORDS: usize = 32;
/// Words of each target in the table of all members' targets, after the members' words: its
/// first cell over all grids, a quantum's thickness on one of its cells (f32 bits), the counter
/// word of its band, a spare.
pub const TABLE_WORDS: usize = 4;
/// Counter words before the members' blocks: the cells listed, and three spare words.
pub const GLOBAL_COUNTER_WORDS: usize = 4;

/// Where a member lies in a dispatch.
#[derive(Clone, Copy, Debug, Default)]
pub struct Place {
    /// Offset of its own words (its models first) in the scene's words.
    pub words: u32,
    /// Its first particle slot.
    pub slot: u32,
    /// Its first target over all members.
    pub target: u32,
    /// Its first cell over all grids.
    pub cell: u32,
    /// Its first counter word.
    pub counters: u32,
}

/// One particle slot as the kernel keeps it: 36 bytes.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct GpuParticle {
    /// Position, m.
    pub x: [f32; 3],
    /// Velocity, m/s.
    pub v: [f32; 3],
    /// Birth step.
    pub born: u32,
    /// Emission index.
    pub id: u32,
    /// Impacts (low 12 bits) and status bits (the next 4).
    pub status: u32,
}

/// Bytes of one particle slot; the particles' buffer holds a sixteenth more for headroom at
/// most (see `dispatch::grow`), so a slot takes at most 17/16 of this of GPU memory.
pub const BYTES_PER_SLOT: usize = std::mem::size_of::<GpuParticle>();

impl GpuParticle {
    /// The slot of `p`, at its position and velocity at the start of its next step.
    pub fn of(p: &Particle, job: &FlightJob<'_>) -> GpuParticle {
        let (x, v) = p.now(job.config.dt, job.config.motion.gravity);
        GpuParticle {
            x: x.as_vec3().to_array(),
            v: v.as_vec3().to_array(),
            born: p.born,
            id: p.id,
            status: u32::from(p.status),
        }
    }

    /// The particle this slot holds, anchored where it stands (re-anchored every step, as the
    /// Euler integrators are).
    pub fn particle(&self) -> Particle {
        Particle {
            anchor: glam::Vec3::from_array(self.x).as_dvec3(),
            velocity: glam::Vec3::from_array(self.v),
            born: self.born,
            id: self.id,
            since: 0,
            status: (self.status & 0xffff) as u16,
        }
    }

    /// Whether the particle in this slot is in flight.
    pub fn is_alive(&self) -> bool {
        (self.status >> 12) & u32::from(flags::ALIVE) != 0
    }
}

/// The words of a job's scene, and where each table starts: the member's own words, whose
/// offsets (the tables', and those in target words) count from their start, wherever a
/// dispatch puts them.
#[derive(Debug)]
pub struct SceneWords {
    /// Every table, one after the other: the impact models first.
    pub words: Vec<u32>,
    /// Word offsets of the targets, the shapes' table (the box around them all, then the
    /// shapes) and the released table.
    pub tables: [u32; 3],
    /// Obstacle shapes.
    pub shapes: u32,
    /// Released particles in the table.
    pub released: u32,
    /// Per target, its first cell in the member's joined grids.
    pub first_cells: Vec<u32>,
    /// Cells of all the member's grids.
    pub cells: u32,
    /// Whether any target erodes.
    pub erodes: bool,
    /// Where its births lie (see `births.rs`).
    pub births: BirthPlace,
}

/// Where a member's births lie among its words and slots.
#[derive(Clone, Copy, Debug, Default)]
pub struct BirthPlace {
    /// Offset of the emitter's words in the member's own words; the batches of births follow.
    pub emitter: u32,
    /// Batches of births (steps that spray).
    pub batches: u32,
    /// Slots of its swarm (uploaded), which the newborns follow.
    pub swarm: u32,
    /// Newborns, sampled in their slots by the `born` kernel.
    pub newborns: u32,
}

pub(crate) fn put_f(w: &mut [u32], at: usize, x: f64) {
    w[at] = (x as f32).to_bits();
}

pub(crate) fn put_v(w: &mut [u32], at: usize, v: DVec3) {
    for k in 0..3 {
        put_f(w, at + k, v[k]);
    }
}

fn model_words(m: &ImpactModel) -> [u32; MODEL_WORDS] {
    let mut w = [0u32; MODEL_WORDS];
    put_f(&mut w, 0, m.alpha);
    put_f(&mut w, 1, m.restitution);
    put_f(&mut w, 2, m.scatter);
    put_f(&mut w, 3, m.rest_speed);
    put_f(&mut w, 4, m.rest_max_slope.cos());
    put_f(&mut w, 5, m.cushion_radius);
    let coefficients = |w: &mut [u32; MODEL_WORDS], c: &[f64]| {
        w[7] = c.len() as u32;
        for (k, &x) in c.iter().enumerate() {
            put_f(w, 8 + k, x);
        }
    };
    match m.rebound.form() {
        ReboundForm::Always => w[6] = 0,
        ReboundForm::Never | ReboundForm::Opaque => w[6] = 1,
        ReboundForm::Polynomial(p) => {
            w[6] = 2;
            coefficients(&mut w, &p.coefficients);
        }
        ReboundForm::Cushion(c) => {
            w[6] = 3;
            coefficients(&mut w, &c.ricochet.coefficients);
            put_f(&mut w, 16, c.aggregate_fraction);
            put_f(&mut w, 17, c.capture_ratio);
            put_f(&mut w, 18, c.trap_ratio);
            w[19] = c.grading.len() as u32;
            for (k, &(d, share)) in c.grading.iter().enumerate() {
                put_f(&mut w, 20 + 2 * k, d);
                put_f(&mut w, 21 + 2 * k, share);
            }
        }
    }
    w
}

fn face_words(w: &mut [u32], at: usize, f: &Face) {
    put_v(w, at, f.center);
    put_v(w, at + 3, f.normal);
    put_v(w, at + 6, f.up);
    put_v(w, at + 9, f.right);
    put_f(w, at + 12, f.half_width);
    put_f(w, at + 13, f.half_height);
}

/// Lays out the shell `c`'s geometry at `at` (see `flight.wgsl`): centre, axis, e1 (angle 0),
/// e2, half its unrolled width (its grid's) and length, its radius (word 26), the side sprayed
/// (28: +1 inside, −1 outside), its kind (29), its start angle (30, rad) and whether its grid
/// wraps round a full turn (31).
fn shell_words(w: &mut [u32], at: usize, c: &CylinderSurface) {
    let shell = &c.chart.shell;
    put_v(w, at, shell.center);
    put_v(w, at + 3, shell.axis);
    put_v(w, at + 6, shell.e1);
    put_v(w, at + 9, shell.e2);
    let (width, length) = c.chart.size();
    put_f(w, at + 12, 0.5 * width);
    put_f(w, at + 13, 0.5 * length);
    put_f(w, at + 26, shell.radius);
    put_f(w, at + 28, if c.chart.inside { 1.0 } else { -1.0 });
    w[at + 29] = SHELL;
    put_f(w, at + 30, shell.angles[0]);
    w[at + 31] = u32::from(c.chart.wraps());
}

fn shape_words(s: &Shape, owner: usize) -> [u32; SHAPE_WORDS] {
    let mut w = [0u32; SHAPE_WORDS];
    w[1] = owner as u32;
    w[16..].copy_from_slice(&box_words(s.aabb()));
    match s {
        Shape::Plane(p) => {
            w[0] = 0;
            put_v(&mut w, 2, p.point);
            put_v(&mut w, 5, p.normal);
        }
        Shape::Sphere(s) => {
            w[0] = 1;
            put_v(&mut w, 2, s.center);
            put_f(&mut w, 5, s.radius);
        }
        Shape::Cylinder(c) => {
            w[0] = 2;
            put_v(&mut w, 2, c.a);
            put_v(&mut w, 5, c.b);
            put_f(&mut w, 8, c.radius);
        }
        Shape::Disk(d) => {
            w[0] = 3;
            put_v(&mut w, 2, d.center);
            put_v(&mut w, 5, d.normal);
            put_f(&mut w, 8, d.radius);
        }
        Shape::Box(b) => {
            w[0] = 5;
            put_v(&mut w, 2, b.center);
            put_v(&mut w, 5, b.axes[0]);
            put_v(&mut w, 8, b.axes[1]);
            put_v(&mut w, 11, b.half_extents);
        }
        // Faces; the scope check has refused every other shape.
        other => {
            w[0] = 4;
            if let Shape::Face(f) = other {
                face_words(&mut w, 2, f);
            }
        }
    }
    w
}

/// Words of one erosion law.
pub const LAW_WORDS: usize = 8;

/// A target's erosion, as target word 25 points to it: the mass of one quantum of material
/// (`quantum_mass`, kg), 1 / [`WEAR_QUANTUM`] (m⁻³), then the coating's law and the
/// substrate's, [`LAW_WORDS`] each: 0 and Finnie's k, or 1 and Oka's E90 at the grain's size
/// (e90 (d / d_ref)^k₃, m³/kg), n₁, n₂, Hv, k₂ and v_ref (the scope check has refused others).
fn erosion_words(e: &ErosionConfig, quantum_mass: f64) -> Vec<u32> {
    let mut w = vec![0u32; 2 + 2 * LAW_WORDS];
    put_f(&mut w, 0, quantum_mass);
    put_f(&mut w, 1, 1.0 / WEAR_QUANTUM);
    for (k, law) in [&e.coating_law, &e.substrate_law].into_iter().enumerate() {
        let at = 2 + LAW_WORDS * k;
        match law.form() {
            ErosionForm::Finnie(f) => put_f(&mut w, at + 1, f.k),
            ErosionForm::Oka(o) => {
                w[at] = 1;
                put_f(&mut w, at + 1, o.e90 * (o.grain_diameter / o.d_ref).powf(o.k3));
                for (j, x) in [o.n1, o.n2, o.hv, o.k2, o.v_ref].into_iter().enumerate() {
                    put_f(&mut w, at + 2 + j, x);
                }
            }
            ErosionForm::Opaque => {}
        }
    }
    w
}

/// Lays out the openings of the grid `r`, whose words start at `at`: word 22 the offset of
/// its polygons (each its corner count, then its corners' in-face coordinates, m, as f32 pairs),
/// 23 their count, 24 the offset of its cells' hole bits (bit `c % 32` of word `c / 32`: cell
/// `c`'s centre lies in an opening). All zero without openings.
fn openings_words<C: Chart>(words: &mut Vec<u32>, at: usize, r: &GridSurface<C>) {
    let openings = r.openings();
    if openings.is_empty() {
        return;
    }
    words[at + 22] = words.len() as u32;
    words[at + 23] = openings.len() as u32;
    for o in openings {
        words.push(o.corners.len() as u32);
        for &(u, v) in &o.corners {
            words.extend([(u as f32).to_bits(), (v as f32).to_bits()]);
        }
    }
    let cells = r.field.thickness().len();
    let bits = words.len();
    words[at + 24] = bits as u32;
    words.resize(bits + cells.div_ceil(32), 0);
    for c in (0..cells).filter(|&c| r.field.is_hole(c as u32)) {
        words[bits + c / 32] |= 1 << (c % 32);
    }
}

/// Lays out the models, targets (with their footprints), shapes and released volumes of `job`.
pub fn scene_words(job: &FlightJob<'_>) -> SceneWords {
    let config = job.config;
    let mut words = Vec::new();
    for m in config.targets.iter().map(|t| &t.impact).chain(config.obstacles.iter().map(|o| &o.impact)) {
        words.extend_from_slice(&model_words(m));
    }
    let targets_at = words.len();
    words.resize(targets_at + TARGET_WORDS * job.targets.len(), 0);
    let (mut first_cells, mut cells) = (Vec::new(), 0u32);
    for (t, target) in job.targets.iter().enumerate() {
        let at = targets_at + TARGET_WORDS * t;
        first_cells.push(cells);
        let field = match &target.surface {
            Surface::Rectangle(r) => {
                face_words(&mut words, at, &r.chart);
                openings_words(&mut words, at, r);
                &r.field
            }
            Surface::Cylinder(c) => {
                shell_words(&mut words, at, c);
                openings_words(&mut words, at, c);
                &c.field
            }
            // The scope check has refused every other surface.
            Surface::Mesh(_) => continue,
        };
        words[at + 14] = field.cols() as u32;
        words[at + 15] = field.rows() as u32;
        words[at + 16] = cells;
        let top = field.max_thickness();
        // The band the layer may fill at the call's start (an upper bound of the thickest cell),
        // rounded up to f32; the kernels keep it in the counters (see `bands`).
        put_f(&mut words, at + 17, top * (1.0 + 1e-6) + 1e-9);
        words[at + 18] = u32::from(target.role == Role::Substrate);
        let offsets = words.len();
        words[at + 19] = offsets as u32;
        words[at + 20] = field.splat_offsets().len() as u32;
        // The struck cell first, then the others in the footprint's order.
        let splat = field.splat_offsets();
        for &(i, j) in splat.iter().filter(|&&o| o == (0, 0)).chain(splat.iter().filter(|&&o| o != (0, 0))) {
            words.push(i as i32 as u32);
            words.push(j as i32 as u32);
        }
        // The thickness one quantum adds to one of its cells, m.
        put_f(&mut words, at + 21, config.volume_quantum() / field.cell_area());
        if let Some(e) = &config.targets[t].erosion {
            words[at + 25] = words.len() as u32;
            words.extend(erosion_words(e, config.volume_quantum() * config.material.density));
        }
        cells += field.thickness().len() as u32;
    }
    let shapes_at = words.len();
    words.extend_from_slice(&shapes_box(config.obstacles.iter().flat_map(|o| &o.shapes)));
    let mut shapes = 0u32;
    for (o, obstacle) in config.obstacles.iter().enumerate() {
        for s in &obstacle.shapes {
            words.extend_from_slice(&shape_words(s, o));
            shapes += 1;
        }
    }
    let released_at = words.len();
    let mut released = 0u32;
    for (p, &q) in job.particles.iter().zip(job.quanta) {
        if p.flags() & flags::RELEASED != 0 {
            words.extend_from_slice(&[p.id, q as u32, (q >> 32) as u32]);
            released += 1;
        }
    }
    // A storage binding may not be empty.
    words.push(0);
    SceneWords {
        words,
        tables: [targets_at as u32, shapes_at as u32, released_at as u32],
        shapes,
        released,
        first_cells,
        cells,
        erodes: config.targets.iter().any(|t| t.erosion.is_some()),
        births: BirthPlace::default(),
    }
}

/// Each target's layer as spans to write over zero, m: per grid (meshes have none), the cells
/// from its first to its last that is not zero, from its first cell (`first_cells`, one per
/// target, over the member's grids); none for a bare layer. The GPU fills the rest of a rebuilt
/// copy with zero, so a fresh run's bare layers cross no bus.
pub fn nonzero_spans(job: &FlightJob<'_>, first_cells: &[u32]) -> Vec<(u32, Vec<f32>)> {
    let grids = job.targets.iter().zip(first_cells).filter(|(t, _)| !matches!(t.surface, Surface::Mesh(_)));
    let mut out = Vec::new();
    for (t, &first) in grids {
        let layer = t.surface.thickness();
        // Bits, not values: a −0 is written as it stands, as a whole copy would.
        let (Some(lo), Some(hi)) =
            (layer.iter().position(|x| x.to_bits() != 0), layer.iter().rposition(|x| x.to_bits() != 0))
        else {
            continue;
        };
        out.push((first + lo as u32, layer[lo..=hi].iter().map(|&x| x as f32).collect()));
    }
    out
}

/// A member's counter words at a call's start: zero, but for each target's band (see `flight.wgsl`).
pub fn counters(scene: &SceneWords, targets: usize, words: usize) -> Vec<u32> {
    let mut out = vec![0u32; words];
    for t in 0..targets {
        out[TALLY_WORDS + TARGET_COUNTER_WORDS * t + 3] = band(scene, t);
    }
    out
}

/// Target `t`'s band at the call's start (f32 bits, m), as `scene_words` wrote it.
pub fn band(scene: &SceneWords, t: usize) -> u32 {
    scene.words[scene.tables[0] as usize + TARGET_WORDS * t + 17]
}

/// Target `t`'s thickness of one quantum on one of its cells (f32 bits, m).
pub fn quantum_thickness(scene: &SceneWords, t: usize) -> u32 {
    scene.words[scene.tables[0] as usize + TARGET_WORDS * t + 21]
}

/// The layer epochs of `job`'s steps, each as (first step, step after its last).
pub fn epochs(job: &FlightJob<'_>) -> Vec<(u64, u64)> {
    let mut out = Vec::new();
    let mut a = job.from;
    while a < job.to {
        let b = ((a / job.epoch.max(1) + 1) * job.epoch.max(1)).min(job.to);
        out.push((a, b));
        a = b;
    }
    out
}

/// The parameters of the steps `from..to` of a dispatch of `slots` particle slots (all
/// members'), with `sizes` = (members, targets, cells, whether any target erodes).
pub fn params((from, to): (u64, u64), slots: u32, sizes: [u32; 4]) -> Params {
    Params { steps: [from as u32, to as u32, slots, WORKGROUP * ROW_GROUPS], sizes }
}

/// The words of `job`'s member (the WGSL `Member`): its physics, seed, sizes, and where it
/// lies (`place`); `scene` its own words, `nozzle` a nozzle particle's quanta.
pub fn member_words(
    job: &FlightJob<'_>,
    scene: &SceneWords,
    nozzle: u32,
    place: Place,
) -> [u32; MEMBER_WORDS] {
    let c = job.config;
    let g = c.motion.gravity;
    let integrator = match c.motion.integrator {
        Integrator::Euler => 0,
        Integrator::SemiImplicitEuler => 1,
        Integrator::Exact => 2,
    };
    let (lo, hi) = (c.domain.min, c.domain.max);
    let mut w = [0u32; MEMBER_WORDS];
    put_v(&mut w, 0, g);
    put_f(&mut w, 3, c.dt);
    put_v(&mut w, 4, lo);
    put_f(&mut w, 7, c.motion.drag);
    put_v(&mut w, 8, hi);
    put_f(&mut w, 11, c.material.max_lifetime / c.dt);
    w[12..16].copy_from_slice(&[integrator, c.seed as u32, (c.seed >> 32) as u32, c.max_impacts_per_step]);
    w[16..20].copy_from_slice(&[job.targets.len() as u32, scene.shapes, scene.released, nozzle]);
    place_member(&mut w, scene, place);
    w
}

/// Writes where a member lies (`place`) into its words: the offsets of its own words and of
/// their tables, its first slot, target, cell and counter word, and its births.
pub fn place_member(w: &mut [u32; MEMBER_WORDS], scene: &SceneWords, place: Place) {
    let [targets, shapes, released] = scene.tables.map(|t| place.words + t);
    w[20..24].copy_from_slice(&[place.words, targets, shapes, released]);
    w[24..28].copy_from_slice(&[place.slot, place.target, place.cell, place.counters]);
    let b = scene.births;
    w[28..32].copy_from_slice(&[place.words + b.emitter, b.batches, b.swarm, b.newborns]);
}
