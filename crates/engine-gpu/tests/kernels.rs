//! The flight kernel against closed forms, on random inputs with their boundary cases: forward
//! Euler flights onto a wall (where they strike, and which miss its edges), through its openings
//! and beside them, onto both sides of cylindrical shells and past their edges, the wear of each
//! impact under the erosion laws, and the 64-bit arithmetic of deposits shared over a footprint.

mod common;

use glam::{DQuat, DVec3};
use spraysim_engine::collision::{Aabb, CylinderShell, Face, OrientedBox, Primitive, Shape};
use spraysim_engine::config::ObstacleConfig;
use spraysim_engine::deposit::{
    Chart, CylinderSurface, DepositSurface, Opening, RectangleSurface, ShellChart, Surface, footprint_cells,
};
use spraysim_engine::particles::{Particle, StreamKey, flags};
use spraysim_engine::pipeline::{FlightJob, FlightStage};
use spraysim_engine::process::rebound::NeverRebound;
use spraysim_engine::{Simulation, SimulationConfig};
use std::sync::Arc;

/// A nozzle particle's volume, quanta.
const NOZZLE: u64 = 1 << 24;

/// The example wall (2 m × 2 m in the plane x = 0, facing −x, centred 1 m up) on which every
/// impact sticks, with `splat_radius` (m), in a domain wide enough that nothing leaves it.
fn sticky_wall(splat_radius: f64) -> SimulationConfig {
    let mut c = SimulationConfig::example_wall(1.0);
    let face = Face::new(DVec3::new(0.0, 0.0, 1.0), DVec3::NEG_X, DVec3::Z, [2.0, 2.0]);
    c.targets[0].surface = Surface::Rectangle(RectangleSurface::new(face, 256, 256, splat_radius));
    c.targets[0].splat_radius = Some(splat_radius);
    c.targets[0].impact.rebound = Arc::new(NeverRebound);
    c.domain = Aabb { min: DVec3::splat(-20.0), max: DVec3::splat(20.0) };
    c
}

/// xorshift64*: the tests' own reproducible uniform draws in [0, 1).
struct Draws(u64);

