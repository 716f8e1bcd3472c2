//! The engine's seams, used from outside it through its public API only: a rebound law and an
//! obstacle shape defined here run in a scene, a shape gives viewers its triangles (or its box),
//! an event handler watches a run, the nozzle's path is replaced mid-run, and a snapshot
//! continues exactly as the original.

use glam::DVec3;
use spraysim_engine::Simulation;
use spraysim_engine::collision::{
    Aabb, Cylinder, CylinderShell, Disk, Face, Flight, Hit, OrientedBox, Plane, Primitive, Shape, Sphere,
    Triangle,
};
use spraysim_engine::config::{ObstacleConfig, SimulationConfig};
use spraysim_engine::deposit::{DepositSurface, RectangleSurface, Surface};
use spraysim_engine::emission::{NozzlePath, Waypoint};
use spraysim_engine::events::{EmissionEvent, EventHandler, ImpactEvent};
use spraysim_engine::process::rebound::PolynomialRebound;
use spraysim_engine::process::{ImpactSite, ReboundLaw};
use std::sync::Arc;

/// A rebound law of our own: every impact steeper than `critical` (rad from the normal)
/// rebounds, every other sticks.
#[derive(Debug)]
struct Threshold {
    critical: f64,
}

impl ReboundLaw for Threshold {
    fn probability(&self, impact: &ImpactSite) -> f64 {
        if impact.theta > self.critical { 1.0 } else { 0.0 }
    }
}

/// An obstacle shape of our own: an infinitely thin square plate at height `z`, spanning
/// `|x|, |y| ≤ half` (a ledge), with the segment and arc tests a shape must answer.
#[derive(Debug)]
struct Ledge {
    z: f64,
    half: f64,
}

impl Ledge {
    fn at(&self, p: DVec3, t: f64, from_above: bool) -> Option<Hit> {
        let on = p.x.abs() <= self.half && p.y.abs() <= self.half;
        on.then_some(Hit { t, point: p, normal: if from_above { DVec3::Z } else { DVec3::NEG_Z } })
    }
}

impl Primitive for Ledge {
    fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        let (d0, d1) = (p0.z - self.z, p1.z - self.z);
        if d0 == 0.0 || (d0 > 0.0) == (d1 > 0.0) && d1 != 0.0 {
            return None;
        }
        let t = d0 / (d0 - d1);
        self.at(p0.lerp(p1, t), t, d0 > 0.0)
    }

    fn intersect_arc(&self, arc: &Flight) -> Option<Hit> {
        // z(τ) = z₀ + v τ + ½ g τ² = ledge height: the first root in (0, T].
        let (a, b, c) = (0.5 * arc.g.z, arc.v0.z, arc.x0.z - self.z);
        let roots = spraysim_engine::collision::roots(&[c, b, a], 0.0, arc.duration);
        let tau = roots.iter().copied().find(|&tau| tau > 0.0)?;
        self.at(arc.at(tau), tau / arc.duration, c > 0.0)
    }

    fn aabb(&self) -> Option<Aabb> {
        let h = DVec3::new(self.half, self.half, 0.0);
        Some(Aabb { min: DVec3::new(0.0, 0.0, self.z) - h, max: DVec3::new(0.0, 0.0, self.z) + h })
    }
}

/// Particles sprayed straight down from 1 m onto a floor, through a ledge 0.5 m up that covers
/// the left half of the spray, with the threshold law on the floor.
fn scene(law: Arc<dyn ReboundLaw>, duration: f64) -> SimulationConfig {
    let mut c = SimulationConfig::example_wall(duration);
    c.nozzle = NozzlePath::fixed(DVec3::new(0.0, 0.0, 1.0), DVec3::NEG_Z, 0.0);
    c.emitter.cone_half_angle = 20f64.to_radians();
    c.emitter.direction = spraysim_engine::emission::Direction::UniformSolidAngle;
    c.emitter.aperture = spraysim_engine::emission::Aperture::Point;
    let floor = Face::new(DVec3::ZERO, DVec3::Z, DVec3::X, [2.0, 2.0]);
    let target = &mut c.targets[0];
    target.name = "floor".into();
    target.surface = Surface::Rectangle(RectangleSurface::new(floor, 64, 64, 0.0));
    target.impact.rebound = law;
    let ledge = Ledge { z: 0.5, half: 0.05 };
    c.obstacles.push(ObstacleConfig {
        name: "ledge".into(),
        shapes: vec![Shape::Custom(Arc::new(ledge))],
        impact: c.targets[0].impact.clone(),
    });
    c.domain = Aabb { min: DVec3::splat(-2.0), max: DVec3::splat(2.0) };
    c
}

