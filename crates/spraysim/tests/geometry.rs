//! Collision primitives against brute-force references, and the no-tunnelling property.

use glam::DVec3;
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use spraysim::collision::{
    Cylinder, CylinderShell, Disk, Face, OrientedBox, Plane, Primitive, Shape, Sphere, Triangle,
};

/// Samples per segment of the brute-force reference.
const SAMPLES: usize = 20_000;

fn rand_vec(rng: &mut ChaCha8Rng, scale: f64) -> DVec3 {
    DVec3::new(
        rng.random_range(-scale..scale),
        rng.random_range(-scale..scale),
        rng.random_range(-scale..scale),
    )
}

fn rand_dir(rng: &mut ChaCha8Rng) -> DVec3 {
    loop {
        let v = rand_vec(rng, 1.0);
        if v.length() > 0.1 && v.length() <= 1.0 {
            return v.normalize();
        }
    }
}

/// Signed distance to the plane of a thin shape and whether a point on that plane lies in it.
fn thin_parts(shape: &Shape) -> (DVec3, DVec3, Box<dyn Fn(DVec3) -> bool + '_>) {
    match shape {
        Shape::Plane(p) => (p.point, p.normal, Box::new(|_| true)),
        Shape::Face(f) => (
            f.center,
            f.normal,
            Box::new(move |q| {
                let (u, v) = f.local(q);
                u.abs() <= f.half_width && v.abs() <= f.half_height
            }),
        ),
        Shape::Disk(d) => (d.center, d.normal, Box::new(move |q| (q - d.center).length() <= d.radius)),
        Shape::Triangle(t) => (
            t.corners[0],
            t.normal,
            // Barycentric coordinates, independent of the engine's edge tests.
            Box::new(move |q| {
                let [a, b, c] = t.corners;
                let (v0, v1, v2) = (b - a, c - a, q - a);
                let (d00, d01, d11, d20, d21) = (v0.dot(v0), v0.dot(v1), v1.dot(v1), v2.dot(v0), v2.dot(v1));
                let den = d00 * d11 - d01 * d01;
                let (v, w) = ((d11 * d20 - d01 * d21) / den, (d00 * d21 - d01 * d20) / den);
                v >= -1e-12 && w >= -1e-12 && v + w <= 1.0 + 1e-12
            }),
        ),
        _ => unreachable!("not a thin shape"),
    }
}

/// First fraction of the segment at which the brute-force walk finds the shape.
fn brute_force(shape: &Shape, p0: DVec3, p1: DVec3) -> Option<f64> {
    let at = |k: usize| p0.lerp(p1, k as f64 / SAMPLES as f64);
    match shape {
        Shape::Plane(_) | Shape::Face(_) | Shape::Disk(_) | Shape::Triangle(_) => {
            let (c, n, within) = thin_parts(shape);
            let mut prev = (p0 - c).dot(n);
            for k in 1..=SAMPLES {
                let d = (at(k) - c).dot(n);
                if prev.signum() != d.signum() || d == 0.0 {
                    // Locate the crossing between samples and test it against the bounds.
                    let t = (k as f64 - 1.0 + prev / (prev - d)) / SAMPLES as f64;
                    if within(p0.lerp(p1, t)) {
                        return Some(t);
                    }
                }
                prev = d;
            }
            None
        }
        Shape::Shell(sh) => {
            // Distance to the axis against the radius, and the bounds in angle and length.
            let f = |q: DVec3| {
                let d = q - sh.center;
                (d - sh.axis * d.dot(sh.axis)).length() - sh.radius
            };
            let mut prev = f(p0);
            for k in 1..=SAMPLES {
                let d = f(at(k));
                if prev.signum() != d.signum() || d == 0.0 {
                    // The distance to the axis is not linear along the segment: bisect.
                    let (mut a, mut b) = ((k - 1) as f64 / SAMPLES as f64, k as f64 / SAMPLES as f64);
                    for _ in 0..60 {
                        let m = 0.5 * (a + b);
                        if f(p0.lerp(p1, m)).signum() == prev.signum() {
                            a = m;
                        } else {
                            b = m;
                        }
                    }
                    let t = 0.5 * (a + b);
                    let (theta, z, _) = sh.coordinates(p0.lerp(p1, t));
                    if sh.covers(theta, z) {
                        return Some(t);
                    }
                }
                prev = d;
            }
            None
        }
        _ => (0..=SAMPLES).find(|&k| shape.contains(at(k))).map(|k| k as f64 / SAMPLES as f64),
    }
}

/// The kinds of primitive the brute-force tests draw; a kind's number seeds its draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Plane = 0,
    Face = 1,
    Disk = 2,
    Sphere = 3,
    Box = 4,
    Cylinder = 5,
    Triangle = 6,
    CylinderShell = 7,
}