impl Draws {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// 4000 particles, each from a start towards an aim (`path` draws both), reaching the aim's
/// height after a flight of `shortest` to `shortest + 0.2` s under gravity `g`.
fn aimed(
    draws: &mut Draws,
    g: DVec3,
    shortest: f64,
    mut path: impl FnMut(&mut Draws) -> (DVec3, DVec3),
) -> Vec<Particle> {
    (0..4000u32)
        .map(|id| {
            let (start, aim) = path(draws);
            let time = shortest + 0.2 * draws.next();
            let v = (aim - start) / time - 0.5 * g * time;
            Particle::new(start, v, 0, id, flags::ALIVE)
        })
        .collect()
}

/// What the GPU reports of `particles` (each a nozzle particle) flown 400 steps in one epoch,
/// with every particle as the call left it, retired or not: every flight meets the bare
/// surfaces.
fn one_epoch(
    gpu: &spraysim_gpu::GpuFlight,
    config: &SimulationConfig,
    sim: &Simulation,
    particles: &[Particle],
) -> spraysim_engine::pipeline::FlightReport {
    let quanta = vec![NOZZLE; particles.len()];
    let job = FlightJob {
        config,
        from: 0,
        to: 400,
        epoch: 400,
        particles,
        quanta: &quanta,
        births: &[],
        nozzle_quanta: NOZZLE,
        key: StreamKey::new(config.seed),
        targets: sim.targets(),
        revised: &[None],
    };
    let (mut report, all) = gpu.fly_traced(&job).expect("the GPU flies the job");
    assert!(
        all.iter().filter(|p| p.is_alive()).eq(&report.particles),
        "the report hands back those in flight"
    );
    report.particles = all;
    report
}

/// Where forward Euler (x += v Δt, then v += g Δt) from `x`, `v` first crosses the plane x = 0
/// within `steps` steps of `dt`, in f64: the chord's crossing, and the steps flown to it (the
/// step of the crossing included).
fn euler_crossing(mut x: DVec3, mut v: DVec3, dt: f64, g: DVec3, steps: u32) -> Option<(DVec3, u64)> {
    for k in 0..steps {
        let x1 = x + v * dt;
        if x.x < 0.0 && x1.x >= 0.0 {
            return Some((x.lerp(x1, -x.x / (x1.x - x.x)), u64::from(k) + 1));
        }
        x = x1;
        v += g * dt;
    }
    None
}

/// Steps forward Euler from `x`, `v` flies within `domain`, at most `steps`: the step that
/// leaves it included.
fn euler_steps_in(domain: &Aabb, mut x: DVec3, mut v: DVec3, dt: f64, g: DVec3, steps: u64) -> u64 {
    for k in 1..=steps {
        x += v * dt;
        v += g * dt;
        if x.cmplt(domain.min).any() || x.cmpgt(domain.max).any() {
            return k;
        }
    }
    steps
}

/// Positions of an f32 flight of up to 400 steps over coordinates up to 2 m round off by up to
/// 400 × 2 m × 2⁻²⁴ ≈ 5·10⁻⁵ m; points closer than twice that to an edge of the wall are not
/// judged (either outcome is right within f32).
const F32_REACH: f64 = 1e-4;

#[test]
fn euler_flights_strike_the_wall_where_the_closed_form_says_and_miss_past_its_edges() {
    let Some(gpu) = common::gpu() else { return };
    let config = sticky_wall(0.0);
    let sim = Simulation::new(config.clone()).expect("valid");
    let (dt, g) = (config.dt, config.motion.gravity);
    let mut draws = Draws(0x9e37_79b9_7f4a_7c15);
    let particles = aimed(&mut draws, g, 0.03, |d| {
        let start = DVec3::new(-0.3 - 1.2 * d.next(), 2.0 * d.next() - 1.0, 2.0 * d.next());
        // Aimed at a point over the wall and up to 0.2 m past its edges.
        (start, DVec3::new(0.0, 2.4 * d.next() - 1.2, 2.4 * d.next() - 0.2))
    });
    let report = one_epoch(&gpu, &config, &sim, &particles);
    let (mut judged, mut hits, mut near_edge) = (0, 0, 0);
    // Particle-steps: a struck particle's flight ends with the step of its crossing; the others
    // fly until they leave the domain, or all 400 steps.
    let mut steps = 0;
    for (p, q) in particles.iter().zip(&report.particles) {
        let crossing = euler_crossing(p.anchor, p.anchor_velocity(), dt, g, 400);
        steps += match crossing {
            Some((_, k)) if q.impacts() > 0 => k,
            _ => euler_steps_in(&config.domain, p.anchor, p.anchor_velocity(), dt, g, 400),
        };
        let Some((point, _)) = crossing else { continue };
        let margin = (1.0 - point.y.abs()).min(1.0 - (point.z - 1.0).abs());
        if margin.abs() < F32_REACH {
            near_edge += 1;
            continue;
        }
        judged += 1;
        if margin > 0.0 {
            hits += 1;
            retired_at(p, q, point, "the wall");
        } else {
            assert_eq!(q.impacts(), 0, "particle {} passes {:.2e} m outside the edge", p.id, -margin);
        }
    }
    assert!(judged > 3500 && hits > 2000 && hits < judged, "{judged} judged, {hits} hits");
    assert_eq!(report.steps, steps, "particle-steps added up over the workgroups");
    let wall = &report.targets[0];
    assert!(wall.stuck.count >= hits as u64 && wall.stuck.count <= (hits + near_edge) as u64);
    assert_eq!(
        wall.stuck.quanta,
        u128::from(wall.stuck.count * NOZZLE),
        "every stuck particle's volume, exactly"
    );
    let cells = &report.cells[0];
    assert_eq!(cells.iter().map(|c| u64::from(c.hits)).sum::<u64>(), wall.hits);
    assert_eq!(u128::from(cells.iter().map(|c| c.quanta).sum::<u64>()), wall.stuck.quanta);
    assert!(cells.windows(2).all(|w| w[0].cell < w[1].cell), "cells listed once each, in order");
}

/// Where forward Euler from `x`, `v` first meets `shape` within `steps` steps of `dt`, in f64,
/// by the engine's own test of each step's chord, with the steps flown to it.
fn euler_hit(
    shape: &impl Primitive,
    mut x: DVec3,
    mut v: DVec3,
    dt: f64,
    g: DVec3,
    steps: u32,
) -> Option<(DVec3, u64)> {
    for k in 0..steps {
        let x1 = x + v * dt;
        if let Some(h) = shape.intersect(x, x1) {
            return Some((h.point, u64::from(k) + 1));
        }
        x = x1;
        v += g * dt;
    }
    None
}

#[test]
fn euler_flights_strike_a_turned_box_where_the_engine_does() {
    let Some(gpu) = common::gpu() else { return };
    // A 0.3 × 0.2 × 0.4 m box turned about two axes, 0.4 m in front of the sticky wall; what
    // strikes it sticks.
    let turn = DQuat::from_rotation_z(0.5) * DQuat::from_rotation_x(0.3);
    let shape = OrientedBox {
        center: DVec3::new(-0.4, 0.1, 1.0),
        axes: [turn * DVec3::X, turn * DVec3::Y, turn * DVec3::Z],
        half_extents: DVec3::new(0.15, 0.1, 0.2),
    };
    let mut config = sticky_wall(0.0);
    let impact = config.targets[0].impact.clone();
    config.obstacles.push(ObstacleConfig { name: "box".into(), shapes: vec![Shape::Box(shape)], impact });
    let sim = Simulation::new(config.clone()).expect("valid");
    let (dt, g) = (config.dt, config.motion.gravity);
    // The same box grown and shrunk by twice f32's reach: a flight that meets one and not the
    // other grazes an edge, where either outcome is right within f32.
    let grown = |by: f64| OrientedBox { half_extents: shape.half_extents + DVec3::splat(by), ..shape };
    let (outer, inner) = (grown(F32_REACH), grown(-F32_REACH));
    let mut draws = Draws(0x2545_f491_4f6c_dd1d);
    let particles = aimed(&mut draws, g, 0.05, |d| {
        let start = DVec3::new(-1.0 - 0.5 * d.next(), 2.0 * d.next() - 1.0, 0.5 + d.next());
        // Aimed at points around the box, half of them within it.
        (start, shape.center + DVec3::new(0.0, 0.6 * d.next() - 0.3, 0.8 * d.next() - 0.4))
    });
    let report = one_epoch(&gpu, &config, &sim, &particles);
    let (mut judged, mut hits) = (0, 0);
    for (p, q) in particles.iter().zip(&report.particles) {
        let (x, v) = (p.anchor, p.anchor_velocity());
        let (wide, narrow) = (euler_hit(&outer, x, v, dt, g, 400), euler_hit(&inner, x, v, dt, g, 400));
        if wide.is_some() != narrow.is_some() {
            continue;
        }
        let Some(_) = narrow else {
            // Misses the box by a margin: flies on, onto the wall or out of the domain.
            assert!(
                q.is_alive() || q.anchor.x.abs() < 1e-3 || q.anchor.abs().max_element() > 19.0,
                "particle {} should have missed the box, stopped at {}",
                p.id,
                q.anchor
            );
            judged += 1;
            continue;
        };
        let (point, _) = euler_hit(&shape, x, v, dt, g, 400).expect("within the grown box, so in the box");
        judged += 1;
        hits += 1;
        retired_at(p, q, point, "the box");
    }
    assert!(judged > 3800 && hits > 1000 && hits < judged - 1000, "{judged} judged, {hits} hits");
    let (boxed, wall) = (&report.obstacles[0], &report.targets[0]);
    assert!(boxed.stuck.count >= hits as u64 && boxed.stuck.count <= hits as u64 + 4000 - judged as u64);
    assert_eq!(boxed.hits, boxed.stuck.count, "every impact sticks");
    // Every particle is somewhere: in flight, stuck on the box or the wall, or gone.
    let alive = report.particles.iter().filter(|p| p.is_alive()).count() as u64;
    let t = &report.tally;
    let gone = t.left_domain.count + t.overspray.count + t.expired.count;
    assert_eq!(alive + boxed.stuck.count + wall.stuck.count + wall.stuck_back.count + gone, 4000);
}

#[test]
fn a_box_rebounds_what_strikes_its_face_as_that_face_alone_does() {
    use spraysim_engine::process::rebound::AlwaysRebound;
    let Some(gpu) = common::gpu() else { return };
    // A perfectly elastic box, 0.1 m deep, its front face at x = -0.45 facing the particles, and
    // that face alone: a flight that strikes the face rebounds once, the same way off either.
    let bouncy = |shape: Shape| {
        let mut c = sticky_wall(0.0);
        let mut impact = c.targets[0].impact.clone();
        impact.alpha = 1.0;
        impact.rebound = Arc::new(AlwaysRebound);
        (impact.restitution, impact.scatter, impact.rest_speed) = (1.0, 0.0, 0.0);
        c.obstacles.push(ObstacleConfig { name: "block".into(), shapes: vec![shape], impact });
        c
    };
    let block = OrientedBox {
        center: DVec3::new(-0.4, 0.0, 1.0),
        axes: [DVec3::X, DVec3::Y, DVec3::Z],
        half_extents: DVec3::new(0.05, 0.3, 0.3),
    };
    let face = Face::new(DVec3::new(-0.45, 0.0, 1.0), DVec3::NEG_X, DVec3::Z, [0.6, 0.6]);
    let (boxed, faced) = (bouncy(Shape::Box(block)), bouncy(Shape::Face(face)));
    let g = boxed.motion.gravity;
    let mut draws = Draws(0x5851_f42d_4c95_7f2d);
    // Aimed well inside the face's edges, from 0.55 to 1.05 m in front of it.
    let particles = aimed(&mut draws, g, 0.05, |d| {
        let start = DVec3::new(-1.0 - 0.5 * d.next(), 0.8 * d.next() - 0.4, 0.6 + 0.8 * d.next());
        (start, DVec3::new(-0.45, 0.5 * d.next() - 0.25, 1.0 + 0.5 * d.next() - 0.25))
    });
    let fly = |config: &SimulationConfig| {
        let sim = Simulation::new(config.clone()).expect("valid");
        one_epoch(&gpu, config, &sim, &particles)
    };
    let (off_box, off_face) = (fly(&boxed), fly(&faced));
    assert_eq!(off_box.obstacles[0].hits, 4000, "each flight strikes the box once");
    assert_eq!(off_face.obstacles[0].hits, 4000, "each flight strikes the face once");
    for (a, b) in off_box.particles.iter().zip(&off_face.particles) {
        assert_eq!((a.impacts(), b.impacts()), (1, 1), "particle {}", a.id);
        let apart = (a.anchor - b.anchor).length();
        assert!(apart < 1e-4, "particle {} ends {apart:.2e} m from where the face alone sends it", a.id);
    }
}

#[test]
fn a_deposit_shares_its_volume_over_the_footprint_exactly_beyond_32_bits() {
    let Some(gpu) = common::gpu() else { return };
    let config = sticky_wall(0.02);
    let sim = Simulation::new(config.clone()).expect("valid");
    let footprint = footprint_cells((2.0 / 256.0, 2.0 / 256.0), 0.02) as u64;
    assert!(footprint > 10, "a footprint of several cells, {footprint}");
    // Released material carrying more than 2³² quanta, and nozzle particles, square onto the
    // wall's middle and onto its corner (where the footprint is cut to a quarter), and released
    // material onto its back (which takes no deposit).
    let big = (1u64 << 33) + 12_345;
    let shots = [
        (DVec3::new(-0.5, 0.0039, 1.0039), flags::RELEASED, big),
        (DVec3::new(-0.5, 0.999, 1.999), flags::RELEASED, big + 1),
        (DVec3::new(-0.5, 0.3, 0.7), 0, NOZZLE),
        (DVec3::new(0.5, -0.3, 1.2), flags::RELEASED, big + 2),
    ];
    let particles: Vec<Particle> = shots
        .iter()
        .enumerate()
        .map(|(k, &(x, bits, _))| {
            let towards_the_wall = DVec3::new(-20.0 * x.x.signum(), 0.0, 0.0);
            Particle::new(x, towards_the_wall, 0, k as u32, flags::ALIVE | bits)
        })
        .collect();
    let quanta: Vec<u64> = shots.iter().map(|s| s.2).collect();
    let job = FlightJob {
        config: &config,
        from: 0,
        to: 100,
        epoch: 100,
        particles: &particles,
        quanta: &quanta,
        births: &[],
        nozzle_quanta: NOZZLE,
        key: StreamKey::new(config.seed),
        targets: sim.targets(),
        revised: &[None],
    };
    let report = gpu.fly(&job).expect("the GPU flies the job");
    let wall = &report.targets[0];
    assert_eq!(wall.received.count, 3);
    assert_eq!(wall.received.quanta, u128::from(3 * big + 3));
    assert_eq!(wall.received_back, u128::from(big + 2), "the back's share, to the quantum");
    assert_eq!(wall.stuck.quanta, u128::from(NOZZLE));
    let deposited: u128 = report.cells[0].iter().map(|c| u128::from(c.quanta)).sum();
    assert_eq!(deposited, u128::from(2 * big + 1 + NOZZLE), "the footprints hold every quantum");
    // Each cell of an interior footprint takes q / n, the struck one the remainder too.
    let struck = sim.targets()[0].surface.cell_at(0, DVec3::new(0.0, 0.0039, 1.0039));
    let took = |cell: u32| report.cells[0].iter().find(|c| c.cell == cell).map_or(0, |c| c.quanta);
    assert_eq!(took(struck), big / footprint + big % footprint);
    assert_eq!(took(struck + 1), big / footprint);
}

/// The wall's openings: a window left of the middle, an L-shaped box-out low on the right and a
/// triangle (its edges slanted across the cells) high on the right, in the face's coordinates (m
/// right of and up from its centre).
fn openings() -> Vec<Opening> {
    let window = Opening::rectangle((-0.4, 0.2), (0.5, 0.7));
    let notch = Opening {
        corners: vec![(0.2, -0.8), (0.8, -0.8), (0.8, -0.5), (0.5, -0.5), (0.5, -0.2), (0.2, -0.2)],
    };
    let skylight = Opening { corners: vec![(0.3, 0.3), (0.9, 0.4), (0.5, 0.9)] };
    vec![window, notch, skylight]
}

/// Whether the engine's choice of the solid cell for the in-face point `(u, v)` is clear within
/// f32: the point lies in a solid cell, or in a cut-away one whose nearest solid centre (in the
/// first ring of cells round it that holds any) is nearer than the next by `2 × F32_REACH`.
fn solid_cell_is_clear(field: &spraysim_engine::deposit::HeightField, (u, v): (f64, f64)) -> bool {
    let cell = field.cell_at(u, v);
    if !field.is_hole(cell) {
        return true;
    }
    let (cols, rows) = (field.cols() as i64, field.rows() as i64);
    let (r0, c0) = (i64::from(cell) / cols, i64::from(cell) % cols);
    for reach in 1..cols.max(rows) {
        let mut d: Vec<f64> = (r0 - reach..=r0 + reach)
            .flat_map(|r| (c0 - reach..=c0 + reach).map(move |c| (r, c)))
            .filter(|&(r, c)| (r - r0).abs().max((c - c0).abs()) == reach)
            .filter(|&(r, c)| (0..rows).contains(&r) && (0..cols).contains(&c))
            .map(|(r, c)| (r * cols + c) as u32)
            .filter(|&k| !field.is_hole(k))
            .map(|k| {
                let (cu, cv) = field.cell_center(k);
                (cu - u).hypot(cv - v)
            })
            .collect();
        if !d.is_empty() {
            d.sort_by(f64::total_cmp);
            return d.len() == 1 || d[1] - d[0] > 2.0 * F32_REACH;
        }
    }
    false
}

/// Whether the outcome of a crossing of the wall at the in-face point `(u, v)` is clear within
/// f32: the point lies clear of the wall's edges, the openings' edges, the cells' borders and any
/// tie between solid cells.
fn clear_within_f32(field: &spraysim_engine::deposit::HeightField, (u, v): (f64, f64)) -> bool {
    let (cell_w, cell_h) = field.cell_size();
    let border = |x: f64, size: f64| {
        let f = (x / size).rem_euclid(1.0);
        f.min(1.0 - f) * size
    };
    let edge = (1.0 - u.abs()).abs().min((1.0 - v.abs()).abs());
    let opening = openings().iter().map(|o| o.distance(u, v)).fold(f64::INFINITY, f64::min);
    edge.min(opening).min(border(u + 1.0, cell_w)).min(border(v + 1.0, cell_h)) > F32_REACH
        && (u.abs().max(v.abs()) > 1.0 || solid_cell_is_clear(field, (u, v)))
}

/// 4000 particles flying onto `face` under `g`: half aimed anywhere over it and past its edges,
/// half within 1.5 cells (of `cell` m) of an opening's edge.
fn aimed_round_openings(face: &Face, g: DVec3, cell: f64) -> Vec<Particle> {
    let on_face = |(u, v): (f64, f64)| face.center + face.right * u + face.up * v;
    let edges: Vec<((f64, f64), (f64, f64))> = openings()
        .iter()
        .flat_map(|o| (0..o.corners.len()).map(|i| (o.corners[i], o.corners[(i + 1) % o.corners.len()])))
        .collect();
    let mut draws = Draws(0x6a09_e667_f3bc_c909);
    aimed(&mut draws, g, 0.03, |d| {
        let start = DVec3::new(-0.3 - 1.2 * d.next(), 2.0 * d.next() - 1.0, 2.0 * d.next());
        if d.next() < 0.5 {
            return (start, DVec3::new(0.0, 2.2 * d.next() - 1.1, 2.2 * d.next() - 0.1));
        }
        let ((u0, v0), (u1, v1)) = edges[(d.next() * edges.len() as f64) as usize % edges.len()];
        let f = d.next();
        let jitter = |d: &mut Draws| 3.0 * cell * (d.next() - 0.5);
        (start, on_face((u0 + f * (u1 - u0) + jitter(d), v0 + f * (v1 - v0) + jitter(d))))
    })
}

#[test]
fn flights_pass_through_openings_and_what_strikes_beside_them_deposits_on_solid_cells_alone() {
    let Some(gpu) = common::gpu() else { return };
    let mut config = sticky_wall(0.02);
    let face = Face::new(DVec3::new(0.0, 0.0, 1.0), DVec3::NEG_X, DVec3::Z, [2.0, 2.0]);
    let surface = RectangleSurface::new(face, 256, 256, 0.02).with_openings(openings());
    config.targets[0].surface = Surface::Rectangle(surface);
    let sim = Simulation::new(config.clone()).expect("valid");
    let Surface::Rectangle(wall) = &sim.targets()[0].surface else { panic!("the wall is a rectangle") };
    let field = &wall.field;
    let (dt, g) = (config.dt, config.motion.gravity);
    let in_face = |p: DVec3| ((p - face.center).dot(face.right), (p - face.center).dot(face.up));
    // Only flights whose outcome f32 cannot change are flown.
    let particles: Vec<Particle> = aimed_round_openings(&face, g, field.cell_size().0)
        .into_iter()
        .filter(|p| {
            euler_crossing(p.anchor, p.anchor_velocity(), dt, g, 400)
                .is_none_or(|(x, _)| clear_within_f32(field, in_face(x)))
        })
        .collect();
    let report = one_epoch(&gpu, &config, &sim, &particles);
    // What the engine books: each flight that crosses the solid wall strikes it and shares its
    // volume evenly over the solid cells of the footprint round the solid cell it is booked to,
    // the struck one taking the remainder.
    let (mut hits, mut quanta) = (vec![0u32; field.thickness().len()], vec![0u64; field.thickness().len()]);
    let (mut struck, mut through, mut rim) = (0u64, 0, 0);
    for (p, q) in particles.iter().zip(&report.particles) {
        let Some((point, _)) = euler_crossing(p.anchor, p.anchor_velocity(), dt, g, 400) else { continue };
        let (u, v) = in_face(point);
        if u.abs() > 1.0 || v.abs() > 1.0 {
            continue;
        }
        if openings().iter().any(|o| o.contains(u, v)) {
            through += 1;
            assert_eq!(q.impacts(), 0, "particle {} passes through the opening at ({u:.3}, {v:.3})", p.id);
            continue;
        }
        struck += 1;
        assert!(!q.is_alive(), "particle {} should have struck the wall at ({u:.3}, {v:.3})", p.id);
        let cell = wall.cell_at(0, point);
        // Struck beside an opening, in a cell whose centre it covers: booked to a solid one.
        rim += usize::from(field.is_hole(field.cell_at(u, v)));
        assert!(!field.is_hole(cell));
        hits[cell as usize] += 1;
        let mut footprint = Vec::new();
        wall.footprint(cell, &mut |c| footprint.push(c));
        let n = footprint.len() as u64;
        for (k, &c) in footprint.iter().enumerate() {
            quanta[c as usize] += NOZZLE / n + if k == 0 { NOZZLE % n } else { 0 };
        }
    }
    assert!(
        struck > 1500 && through > 800 && rim > 20,
        "{struck} struck ({rim} on an opening's rim), {through} through the openings"
    );
    assert_eq!(report.targets[0].stuck.count, struck);
    let listed = &report.cells[0];
    for c in listed {
        assert!(!field.is_hole(c.cell), "cell {} lies in an opening, yet holds a deposit", c.cell);
        assert_eq!(c.hits, hits[c.cell as usize], "impacts in cell {}", c.cell);
        assert_eq!(c.quanta, quanta[c.cell as usize], "deposit in cell {}", c.cell);
    }
    let expected = quanta.iter().filter(|&&q| q > 0).count();
    assert_eq!(listed.iter().filter(|c| c.quanta > 0).count(), expected, "the cells that take a share");
    assert_eq!(listed.iter().map(|c| u128::from(c.quanta)).sum::<u128>(), u128::from(struck * NOZZLE));
}

/// Where forward Euler from `x`, `v` first crosses the plane x = 0 within `steps` steps of `dt`,
/// in f64, and the velocity there (the step's velocity moved on by g over the step's fraction
/// flown, as the kernels interpolate it).
fn euler_impact(mut x: DVec3, mut v: DVec3, dt: f64, g: DVec3, steps: u32) -> Option<(DVec3, DVec3)> {
    for _ in 0..steps {
        let x1 = x + v * dt;
        if x.x < 0.0 && x1.x >= 0.0 {
            let t = -x.x / (x1.x - x.x);
            return Some((x.lerp(x1, t), v + g * dt * t));
        }
        x = x1;
        v += g * dt;
    }
    None
}

#[test]
fn each_impact_wears_coating_and_substrate_as_the_erosion_laws_say() {
    use spraysim_engine::config::ErosionConfig;
    use spraysim_engine::deposit::wear_quanta;
    use spraysim_engine::process::ErosionLaw;
    use spraysim_engine::process::erosion::{Finnie, Oka};
    let Some(gpu) = common::gpu() else { return };
    // Grit at 30 to 150 m/s, from square on to 80° off the normal, onto a wall whose coat wears
    // by Finnie's law and whose steel by Oka's; every impact sticks, so each strikes once.
    let coat = Finnie { k: 2e-9 };
    let steel = Oka::for_hardness(1.4, 6.2e-8, 104.0, 326e-6, 0.19, 500e-6);
    let mut config = sticky_wall(0.0);
    config.targets[0].erosion =
        Some(ErosionConfig { coating: 1e-4, coating_law: Arc::new(coat), substrate_law: Arc::new(steel) });
    let sim = Simulation::new(config.clone()).expect("valid");
    let Surface::Rectangle(wall) = &sim.targets()[0].surface else { panic!("the wall is a rectangle") };
    let field = &wall.field;
    let (dt, g) = (config.dt, config.motion.gravity);
    let mass = NOZZLE as f64 * config.volume_quantum() * config.material.density;
    let mut draws = Draws(0xbb67_ae85_84ca_a73b);
    let particles: Vec<Particle> = (0..4000u32)
        .map(|id| {
            let start =
                DVec3::new(-0.1 - 0.4 * draws.next(), 1.6 * draws.next() - 0.8, 0.2 + 1.6 * draws.next());
            let (off, turn) = (80f64.to_radians() * draws.next(), std::f64::consts::TAU * draws.next());
            let dir = DVec3::new(off.cos(), off.sin() * turn.cos(), off.sin() * turn.sin());
            Particle::new(start, dir * (30.0 + 120.0 * draws.next()), 0, id, flags::ALIVE)
        })
        .filter(|p| {
            // Clear of the wall's edges and the cells' borders, where f32 may book another cell.
            euler_impact(p.anchor, p.anchor_velocity(), dt, g, 400).is_none_or(|(x, _)| {
                let (u, v) = (-x.y, x.z - 1.0);
                let (cw, ch) = field.cell_size();
                let border = |x: f64, size: f64| {
                    let f = (x / size).rem_euclid(1.0);
                    f.min(1.0 - f) * size
                };
                (1.0 - u.abs())
                    .abs()
                    .min((1.0 - v.abs()).abs())
                    .min(border(u + 1.0, cw))
                    .min(border(v + 1.0, ch))
                    > F32_REACH
            })
        })
        .collect();
    let report = one_epoch(&gpu, &config, &sim, &particles);
    // What the engine books per cell: each impact's volumes, rounded to f32, in wear quanta; and
    // the most each law could have removed at that speed, at its worst angle (the scale of f32's
    // error, which is largest relative to a volume near an angle where a law vanishes: Finnie's
    // at square incidence).
    let cells = field.thickness().len();
    let (mut expected, mut scale) = (vec![[0u64; 2]; cells], vec![[0.0f64; 2]; cells]);
    let mut struck = 0;
    for p in &particles {
        let Some((point, v_in)) = euler_impact(p.anchor, p.anchor_velocity(), dt, g, 400) else { continue };
        if point.y.abs() > 1.0 || (point.z - 1.0).abs() > 1.0 {
            continue;
        }
        struck += 1;
        let speed = v_in.length();
        let gamma = (v_in.x / speed).clamp(0.0, 1.0).asin();
        let cell = wall.cell_at(0, point) as usize;
        for (k, law) in [&coat as &dyn ErosionLaw, &steel].into_iter().enumerate() {
            expected[cell][k] += wear_quanta(f64::from(law.removed_volume(mass, speed, gamma) as f32));
            let most = (1..=90).map(|d| law.removed_volume(mass, speed, f64::from(d).to_radians()));
            scale[cell][k] += wear_quanta(most.fold(0.0, f64::max)) as f64;
        }
    }
    assert!(struck > 3000, "{struck} struck");
    assert_eq!(report.targets[0].hits, struck as u64);
    let listed = &report.cells[0];
    assert_eq!(listed.len(), expected.iter().filter(|w| w[0] > 0).count(), "the cells worn");
    // f32's angles, sines and powers against f64's: within 10⁻⁴ of what the impacts could remove
    // at most (a wrong angle or exponent is off by far more).
    for c in listed {
        for k in 0..2 {
            let (want, got) = (expected[c.cell as usize][k] as f64, c.wear[k] as f64);
            let tolerance = 1e-4 * scale[c.cell as usize][k];
            assert!(
                want > 0.0 && (got - want).abs() <= tolerance,
                "cell {}: wear {k} {got:e} against the law's {want:e} (tolerance {tolerance:.1e})",
                c.cell
            );
        }
    }
}

/// What forward Euler from `x`, `v` first meets within 400 steps of `dt` (s) under `g`, in f64:
/// the first answer of `meet` on a step's chord.
fn euler_first<T>(
    mut x: DVec3,
    mut v: DVec3,
    (dt, g): (f64, DVec3),
    meet: impl Fn(DVec3, DVec3) -> Option<T>,
) -> Option<T> {
    for _ in 0..400 {
        let x1 = x + v * dt;
        if let Some(m) = meet(x, x1) {
            return Some(m);
        }
        x = x1;
        v += g * dt;
    }
    None
}

/// Asserts that the GPU's flight `q` of `p` ended struck (on `what`) where the reference (a
/// closed form, or the engine on each step's chord) says, at `point`, to half of `F32_REACH`.
fn retired_at(p: &Particle, q: &Particle, point: DVec3, what: &str) {
    assert!(!q.is_alive(), "particle {} should have struck ({what}) at {point}", p.id);
    let err = (q.anchor - point).length();
    assert!(
        err < 0.5 * F32_REACH,
        "particle {} ({what}): at {} against the reference's {point}",
        p.id,
        q.anchor
    );
}

/// Whether a hit at `point` on `chart`'s shell, its normal facing the particle, strikes the side
/// the chart receives spray on (its front).
fn on_front(chart: &ShellChart, point: DVec3, normal: DVec3) -> bool {
    let (u, _, _) = chart.local(point);
    normal.dot(chart.frame(u, 0.0).0) > 0.0
}

/// Where a chord meets `chart`'s bare shell by the engine's own test: the point, and whether it
/// strikes its front.
fn shell_chord(chart: &ShellChart, x: DVec3, x1: DVec3) -> Option<(DVec3, bool)> {
    let h = chart.shell.intersect(x, x1)?;
    Some((h.point, on_front(chart, h.point, h.normal)))
}

/// Where forward Euler from `x`, `v` first meets `chart`'s shell within 400 steps of `dt`
/// under `g` (see [`shell_chord`]).
fn euler_shell_hit(chart: &ShellChart, x: DVec3, v: DVec3, dt: f64, g: DVec3) -> Option<(DVec3, bool)> {
    euler_first(x, v, (dt, g), |a, b| shell_chord(chart, a, b))
}

/// Flights onto `chart`'s shell (sticky, 240 × 160 cells), in steps of `dt` (s), from `start`s
/// towards `aim`s, judged
/// against the engine's shell path by path: each strikes the same side at the same point (its
/// front in the same cell) or misses. Flights whose outcome f32 could change (the shell grown or
/// shrunk by `F32_REACH` disagrees, or the point lies that close to a cell's border) are not
/// flown. Returns (front hits, back hits, misses).
fn shell_flights(
    gpu: &spraysim_gpu::GpuFlight,
    (chart, dt): (ShellChart, f64),
    seed: u64,
    mut path: impl FnMut(&mut Draws) -> (DVec3, DVec3),
) -> (u64, u64, u64) {
    let mut config = sticky_wall(0.0);
    config.dt = dt;
    let surface = CylinderSurface::new(chart, 240, 160, 0.0);
    config.targets[0].surface = Surface::Cylinder(surface);
    let sim = Simulation::new(config.clone()).expect("valid");
    let Surface::Cylinder(grid) = &sim.targets()[0].surface else { panic!("a shell") };
    let field = &grid.field;
    let g = config.motion.gravity;
    let resized = |by: f64| {
        let mut c = chart;
        let reach = by / c.shell.radius;
        (c.shell.radius, c.shell.half_length) = (c.shell.radius + by, c.shell.half_length + by);
        c.shell.angles = [c.shell.angles[0] - reach, c.shell.angles[1] + reach];
        c
    };
    let (outer, inner) = (resized(F32_REACH), resized(-F32_REACH));
    let outcome = |c: &ShellChart, p: &Particle| {
        euler_shell_hit(c, p.anchor, p.anchor_velocity(), dt, g).map(|(_, front)| front)
    };
    let mut draws = Draws(seed);
    let particles: Vec<Particle> = (0..4000u32)
        .map(|id| {
            let (start, aim) = path(&mut draws);
            Particle::new(start, (aim - start).normalize() * (8.0 + 8.0 * draws.next()), 0, id, flags::ALIVE)
        })
        .filter(|p| outcome(&outer, p) == outcome(&inner, p))
        .filter(|p| match euler_shell_hit(&chart, p.anchor, p.anchor_velocity(), dt, g) {
            Some((point, true)) => {
                let (u, v, _) = chart.local(point);
                let (w, h) = chart.size();
                let (cw, ch) = field.cell_size();
                let border = |x: f64, size: f64| {
                    let f = (x / size).rem_euclid(1.0);
                    f.min(1.0 - f) * size
                };
                border(u + 0.5 * w, cw).min(border(v + 0.5 * h, ch)) > F32_REACH
            }
            _ => true,
        })
        .collect();
    let report = one_epoch(gpu, &config, &sim, &particles);
    let mut hits = vec![0u32; field.thickness().len()];
    let (mut front, mut back, mut missed) = (0, 0, 0);
    for (p, q) in particles.iter().zip(&report.particles) {
        match euler_shell_hit(&chart, p.anchor, p.anchor_velocity(), dt, g) {
            Some((point, side)) => {
                retired_at(p, q, point, if side { "front" } else { "back" });
                if side {
                    front += 1;
                    hits[grid.cell_at(0, point) as usize] += 1;
                } else {
                    back += 1;
                }
            }
            None => {
                missed += 1;
                assert_eq!(q.impacts(), 0, "particle {} misses the shell", p.id);
            }
        }
    }
    let tally = &report.targets[0];
    assert_eq!((tally.stuck.count, tally.stuck_back.count), (front, back), "front and back");
    for c in &report.cells[0] {
        assert_eq!(c.hits, hits[c.cell as usize], "impacts in cell {}", c.cell);
    }
    assert_eq!(report.cells[0].len(), hits.iter().filter(|&&h| h > 0).count(), "the cells struck");
    (front, back, missed)
}

#[test]
fn flights_strike_both_sides_of_shells_and_pass_their_edges_where_the_engine_says() {
    let Some(gpu) = common::gpu() else { return };
    let shell = |radius: f64, angles: [f64; 2], inside: bool| ShellChart {
        shell: CylinderShell::new(
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::Y,
            DVec3::X,
            radius,
            2.0,
            angles.map(f64::to_radians),
        )
        .expect("a shell"),
        inside,
    };
    // A tunnel's arch (30° to 150°, sprayed from inside), from points near its axis in all
    // directions: the arch, or out past its springlines and ends.
    let arch = shell(1.5, [30.0, 150.0], true);
    let (front, back, missed) = shell_flights(&gpu, (arch, 1e-3), 0x3c6e_f372_fe94_f82b, |d| {
        let start = DVec3::new(0.6 * d.next() - 0.3, 1.6 * d.next() - 0.8, 1.0 + 0.6 * d.next() - 0.3);
        let aim = DVec3::new(4.0 * d.next() - 2.0, 3.0 * d.next() - 1.5, 1.0 + 4.0 * d.next() - 2.0);
        (start, aim)
    });
    assert!(front > 500 && missed > 500 && back == 0, "arch: {front} front, {back} back, {missed} missed");
    // The same arch from behind (the rock's side): onto its back from above, or up through the
    // open invert and onto the arch from inside, in steps of 2 to 4 m, so that many pass the
    // invert and strike the arch within one step.
    let (front, back, _) = shell_flights(&gpu, (arch, 0.25), 0x1f83_d9ab_fb41_bd6b, |d| {
        let around = std::f64::consts::PI * (0.1 + 1.8 * d.next());
        let r = 2.0 + 0.5 * d.next();
        let start = DVec3::new(r * around.cos(), 1.6 * d.next() - 0.8, 1.0 + r * around.sin());
        (start, DVec3::new(0.8 * d.next() - 0.4, 1.6 * d.next() - 0.8, 1.0 + 0.8 * d.next() - 0.4))
    });
    assert!(front > 300 && back > 300, "arch from behind: {front} front, {back} back");
    // The upper half of a pipe (0° to 180°, sprayed from outside), from all round: its outside,
    // or from below into it and onto the back of its far side (in steps of 0.4 to 0.8 m, within
    // one step for many), or past it.
    let half_pipe = shell(0.4, [0.0, 180.0], false);
    let (front, back, missed) = shell_flights(&gpu, (half_pipe, 0.05), 0xa54f_f53a_5f1d_36f1, |d| {
        let around = std::f64::consts::TAU * d.next();
        let start = DVec3::new(around.cos(), 1.6 * d.next() - 0.8, 1.0 + around.sin());
        let aim = DVec3::new(0.8 * d.next() - 0.4, 2.4 * d.next() - 1.2, 1.0 + 0.8 * d.next() - 0.4);
        (start, aim)
    });
    assert!(
        front > 1000 && back > 300 && missed > 300,
        "half pipe: {front} front, {back} back, {missed} missed"
    );
    // A whole pipe (its grid wraps), from outside.
    let pipe = shell(0.4, [0.0, 360.0], false);
    let (front, back, _) = shell_flights(&gpu, (pipe, 1e-3), 0x510e_527f_ade6_82d1, |d| {
        let around = std::f64::consts::TAU * d.next();
        let start = DVec3::new(around.cos(), 1.6 * d.next() - 0.8, 1.0 + around.sin());
        (start, DVec3::new(0.6 * d.next() - 0.3, 2.4 * d.next() - 1.2, 1.0 + 0.6 * d.next() - 0.3))
    });
    assert!(front > 2000 && back == 0, "pipe: {front} front, {back} back");
}

/// What a flight meets first on a layered shell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Met {
    /// The layer's top, on the side sprayed.
    Layer,
    /// The bare surface on the side sprayed: only from a step that started behind the shell and
    /// passed its edge.
    BareFront,
    /// Its bare back.
    Back,
}

