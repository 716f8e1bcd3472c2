//! Triangle-mesh obstacles from OBJ and STL files.

use spraysim::collision::Primitive;
use spraysim::scenario::scenes::{NOZZLE_AT_WALL, refusal, triangle_stl, wall, wall_scene};
use spraysim::{Metrics, Scenario, Simulation};
use std::path::Path;

/// Corners of a cube of side 0.2 m centred at (−0.3, 0, 1) and its 12 outward triangles.
fn cube() -> (Vec<[f64; 3]>, Vec<[usize; 3]>) {
    let (c, h) = ([-0.3, 0.0, 1.0], 0.1);
    let v: Vec<[f64; 3]> = (0..8)
        .map(|i| {
            let s = |bit: usize| if i >> bit & 1 == 1 { h } else { -h };
            [c[0] + s(0), c[1] + s(1), c[2] + s(2)]
        })
        .collect();
    let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let tris = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
    (v, tris)
}

fn write_obj(path: &Path) {
    let (v, t) = cube();
    let mut s = String::new();
    for p in &v {
        s.push_str(&format!("v {} {} {}\n", p[0], p[1], p[2]));
    }
    for f in &t {
        s.push_str(&format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1));
    }
    std::fs::write(path, s).expect("write obj");
}

fn write_stl(path: &Path) {
    let (v, t) = cube();
    let mut s = String::from("solid cube\n");
    for f in &t {
        s.push_str("facet normal 0 0 0\nouter loop\n");
        for &i in f {
            s.push_str(&format!("vertex {} {} {}\n", v[i][0], v[i][1], v[i][2]));
        }
        s.push_str("endloop\nendfacet\n");
    }
    s.push_str("endsolid cube\n");
    std::fs::write(path, s).expect("write stl");
}

/// Grit blasted for 0.3 s from the nozzle at the wall (64 × 64 cells) past an obstacle named
/// `block` whose other keys are `obstacle` (TOML).
fn scene(obstacle: &str) -> String {
    format!(
        r#"
        [simulation]
        duration = 0.3
        [process]
        preset = "blasting"
        {NOZZLE_AT_WALL}{wall}
        [[obstacle]]
        name = "block"
        {obstacle}
        "#,
        wall = wall().resolution(64, 64),
    )
}

fn run(path: &Path) -> (Simulation, Metrics) {
    let sc = Scenario::from_path(path).unwrap_or_else(|e| panic!("{e}"));
    let mut sim = sc.build().expect("valid");
    let block = spraysim::collision::Shape::Box(spraysim::collision::OrientedBox {
        center: glam::DVec3::new(-0.3, 0.0, 1.0),
        axes: [glam::DVec3::X, glam::DVec3::Y, glam::DVec3::Z],
        half_extents: glam::DVec3::splat(0.1),
    });
    while !sim.is_finished() {
        sim.step();
        for (p, _, _) in sim.in_flight() {
            assert!(!block.contains(p), "a grain inside the mesh at {p}");
        }
    }
    let m = sim.metrics();
    (sim, m)
}

#[test]
fn a_closed_mesh_stops_grit_like_the_box_it_describes() {
    let tmp = tempfile::tempdir().expect("tempdir");
    write_obj(&tmp.path().join("cube.obj"));
    write_stl(&tmp.path().join("cube.stl"));
    let obj = tmp.path().join("obj.toml");
    std::fs::write(&obj, scene("shape = \"mesh\"\nfile = \"cube.obj\"")).expect("write");
    let stl = tmp.path().join("stl.toml");
    std::fs::write(&stl, scene("shape = \"mesh\"\nfile = \"cube.stl\"")).expect("write");
    let boxed = tmp.path().join("box.toml");
    std::fs::write(&boxed, scene("shape = \"box\"\ncenter = [-0.3, 0.0, 1.0]\nsize = [0.2, 0.2, 0.2]"))
        .expect("write");
    let (_, from_obj) = run(&obj);
    let (_, from_stl) = run(&stl);
    let (_, from_box) = run(&boxed);
    assert!(from_obj.obstacles[0].hits > 1000);
    // The same triangles from either format: the same run.
    assert_eq!(from_obj.obstacles[0].hits, from_stl.obstacles[0].hits);
    assert_eq!(from_obj.targets[0].hits, from_stl.targets[0].hits);
    // The box and its mesh shade the wall alike (binomial spread of the grains' fates).
    let n = from_box.emitted.count as f64;
    let (a, b) = (from_obj.targets[0].hits as f64 / n, from_box.targets[0].hits as f64 / n);
    assert!((a - b).abs() < 5.0 * (a * (1.0 - a) / n).sqrt() + 0.01, "mesh {a} vs box {b}");
}