impl Kind {
    /// Every kind, in the order of their numbers.
    const ALL: [Kind; 8] = [
        Kind::Plane,
        Kind::Face,
        Kind::Disk,
        Kind::Sphere,
        Kind::Box,
        Kind::Cylinder,
        Kind::Triangle,
        Kind::CylinderShell,
    ];

    /// The seed of this kind's draws, `offset` plus its number.
    fn seed(self, offset: u64) -> u64 {
        self as u64 + offset
    }
}

/// A shape of `kind` near the origin, its size, orientation and place drawn from `rng`.
fn random_shape(rng: &mut ChaCha8Rng, kind: Kind) -> Shape {
    let c = rand_vec(rng, 0.3);
    match kind {
        Kind::Plane => Shape::Plane(Plane { point: c, normal: rand_dir(rng) }),
        Kind::Face => {
            let n = rand_dir(rng);
            let up = n.any_orthonormal_vector();
            Shape::Face(Face::new(
                c,
                n,
                up + 0.3 * rand_vec(rng, 1.0).reject_from(n),
                [rng.random_range(0.1..1.0), rng.random_range(0.1..1.0)],
            ))
        }
        Kind::Disk => {
            Shape::Disk(Disk { center: c, normal: rand_dir(rng), radius: rng.random_range(0.05..0.6) })
        }
        Kind::Sphere => Shape::Sphere(Sphere { center: c, radius: rng.random_range(0.05..0.6) }),
        Kind::Box => {
            let x = rand_dir(rng);
            let y = rand_dir(rng).reject_from(x).normalize();
            Shape::Box(OrientedBox {
                center: c,
                axes: [x, y, x.cross(y)],
                half_extents: DVec3::new(
                    rng.random_range(0.05..0.5),
                    rng.random_range(0.05..0.5),
                    rng.random_range(0.05..0.5),
                ),
            })
        }
        Kind::Cylinder => Shape::Cylinder(Cylinder {
            a: c,
            b: c + rand_dir(rng) * rng.random_range(0.1..1.0),
            radius: rng.random_range(0.02..0.4),
        }),
        Kind::Triangle => loop {
            if let Some(t) =
                Triangle::new(c + rand_vec(rng, 0.9), c + rand_vec(rng, 0.9), c + rand_vec(rng, 0.9))
            {
                break Shape::Triangle(t);
            }
        },
        Kind::CylinderShell => {
            let start = rng.random_range(-3.0..3.0);
            let span = rng.random_range(0.5..std::f64::consts::TAU);
            let shell = CylinderShell::new(
                c,
                rand_dir(rng),
                rand_dir(rng),
                rng.random_range(0.1..0.8),
                rng.random_range(0.2..1.5),
                [start, start + span],
            );
            Shape::Shell(shell.unwrap_or_else(|| panic!("a valid shell")))
        }
    }
}

/// 1000 segments against random shapes of `kind`: the exact hit is the brute-force walk's.
fn check_against_brute_force(kind: Kind) {
    let mut rng = ChaCha8Rng::seed_from_u64(kind.seed(100));
    let mut hits = 0;
    for _ in 0..1000 {
        let shape = random_shape(&mut rng, kind);
        let p0 = rand_vec(&mut rng, 1.5);
        if shape.contains(p0) {
            continue;
        }
        // Aim near the shape so that most segments test something.
        let aim = shape.aabb().map_or(DVec3::ZERO, |b| (b.min + b.max) / 2.0) + rand_vec(&mut rng, 0.4);
        let p1 = p0 + (aim - p0) * rng.random_range(0.3..2.0);
        let exact = shape.intersect(p0, p1);
        let reference = brute_force(&shape, p0, p1);
        let step = 1.0 / SAMPLES as f64;
        match (exact, reference) {
            (Some(h), Some(t)) => {
                hits += 1;
                assert!(
                    h.t <= t + 1e-9 && h.t >= t - 2.0 * step,
                    "{kind:?} {shape:?}: t = {} but brute force {t}",
                    h.t
                );
                assert!(h.point.distance(p0.lerp(p1, h.t)) < 1e-9);
                assert!((h.normal.length() - 1.0).abs() < 1e-9);
                assert!(
                    h.normal.dot(p1 - p0) <= 1e-12,
                    "{kind:?} {shape:?}: normal does not face the incoming segment"
                );
            }
            (None, Some(t)) => panic!("{kind:?} {shape:?}: missed a hit at t = {t} from {p0} to {p1}"),
            (Some(h), None) => {
                // Thin surfaces: the sign-change reference is exact, so this is a false hit.
                let thin = matches!(
                    shape,
                    Shape::Plane(_) | Shape::Face(_) | Shape::Disk(_) | Shape::Triangle(_) | Shape::Shell(_)
                );
                assert!(!thin, "{kind:?} {shape:?}: a hit at t = {} the reference does not see", h.t);
                // Solids: a grazing chord shorter than the sampling step.
                let ahead = p0.lerp(p1, (h.t + 2.0 * step).min(1.0));
                assert!(
                    !shape.contains(ahead),
                    "{kind:?} {shape:?}: brute force found no hit, algebra found t = {}",
                    h.t
                );
            }
            (None, None) => {}
        }
    }
    assert!(hits > 100, "{kind:?}: too few hits ({hits}) to test anything");
}