/// Where forward Euler from `x`, `v` first meets the layered `surface` (charted as `chart`)
/// within 400 steps of `dt`, in f64, by the engine's own tests of each step's chord (its bare
/// faces, then its layer, as the engine's flight takes the nearer): the point and what it meets.
fn euler_layered_hit(
    (surface, chart): (&Surface, &ShellChart),
    x: DVec3,
    v: DVec3,
    dt: f64,
    g: DVec3,
) -> Option<(DVec3, Met)> {
    euler_first(x, v, (dt, g), |x, x1| {
        let bare = surface.intersect(x, x1);
        match (bare, surface.layer_contact(x, x1)) {
            (_, Some(l)) if bare.is_none_or(|b| l.s < b.t) => Some((l.point, Met::Layer)),
            (Some(b), _) => {
                Some((b.point, if on_front(chart, b.point, b.normal) { Met::BareFront } else { Met::Back }))
            }
            _ => None,
        }
    })
}

/// Whether forward Euler from `p`, up to its first contact with `surface` (charted as `chart`,
/// lined `lining` m thick), passes within a cell of the chart's edges or ends at a height within
/// the lining (or a millimetre of it), where the lining's corner may be met or not: sampled
/// every 2 mm of its steps of `dt` (s) under `g`.
fn clips_edge(
    chart: &ShellChart,
    surface: &Surface,
    p: &Particle,
    (dt, g): (f64, DVec3),
    lining: f64,
) -> bool {
    let (w, h) = chart.size();
    let Surface::Cylinder(grid) = surface else { return false };
    let (cw, ch) = grid.field.cell_size();
    let near = |x: f64, half: f64, cell: f64| (x.abs() - half).abs() < cell;
    let (mut x, mut v) = (p.anchor, p.anchor_velocity());
    for _ in 0..400 {
        let x1 = x + v * dt;
        // The step's first contact, as a fraction of it: the path is looked at up to there.
        let contact = [surface.intersect(x, x1).map(|h| h.t), surface.layer_contact(x, x1).map(|l| l.s)];
        let end = contact.iter().flatten().fold(1.0_f64, |a, &b| a.min(b));
        let n = ((x1 - x).length() * end / 2e-3).ceil().max(1.0) as usize;
        for k in 0..=n {
            let (u, along, height) = chart.local(x.lerp(x1, end * k as f64 / n as f64));
            let in_band = (-1e-3..=lining + 1e-3).contains(&height);
            let by_side = near(u, 0.5 * w, cw) && along.abs() < 0.5 * h + ch;
            let by_end = near(along, 0.5 * h, ch) && u.abs() < 0.5 * w + cw;
            if in_band && (by_side || by_end) {
                return true;
            }
        }
        if end < 1.0 || x1.length() > 8.0 {
            return false;
        }
        x = x1;
        v += g * dt;
    }
    false
}