#[test]
fn a_rebound_law_and_an_obstacle_shape_from_outside_the_engine_run_in_a_scene() {
    // Nothing is steeper than 30° here, so the threshold law makes every impact stick.
    let law = Arc::new(Threshold { critical: 30f64.to_radians() });
    let mut sim = Simulation::new(scene(law, 0.2)).expect("valid");
    sim.run(|_| {});
    let m = sim.metrics();
    assert_eq!(m.rebound_ratio, Some(0.0), "the law of our own decides");
    // A point source uniform over a cone's solid angle puts on a square of half-width a at
    // distance h the share ∫ h / r³ dA / (2π (1 − cos θc)); gravity shortens the fall to the
    // ledge by about 1 % at these speeds.
    let (a, h, cos_c) = (0.05, 0.5, 20f64.to_radians().cos());
    let n = 400;
    let cell = 2.0 * a / n as f64;
    let mut solid = 0.0;
    for i in 0..n {
        for j in 0..n {
            let (x, y) = (-a + (i as f64 + 0.5) * cell, -a + (j as f64 + 0.5) * cell);
            solid += h / (x * x + y * y + h * h).powf(1.5) * cell * cell;
        }
    }
    let expected = solid / (std::f64::consts::TAU * (1.0 - cos_c));
    let share = m.obstacles[0].stuck.count as f64 / m.emitted.count as f64;
    let sd = (expected * (1.0 - expected) / m.emitted.count as f64).sqrt();
    assert!(
        (share - expected).abs() < 5.0 * sd + 0.02 * expected,
        "ledge share {share} vs {expected} ± {sd}"
    );
    assert_eq!(m.fates.total().count, m.emitted.count);
    // Nothing reaches the floor under the ledge: its shadow is empty.
    let floor = &sim.targets()[0].surface;
    assert!(floor.thickness()[floor.cell_at(0, DVec3::new(0.0, 0.0, 0.0)) as usize] == 0.0);
    // The same scene with every impact rebounding (threshold 0): the law really is consulted.
    let always = Arc::new(Threshold { critical: -1.0 });
    let mut sim = Simulation::new(scene(always, 0.2)).expect("valid");
    sim.run(|_| {});
    assert_eq!(sim.metrics().rebound_ratio, Some(1.0));
}

/// Counts what it sees.
#[derive(Default)]
struct Watcher {
    impacts: Vec<ImpactEvent>,
    emitted: u64,
    steps: u64,
}

impl EventHandler for Watcher {
    fn wants_impacts(&self) -> bool {
        true
    }
    fn impact(&mut self, e: &ImpactEvent) {
        self.impacts.push(*e);
    }
    fn emission(&mut self, e: &EmissionEvent) {
        self.emitted += e.count;
    }
    fn step_end(&mut self, _time: f64) {
        self.steps += 1;
    }
}

#[test]
fn an_event_handler_sees_every_impact_in_the_same_order_whatever_the_threads() {
    let law: Arc<dyn ReboundLaw> = Arc::new(PolynomialRebound { coefficients: vec![0.3] });
    let watch = |threads: usize| {
        let mut sim = Simulation::new(scene(law.clone(), 0.1)).expect("valid");
        sim.set_threads(threads).expect("pool");
        let mut w = Watcher::default();
        while !sim.is_finished() {
            sim.step_with(&mut w);
        }
        (sim, w)
    };
    let (sim, one) = watch(1);
    let (_, two) = watch(2);
    let m = sim.metrics();
    assert_eq!(one.impacts, two.impacts);
    assert_eq!(one.emitted, m.emitted.count);
    assert_eq!(one.steps, sim.steps_done());
    let hits: u64 =
        m.targets.iter().map(|t| t.hits).sum::<u64>() + m.obstacles.iter().map(|o| o.hits).sum::<u64>();
    assert_eq!(one.impacts.len() as u64, hits, "every impact, once");
    let stuck = one.impacts.iter().filter(|e| e.stuck).count() as u64;
    assert_eq!(stuck, m.fates.stuck_on_targets.count + m.fates.stuck_on_obstacles.count);
}

#[test]
fn the_nozzle_path_can_be_replaced_between_steps() {
    let law: Arc<dyn ReboundLaw> = Arc::new(Threshold { critical: 1.5 });
    // Spray for 50 ms from above the origin, then 50 ms from 0.7 m to the side, then let
    // everything land.
    let pose = |x: f64, from: f64, until: f64| {
        let (position, axis) = (DVec3::new(x, 0.0, 1.0), DVec3::NEG_Z);
        NozzlePath::through(
            vec![
                Waypoint { time: from, position, axis, spray: true },
                Waypoint { time: until, position, axis, spray: false },
            ],
            0.0,
        )
    };
    let mut config = scene(law, 0.2);
    config.nozzle = pose(0.0, 0.0, 0.05);
    let mut sim = Simulation::new(config).expect("valid");
    while sim.time() < 0.05 - 1e-9 {
        sim.step();
    }
    // Closed-loop control: a new path from now on.
    sim.set_nozzle_path(pose(0.7, sim.time(), 0.1)).expect("a valid path");
    sim.run(|_| {});
    let floor = sim.targets()[0].surface.as_rectangle().expect("a rectangle");
    // Volume on the floor around x (m), within 0.4 m.
    let around = |x0: f64| -> f64 {
        let f = &floor.field;
        (0..f.thickness().len() as u32)
            .filter(|&c| {
                let (u, v) = f.cell_center(c);
                let p = floor.chart.point(u, v, 0.0);
                (p.x - x0).hypot(p.y) < 0.4
            })
            .map(|c| f.thickness()[c as usize] * f.cell_area())
            .sum()
    };
    // Half the spraying time at each pose: about equal volumes in both spots.
    let (first, second) = (around(0.0), around(0.7));
    assert!(
        first > 0.0 && (second / first - 1.0).abs() < 0.2,
        "{first} m³ under the first pose, {second} m³ under the second"
    );
    assert_eq!(sim.nozzle().waypoints()[0].position, DVec3::new(0.7, 0.0, 1.0));
}