#[test]
fn plane_matches_brute_force() {
    check_against_brute_force(Kind::Plane);
}

#[test]
fn face_matches_brute_force() {
    check_against_brute_force(Kind::Face);
}

#[test]
fn disk_matches_brute_force() {
    check_against_brute_force(Kind::Disk);
}

#[test]
fn sphere_matches_brute_force() {
    check_against_brute_force(Kind::Sphere);
}

#[test]
fn box_matches_brute_force() {
    check_against_brute_force(Kind::Box);
}

#[test]
fn cylinder_matches_brute_force() {
    check_against_brute_force(Kind::Cylinder);
}

#[test]
fn triangle_matches_brute_force() {
    check_against_brute_force(Kind::Triangle);
}

#[test]
fn cylinder_shell_matches_brute_force() {
    check_against_brute_force(Kind::CylinderShell);
}

#[test]
fn cylinder_hit_on_mantle_and_cap_has_the_right_normal() {
    let c = Shape::Cylinder(Cylinder { a: DVec3::ZERO, b: DVec3::new(1.0, 0.0, 0.0), radius: 0.1 });
    let side = c.intersect(DVec3::new(0.5, -1.0, 0.0), DVec3::new(0.5, 1.0, 0.0)).expect("mantle hit");
    assert!((side.t - 0.45).abs() < 1e-12 && side.normal.abs_diff_eq(-DVec3::Y, 1e-12));
    let cap = c.intersect(DVec3::new(-1.0, 0.05, 0.0), DVec3::new(1.0, 0.05, 0.0)).expect("cap hit");
    assert!((cap.t - 0.5).abs() < 1e-12 && cap.normal.abs_diff_eq(-DVec3::X, 1e-12));
}

/// The closed primitives: what a segment must never pass through.
const SOLIDS: &[Kind] = &[Kind::Sphere, Kind::Box, Kind::Cylinder];

/// A solid of `kind` (one of [`SOLIDS`]) at `c`, of size `r` (m), its axis along `dir`.
fn solid(kind: Kind, c: DVec3, r: f64, dir: DVec3) -> Shape {
    match kind {
        Kind::Sphere => Shape::Sphere(Sphere { center: c, radius: r }),
        Kind::Box => {
            let x = dir.normalize();
            let y = x.any_orthonormal_vector();
            Shape::Box(OrientedBox {
                center: c,
                axes: [x, y, x.cross(y)],
                half_extents: DVec3::new(r, r * 0.5, r * 1.5),
            })
        }
        Kind::Cylinder => Shape::Cylinder(Cylinder { a: c, b: c + dir.normalize() * 3.0 * r, radius: r }),
        other => unreachable!("{other:?} is not a solid"),
    }
}

fn vec3() -> impl Strategy<Value = DVec3> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// A segment from outside a closed primitive that reports no hit never enters it; one that
    /// reports a hit touches the surface there, and moving back along the normal is outside.
    #[test]
    fn segments_never_pass_through_solids(
        kind in proptest::sample::select(SOLIDS), c in vec3(), r in 0.01..0.5f64, dir in vec3(), p0 in vec3(), d in vec3(), scale in 0.01..4.0f64,
    ) {
        prop_assume!(dir.length() > 1e-3);
        let shape = solid(kind, c, r, dir);
        prop_assume!(!shape.contains(p0));
        let p1 = p0 + d * scale;
        match shape.intersect(p0, p1) {
            None => {
                for k in 0..=2000 {
                    let q = p0.lerp(p1, k as f64 / 2000.0);
                    prop_assert!(!shape.contains(q), "passed through {:?} at {}", shape, q);
                }
            }
            Some(h) => {
                prop_assert!((0.0..=1.0).contains(&h.t));
                prop_assert!(!shape.contains(h.point + h.normal * 1e-9));
                for k in 0..200 {
                    let q = p0.lerp(h.point, k as f64 / 200.0);
                    prop_assert!(!shape.contains(q), "entered {:?} before the reported hit", shape);
                }
            }
        }
    }
}