/// A tunnel's arch seen from inside (1.5 m radius, 30° to 150°, 2 m long, its axis along y
/// through (0, 0, 1)), grown by `by` m in radius, half-length and arc.
fn lined_arch(by: f64) -> ShellChart {
    let shell = CylinderShell::new(
        DVec3::new(0.0, 0.0, 1.0),
        DVec3::Y,
        DVec3::X,
        1.5 + by,
        2.0 + 2.0 * by,
        [30.0_f64, 150.0].map(|a| a.to_radians()).map(|a| a + by / 1.5 * (a - 90f64.to_radians()).signum()),
    )
    .expect("a shell");
    ShellChart { shell, inside: true }
}

/// `chart`'s surface (240 × 160 cells) with every cell lined `lining` m thick.
fn lined(chart: ShellChart, lining: f64) -> Surface {
    let mut s = Surface::Cylinder(CylinderSurface::new(chart, 240, 160, 0.0));
    for cell in 0..s.thickness().len() as u32 {
        s.add_thickness(cell, lining);
    }
    s
}

/// `n` particles at 8 to 16 m/s: half from behind the lined arch (2 to 2.5 m from its axis, all
/// round but for its invert) towards its middle, a quarter from near its axis outwards, and a
/// quarter from within the lining's height past its springlines (5° to 50° past them) across
/// the tunnel.
fn lined_arch_paths(n: u32) -> Vec<Particle> {
    let mut draws = Draws(0x9b05_688c_2b3e_6c1f);
    let middle =
        |d: &mut Draws| DVec3::new(0.8 * d.next() - 0.4, 1.6 * d.next() - 0.8, 1.0 + 0.8 * d.next() - 0.4);
    (0..n)
        .map(|id| {
            let (start, aim) = match id % 4 {
                0 => {
                    let start = DVec3::new(
                        0.6 * draws.next() - 0.3,
                        1.6 * draws.next() - 0.8,
                        1.0 + 0.6 * draws.next() - 0.3,
                    );
                    (start, start + (middle(&mut draws) - DVec3::new(0.0, 0.0, 1.0)) * 4.0)
                }
                1 => {
                    let past = (5.0 + 45.0 * draws.next()).to_radians();
                    let around = if draws.next() < 0.5 {
                        30f64.to_radians() - past
                    } else {
                        150f64.to_radians() + past
                    };
                    let r = 1.5 - 0.05 * draws.next();
                    let start =
                        DVec3::new(r * around.cos(), 1.6 * draws.next() - 0.8, 1.0 + r * around.sin());
                    (start, middle(&mut draws) + DVec3::new(0.0, 0.0, 1.0))
                }
                _ => {
                    let around = std::f64::consts::PI * (0.1 + 1.8 * draws.next());
                    let r = 2.0 + 0.5 * draws.next();
                    let start =
                        DVec3::new(r * around.cos(), 1.6 * draws.next() - 0.8, 1.0 + r * around.sin());
                    (start, middle(&mut draws))
                }
            };
            Particle::new(start, (aim - start).normalize() * (8.0 + 8.0 * draws.next()), 0, id, flags::ALIVE)
        })
        .collect()
}