#[test]
fn a_snapshot_continues_exactly_as_the_original() {
    let law: Arc<dyn ReboundLaw> = Arc::new(PolynomialRebound { coefficients: vec![0.5] });
    let mut sim = Simulation::new(scene(law, 0.12)).expect("valid");
    for _ in 0..40 {
        sim.step();
    }
    let mut branch = sim.clone();
    sim.run(|_| {});
    branch.run(|_| {});
    let (a, b) = (&sim.targets()[0].surface, &branch.targets()[0].surface);
    assert_eq!(a.thickness(), b.thickness());
    assert_eq!(sim.metrics().fates.in_flight, branch.metrics().fates.in_flight);
    assert_eq!(sim.swarm(), branch.swarm());
}

#[test]
fn the_configuration_is_checked_before_a_run() {
    let mut c = SimulationConfig::example_wall(0.1);
    c.dt = f64::NAN;
    let err = Simulation::new(c).expect_err("NaN step refused");
    assert!(err.to_string().contains("`dt`"), "{err}");
    let mut c = SimulationConfig::example_wall(0.1);
    c.obstacles.push(ObstacleConfig {
        name: "wall".into(),
        shapes: vec![],
        impact: c.targets[0].impact.clone(),
    });
    assert!(Simulation::new(c).expect_err("duplicate name").to_string().contains("twice"));
}

#[test]
fn every_built_in_shape_gives_viewers_triangles_on_itself_and_one_from_outside_may_give_none() {
    let (around, extent) = (DVec3::new(0.3, -0.2, 0.4), 5.0);
    let plane = Plane { point: DVec3::new(0.0, 0.0, 0.2), normal: DVec3::new(0.0, 0.6, 0.8) };
    let bounded = [
        Shape::Face(Face::new(DVec3::new(1.0, 2.0, 3.0), DVec3::new(0.3, 1.0, 0.2), DVec3::Z, [0.7, 1.3])),
        Shape::Disk(Disk { center: DVec3::X, normal: DVec3::new(0.6, 0.0, 0.8), radius: 0.4 }),
        Shape::Sphere(Sphere { center: DVec3::new(-1.0, 0.5, 2.0), radius: 0.2 }),
        Shape::Box(OrientedBox {
            center: DVec3::new(0.1, 0.2, 0.3),
            axes: [DVec3::X, DVec3::new(0.0, 0.6, 0.8), DVec3::new(0.0, -0.8, 0.6)],
            half_extents: DVec3::new(0.1, 0.4, 0.2),
        }),
        Shape::Cylinder(Cylinder {
            a: DVec3::new(0.0, -1.0, 0.3),
            b: DVec3::new(0.2, 1.0, 0.5),
            radius: 0.01,
        }),
        Shape::Triangle(Triangle::new(DVec3::ZERO, DVec3::X, DVec3::new(0.2, 0.9, 0.1)).expect("a triangle")),
        Shape::Shell(
            CylinderShell::new(DVec3::ZERO, DVec3::Y, DVec3::X, 3.0, 4.0, [0.3, 2.5]).expect("a shell"),
        ),
    ];
    for shape in bounded.iter().chain([&Shape::Plane(plane)]) {
        let t = shape.tessellate(around, extent).unwrap_or_else(|| panic!("{shape:?} gives no triangles"));
        assert!(!t.triangles.is_empty() && t.normals.len() == t.positions.len(), "{shape:?}");
        assert!(t.triangles.iter().flatten().all(|&i| (i as usize) < t.positions.len()), "{shape:?}");
        assert!(t.normals.iter().all(|n| n.length() > 0.0), "{shape:?}");
        for &p in &t.positions {
            match shape.aabb() {
                Some(b) => assert!(b.inflate(1e-9).contains(p), "{shape:?}: {p} outside its box"),
                // The plane: a square on it within `extent` of `around`.
                None => assert!(
                    (p - plane.point).dot(plane.normal).abs() < 1e-9 && (p - around).length() < 2.0 * extent
                ),
            }
        }
    }
    // The ledge says nothing of its looks: a viewer draws the edges of its box.
    let ledge = Shape::Custom(Arc::new(Ledge { z: 0.5, half: 0.05 }));
    assert!(ledge.tessellate(around, extent).is_none() && ledge.aabb().is_some());
}