/// The kinds of the obstacles of [`indexed_scene_query_matches_the_linear_scan`], in turn.
const MIXED: [Kind; 5] = [Kind::Face, Kind::Disk, Kind::Sphere, Kind::Box, Kind::Cylinder];

/// The grid-accelerated query returns exactly what testing every surface returns.
#[test]
fn indexed_scene_query_matches_the_linear_scan() {
    use spraysim::collision::{Aabb, Scene, SurfaceKind, SurfaceRef};
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    for scene_no in 0..20 {
        let surfaces: Vec<SurfaceRef> = (0..200)
            .map(|i| SurfaceRef {
                shape: random_shape(&mut rng, MIXED[i % MIXED.len()]),
                kind: SurfaceKind::Obstacle(i),
                piece: 0,
                impact: 0,
                layer: 0.0,
            })
            .chain(std::iter::once(SurfaceRef {
                shape: Shape::Plane(Plane { point: DVec3::new(0.0, 0.0, -0.9), normal: DVec3::Z }),
                kind: SurfaceKind::Obstacle(200),
                piece: 0,
                impact: 0,
                layer: 0.0,
            }))
            .collect();
        // Bounds smaller than the scene in some runs: the query must not depend on them.
        let half = if scene_no % 2 == 0 { 2.0 } else { 0.5 };
        let scene = Scene::new(surfaces, Aabb { min: DVec3::splat(-half), max: DVec3::splat(half) });
        let mut hits = 0;
        for k in 0..2000 {
            let p0 = rand_vec(&mut rng, 1.2);
            let len = if k % 3 == 0 { 2.5 } else { 0.05 };
            let p1 = p0 + rand_vec(&mut rng, len);
            let fast = scene.first_hit(p0, p1);
            let slow = scene.first_hit_linear(p0, p1);
            assert_eq!(fast.map(|(i, h)| (i, h.t)), slow.map(|(i, h)| (i, h.t)), "{p0} → {p1}");
            if fast.is_none() {
                assert!(scene.is_clear(p0, p1) || slow.is_none());
            } else {
                hits += 1;
                assert!(!scene.is_clear(p0, p1), "a segment that hits was called clear");
            }
        }
        assert!(hits > 200, "{hits}");
    }
}

/// Exact arc hits against a reference that walks the arc as 4000 short chords.
#[test]
fn arc_hits_match_a_dense_polyline_for_every_primitive() {
    use spraysim::collision::Flight;
    const CHORDS: usize = 4000;
    for kind in Kind::ALL {
        let mut rng = ChaCha8Rng::seed_from_u64(kind.seed(500));
        let mut hits = 0;
        for _ in 0..2500 {
            let shape = random_shape(&mut rng, kind);
            let x0 = rand_vec(&mut rng, 1.5);
            if shape.contains(x0) {
                continue;
            }
            let aim = shape.aabb().map_or(DVec3::ZERO, |b| (b.min + b.max) / 2.0) + rand_vec(&mut rng, 0.4);
            // Strongly curved: the acceleration bends the path by up to a metre over the arc.
            let arc = Flight {
                x0,
                v0: (aim - x0) * rng.random_range(0.5..2.0),
                g: rand_vec(&mut rng, 4.0),
                duration: 1.0,
            };
            let exact = shape.intersect_arc(&arc);
            let reference = (0..CHORDS).find_map(|k| {
                let (a, b) = (k as f64 / CHORDS as f64, (k + 1) as f64 / CHORDS as f64);
                shape.intersect(arc.at(a), arc.at(b)).map(|h| a + h.t / CHORDS as f64)
            });
            match (exact, reference) {
                (Some(h), Some(t)) => {
                    hits += 1;
                    assert!((h.t - t).abs() < 2e-3, "{kind:?} {shape:?}: exact {} vs polyline {t}", h.t);
                    assert!(h.point.distance(arc.at(h.t)) < 1e-9);
                    assert!(h.normal.dot(arc.velocity(h.t)) <= 1e-9, "normal does not face the particle");
                }
                (None, Some(t)) => {
                    // Only a chord cutting a corner the arc itself misses may differ.
                    let mid = arc.at(t);
                    assert!(!shape.contains(mid), "{kind:?} {shape:?}: the exact test missed a hit at {t}");
                }
                (Some(h), None) => {
                    let ahead = arc.at((h.t + 2.0 / CHORDS as f64).min(1.0));
                    assert!(
                        !shape.contains(ahead),
                        "{kind:?} {shape:?}: polyline found nothing, exact {}",
                        h.t
                    );
                }
                (None, None) => {}
            }
        }
        assert!(hits > 100, "{kind:?}: only {hits} hits");
    }
}