#[test]
fn a_step_from_behind_a_lined_arch_past_its_edge_meets_only_its_bare_surface() {
    let Some(gpu) = common::gpu() else { return };
    // A tunnel's arch (1.5 m, 30° to 150°, sprayed from inside) lined 5 cm thick, flown at
    // in steps of 2 to 4 m: from behind (the rock's side) onto its back, or past its
    // springlines and into the arch, which a step that started behind meets on its bare
    // surface, as the engine does (the lining is struck from the next step on); from inside,
    // onto the lining, also where the step leaves the shell past its end; and from within the
    // lining's height past the springlines, up across the tunnel and down onto the lining's
    // top (not its side).
    let (lining, dt) = (0.05, 0.25);
    let [arch, outer, inner] = [0.0, F32_REACH, -F32_REACH].map(lined_arch);
    let surfaces = [arch, outer, inner].map(|c| lined(c, lining));
    let mut config = sticky_wall(0.0);
    config.dt = dt;
    config.targets[0].surface = surfaces[0].clone();
    let sim = Simulation::new(config.clone()).expect("valid");
    let Surface::Cylinder(grid) = &sim.targets()[0].surface else { panic!("a shell") };
    assert!(grid.thickness().iter().all(|&t| t == lining), "the arch is lined");
    let g = config.motion.gravity;
    let met = |k: usize, p: &Particle| {
        let c = [arch, outer, inner][k];
        euler_layered_hit((&surfaces[k], &c), p.anchor, p.anchor_velocity(), dt, g)
    };
    let particles: Vec<Particle> = lined_arch_paths(8000)
        .into_iter()
        // Those whose outcome f32 could change: another side or kind on a shell grown or shrunk
        // by F32_REACH.
        .filter(|p| {
            let kind = |k: usize| met(k, p).map(|m| m.1);
            kind(0) == kind(1) && kind(0) == kind(2)
        })
        // Those that clip the lining's edge: the engine marches at half a cell along the
        // surface, the GPU crosses the layer's height, and a corner may be seen by one alone.
        .filter(|p| !clips_edge(&arch, &surfaces[0], p, (dt, g), lining))
        .collect();
    let report = one_epoch(&gpu, &config, &sim, &particles);
    let mut counts = [0u64; 4];
    for (p, q) in particles.iter().zip(&report.particles) {
        let Some((point, kind)) = met(0, p) else {
            assert_eq!(q.impacts(), 0, "particle {} misses the arch", p.id);
            counts[3] += 1;
            continue;
        };
        retired_at(p, q, point, &format!("{kind:?}"));
        counts[kind as usize] += 1;
    }
    let tally = &report.targets[0];
    assert_eq!(tally.stuck.count, counts[0] + counts[1], "struck on the side sprayed");
    assert_eq!(tally.stuck_back.count, counts[2], "struck on the back");
    let [layer, bare, back, missed] = counts;
    assert!(
        layer > 500 && bare > 100 && back > 500 && missed > 500,
        "{layer} on the lining, {bare} on the bare surface past the edge, {back} on the back, {missed} missed"
    );
}