#[test]
fn a_bad_mesh_file_is_refused_with_its_key() {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("broken.obj"), "v 0 0 0\nf 1 2 3\n").expect("write");
    for (file, expect) in
        [("missing.stl", "missing.stl"), ("broken.obj", "broken.obj"), ("cube.ply", "unknown mesh format")]
    {
        let path = tmp.path().join("s.toml");
        std::fs::write(&path, scene(&format!("shape = \"mesh\"\nfile = \"{file}\""))).expect("write");
        let err = Scenario::from_path(&path).expect_err("refused").to_string();
        assert!(err.contains("`obstacle[0].file`") && err.contains(expect), "{err}");
    }
}

#[test]
fn a_mesh_beyond_the_coordinate_limit_is_refused_and_the_widest_accepted_one_runs() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let wall = wall_scene(0.05, 32);
    for (name, corners, scale) in [
        ("huge.stl", [[-1e30, 0.0, 0.0], [1e30, 0.0, 0.0], [0.0, 0.0, 1e30]], 1.0),
        ("big.stl", [[-1e9, 0.0, 0.0], [1e10, 0.0, 0.0], [0.0, 0.0, 1e9]], 1.0),
        ("scaled.stl", [[-1e4, 0.0, 0.0], [1e4, 0.0, 0.0], [0.0, 0.0, 1e4]], 1e6),
    ] {
        std::fs::write(tmp.path().join(name), triangle_stl(corners)).expect("write");
        let text = format!(
            "{wall}\n[[obstacle]]\nname = \"o\"\nshape = \"mesh\"\nfile = \"{name}\"\nscale = {scale:e}\n"
        );
        std::fs::write(tmp.path().join("s.toml"), text).expect("write");
        let (key, message) = refusal(Scenario::from_path(&tmp.path().join("s.toml")), name);
        assert_eq!(key, "obstacle[0].file", "{name}");
        assert!(message.contains("must lie within"), "{name}: {message}");
    }
    // The largest accepted extent, a mesh 2 × 10⁴ m wide, runs (and its broad phase is small:
    // the cap on cells is tested in the engine, the memory in tests/property.rs).
    let corners = [[-1e4, -1e4, 0.0], [1e4, -1e4, 0.0], [0.0, 1e4, 0.0]];
    std::fs::write(tmp.path().join("wide.stl"), triangle_stl(corners)).expect("write");
    let text = format!("{wall}\n[[obstacle]]\nname = \"o\"\nshape = \"mesh\"\nfile = \"wide.stl\"\n");
    std::fs::write(tmp.path().join("s.toml"), text).expect("write");
    let sc = Scenario::from_path(&tmp.path().join("s.toml")).expect("accepted");
    let mut sim = sc.build().expect("builds");
    for _ in 0..5 {
        sim.step();
    }
    assert!(sim.swarm().alive() > 0);
}

#[test]
fn a_binary_stl_whose_facet_count_disagrees_with_its_length_is_refused() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let mut stl = vec![0u8; 80];
    stl.extend_from_slice(&3u32.to_le_bytes()); // says 3 facets…
    stl.extend_from_slice(&[0u8; 12]);
    for c in [0.0f32, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 2.0] {
        stl.extend_from_slice(&c.to_le_bytes());
    }
    stl.extend_from_slice(&[0u8; 2]);
    stl.extend_from_slice(&[7u8; 60]); // …but holds one and some bytes
    std::fs::write(tmp.path().join("m.stl"), &stl).expect("write");
    let text =
        format!("{}\n[[obstacle]]\nname = \"o\"\nshape = \"mesh\"\nfile = \"m.stl\"\n", wall_scene(0.05, 32));
    std::fs::write(tmp.path().join("s.toml"), text).expect("write");
    let (key, message) = refusal(Scenario::from_path(&tmp.path().join("s.toml")), "wrong count");
    assert_eq!(key, "obstacle[0].file");
    assert!(message.contains("counts 3 facets"), "{message}");
}
