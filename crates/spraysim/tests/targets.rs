//! Deposition on real parts: cylinder shells, meshes and faces with openings, against closed
//! forms and against each other; their metrics and 3D exports.

use glam::DVec3;
use spraysim::Scenario;
use spraysim::deposit::{DepositSurface, Surface};
use spraysim::scenario::scenes::wall;
use spraysim_validate::chi2_limit as chi2_limit_for;
use spraysim_validate::targets::{shell_cos3, sphere_cos3};
use std::fmt::Write as _;
use std::path::Path;

#[test]
fn the_cos3_law_holds_on_a_cylinder_shell_seen_from_its_axis() {
    let r = shell_cos3(1e5, 0);
    let dof = r.angles.len();
    assert!(r.chi2 < chi2_limit_for(dof), "χ² {} over {dof} rings: {r:?}", r.chi2);
    assert!(r.volume_error.abs() < 1e-9, "{}", r.volume_error);
}

#[test]
fn the_cos3_law_holds_on_a_triangulated_sphere_section() {
    let r = sphere_cos3(1e5, 0);
    let dof = r.angles.len();
    assert!(r.chi2 < chi2_limit_for(dof), "χ² {} over {dof} rings: {r:?}", r.chi2);
    assert!(r.volume_error.abs() < 1e-9, "{}", r.volume_error);
}

/// An ASCII STL of a `size` m square plate at height `z`, facing +z, of `n × n` squares cut in
/// two triangles each (row-major from the −x, −y corner; the first triangle of a square is the
/// one against its bottom edge).
fn plate_stl(size: f64, n: usize, z: f64) -> String {
    let mut out = String::from("solid plate\n");
    let h = size / n as f64;
    let p = |i: usize, j: usize| (-size / 2.0 + i as f64 * h, -size / 2.0 + j as f64 * h);
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
            for tri in [[a, b, c], [a, c, d]] {
                out.push_str("facet normal 0 0 1\nouter loop\n");
                for (x, y) in tri {
                    let _ = writeln!(out, "vertex {x} {y} {z}");
                }
                out.push_str("endloop\nendfacet\n");
            }
        }
    }
    out.push_str("endsolid plate\n");
    out
}

/// Paint sprayed straight down for 0.5 s from 0.3 m onto the target `target` (TOML).
fn painted(target: &str, dir: &Path) -> spraysim::Simulation {
    let text = format!(
        r#"
        [simulation]
        duration = 0.5
        [process]
        preset = "painting"
        [emitter]
        spawn_rate = 400000.0
        cone_angle = 60.0
        [nozzle]
        position = [0.0, 0.0, 0.3]
        axis = [0.0, 0.0, -1.0]
        {target}
        "#
    );
    std::fs::write(dir.join("s.toml"), text).expect("write");
    let sc = Scenario::from_path(&dir.join("s.toml")).unwrap_or_else(|e| panic!("{e}"));
    let mut sim = sc.build().expect("valid");
    sim.run(|_| {});
    sim
}

#[test]
fn a_flat_mesh_and_the_same_rectangle_collect_the_same_layer() {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("plate.stl"), plate_stl(1.0, 50, 0.0)).expect("write");
    let mesh = painted("[[target]]\nname = \"plate\"\nshape = \"mesh\"\nfile = \"plate.stl\"", tmp.path());
    let rect = painted(
        "[[target]]\nname = \"plate\"\ncenter = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\nup = [0.0, 1.0, 0.0]\n\
         size = [1.0, 1.0]\nresolution = [50, 50]",
        tmp.path(),
    );
    let (m, r) = (mesh.metrics(), rect.metrics());
    // Mass-exact: Σ thickness × area is the stuck volume, on both.
    for (sim, metrics) in [(&mesh, &m), (&rect, &r)] {
        let layer = sim.targets()[0].surface.volume();
        let stuck = metrics.targets[0].stuck.volume;
        assert!((layer - stuck).abs() <= 1e-9 * stuck, "{layer} vs {stuck}");
    }
    // The same particles land: the two triangles of a square hold what its cell holds.
    let (tm, tr) = (mesh.targets()[0].surface.thickness(), rect.targets()[0].surface.thickness());
    let Surface::Rectangle(rs) = &rect.targets()[0].surface else { panic!("a rectangle") };
    let one = m.emitted.volume / m.emitted.count as f64 * 2500.0;
    let (mut worst, mut moved) = (0.0_f64, 0.0);
    for j in 0..50 {
        for i in 0..50 {
            // The rectangle's columns grow along right = up × normal = y × z = +x, rows along +y.
            let cell =
                rs.field.cell_at(-0.5 + (i as f64 + 0.5) / 50.0, -0.5 + (j as f64 + 0.5) / 50.0) as usize;
            let square = 0.5 * (tm[2 * (j * 50 + i)] + tm[2 * (j * 50 + i) + 1]);
            worst = worst.max((square - tr[cell]).abs() / one);
            moved += (square - tr[cell]).abs() / one;
        }
    }
    // A particle striking a shared edge (most of them near the nozzle's axis, over a corner
    // of four squares) may go to either side: a handful of particles of 2 × 10⁵.
    assert!(
        worst <= 10.0 && moved <= 1e-3 * m.emitted.count as f64,
        "worst square {worst}, moved {moved} particles"
    );
    // Statistics: the same mean, and within sampling noise the same spread and coverage.
    let (sm, sr) = (&m.targets[0].thickness, &r.targets[0].thickness);
    assert!((sm.mean - sr.mean).abs() <= 1e-9 * sr.mean, "{sm:?} vs {sr:?}");
    assert!((sm.cv - sr.cv).abs() < 0.05 * sr.cv, "{sm:?} vs {sr:?}");
    assert!((sm.covered_fraction - sr.covered_fraction).abs() < 0.02, "{sm:?} vs {sr:?}");
}

#[test]
fn material_passes_through_an_opening_and_lands_behind_it() {
    let text = format!(
        r#"
        [simulation]
        duration = 0.3
        [process]
        preset = "painting"
        [emitter]
        cone_angle = 20.0
        [nozzle]
        position = [-0.5, 0.0, 1.0]
        axis = [1.0, 0.0, 0.0]
        {wall}{behind}
        "#,
        wall = wall().resolution(100, 100).with("[[target.opening]]\ncenter = [0.0, 0.0]\nsize = [0.1, 0.1]"),
        behind = wall().named("behind").collector().at([0.5, 0.0, 1.0]).resolution(100, 100),
    );
    let sc = Scenario::from_toml(&text, "window").unwrap_or_else(|e| panic!("{e}"));
    let mut sim = sc.build().expect("valid");
    sim.run(|_| {});
    let m = sim.metrics();
    let (wall, behind) = (&sim.targets()[0], &sim.targets()[1]);
    // The 10 cm window passes the core of the jet; the wall keeps the rest, none of it in
    // the window's cells.
    assert!(
        m.targets[1].stuck.volume > 0.2 * m.emitted.volume
            && m.targets[0].stuck.volume > 0.2 * m.emitted.volume,
        "{m:?}"
    );
    let s = &wall.surface;
    let holes: Vec<u32> = (0..s.thickness().len() as u32).filter(|&c| s.cell_area(c) == 0.0).collect();
    assert_eq!(holes.len(), 25, "5 × 5 cells of 2 cm lie in the window");
    assert!(holes.iter().all(|&c| s.thickness()[c as usize] == 0.0));
    // Behind the wall, only the window's shadow: a spot about the window's size.
    let t = behind.surface.thickness();
    let far = (0..t.len() as u32)
        .filter(|&c| t[c as usize] > 0.0)
        .map(|c| behind.surface.point_above(c, 0.0))
        .fold(0.0_f64, |a, p| a.max((p - DVec3::new(0.5, 0.0, 1.0)).length()));
    assert!(far < 0.1 * 1.0 / 0.5 + 0.03, "deposit reaches {far} m from the window's axis");
    let b = &m.volume_balance;
    assert!(b.residual.abs() <= 1e-6 * b.emitted, "{b:?}");
    // The wall's metrics cover its surface only.
    assert!((m.targets[0].thickness.area - (4.0 - 0.01)).abs() < 1e-9, "{:?}", m.targets[0].thickness);
}

#[test]
fn the_default_domain_covers_a_mesh_target_far_from_the_nozzle() {
    let tmp = tempfile::tempdir().expect("tempdir");
    // A plate 20 m up, sprayed from 1 m below it: without [domain], the particles must reach it.
    std::fs::write(tmp.path().join("high.stl"), plate_stl(1.0, 4, 20.0)).expect("write");
    let text = r#"
        [simulation]
        duration = 0.3
        gravity = [0.0, 0.0, 0.0]
        [process]
        preset = "painting"
        [nozzle]
        position = [0.0, 0.0, 19.0]
        axis = [0.0, 0.0, 1.0]
        [[target]]
        name = "high"
        shape = "mesh"
        file = "high.stl"
        side = "back"
        "#;
    std::fs::write(tmp.path().join("s.toml"), text).expect("write");
    let sc = Scenario::from_path(&tmp.path().join("s.toml")).unwrap_or_else(|e| panic!("{e}"));
    let d = sc.domain();
    assert!(d.max[2] >= 21.0 - 1e-9 && d.min[2] <= 18.0 + 1e-9, "{d:?}");
    let mut sim = sc.build().expect("valid");
    sim.run(|_| {});
    let m = sim.metrics();
    // All of it on the plate, or still on its way there.
    assert_eq!(m.fates.left_domain.count, 0);
    assert_eq!(m.targets[0].stuck.count + m.fates.in_flight.count, m.emitted.count, "{:?}", m.fates);
}

#[test]
fn a_thick_layer_in_a_shaft_slumps_to_the_wall_limit_around_the_curve() {
    use spraysim::collision::CylinderShell;
    use spraysim::deposit::{CylinderSurface, ShellChart};
    use spraysim::process::layer::relax;
    // A vertical shaft of 1 m radius, lined inside, 4 mm cells around and along.
    let shell = CylinderShell::new(DVec3::ZERO, DVec3::Z, DVec3::X, 1.0, 0.4, [0.0, 0.5]).expect("valid");
    let cols = (0.5 / 0.004) as usize;
    let mut s = CylinderSurface::new(ShellChart { shell, inside: true }, cols, 100, 0.0);
    let cells = s.thickness().len() as u32;
    (0..cells).for_each(|c| s.add_thickness(c, 0.2));
    let before = s.volume();
    let r = relax(&mut s, 2300.0, DVec3::new(0.0, 0.0, -9.81), 2500.0, 100_000);
    assert!(r.settled);
    let ran_off: f64 = r.run_off.iter().map(|o| o.volume).sum();
    assert!((s.volume() + ran_off - before).abs() < 1e-12 * before);
    // Every column of a wall holds τ_y/(ρ g) = 110.8 mm, within the stage's 1 %. What ran off
    // went downwards, nearly all of it over the bottom edge (the free sides pass a little
    // diagonally).
    let a = 2500.0 / (2300.0 * 9.81);
    assert!(
        s.thickness().iter().all(|&t| t >= 0.99 * a * (1.0 - 1e-9) && t <= 1.01 * a),
        "{:?}",
        &s.thickness()[..5]
    );
    assert!(r.run_off.iter().all(|o| o.direction.z < -0.5), "{:?}", r.run_off.first());
    let bottom: f64 = r.run_off.iter().filter(|o| o.edge.z < -0.19).map(|o| o.volume).sum();
    assert!(bottom > 0.9 * ran_off, "{bottom} of {ran_off} m³ over the bottom edge");
    assert!((ran_off - (0.2 - a) * s.area_of(&(0..cells).collect::<Vec<_>>())).abs() < 0.02 * ran_off);
}

#[test]
fn thickness_statistics_weigh_by_area_report_the_share_in_spec_and_leave_out_the_margin() {
    use spraysim::collision::Face;
    use spraysim::deposit::RectangleSurface;
    use spraysim::metrics::ThicknessStats;
    // 1 m square of 1 cm cells: 10 mm within 0.4 m of the centre (in x and y), 2 mm outside.
    let face = Face::new(DVec3::ZERO, DVec3::Z, DVec3::Y, [1.0, 1.0]);
    let mut s = RectangleSurface::new(face, 100, 100, 0.0);
    for c in 0..10_000u32 {
        let p = s.point_above(c, 0.0);
        s.add_thickness(c, if p.x.abs() < 0.4 && p.y.abs() < 0.4 { 0.01 } else { 0.002 });
    }
    let all = ThicknessStats::of(&s, 1e-3, 0.0, Some([0.005, 0.015]), 1.0);
    assert!(
        (all.area - 1.0).abs() < 1e-9 && (all.in_tolerance.expect("band") - 0.64).abs() < 1e-9,
        "{all:?}"
    );
    assert!((all.mean - (0.64 * 0.01 + 0.36 * 0.002)).abs() < 1e-12);
    // A 0.1 m margin leaves the 0.8 m square only.
    let inner = ThicknessStats::of(&s, 1e-3, 0.1, Some([0.005, 0.015]), 1.0);
    assert!((inner.area - 0.64).abs() < 1e-9 && inner.in_tolerance == Some(1.0), "{inner:?}");
    assert!(inner.std_dev < 1e-12 && (inner.mean - 0.01).abs() < 1e-12);
}

#[test]
fn the_covered_mean_and_cv_leave_out_the_bare_cells() {
    use spraysim::collision::Face;
    use spraysim::deposit::RectangleSurface;
    use spraysim::metrics::ThicknessStats;
    // 1 m square of 1 cm cells: a 0.2 m × 0.2 m spot of 1 mm and 3 mm cells in a checkerboard
    // (mean 2 mm, standard deviation 1 mm), the rest bare.
    let face = Face::new(DVec3::ZERO, DVec3::Z, DVec3::Y, [1.0, 1.0]);
    let mut s = RectangleSurface::new(face, 100, 100, 0.0);
    for c in 0..10_000u32 {
        let p = s.point_above(c, 0.0);
        if p.x.abs() < 0.1 && p.y.abs() < 0.1 {
            s.add_thickness(c, if (c / 100 + c % 100) % 2 == 0 { 0.001 } else { 0.003 });
        }
    }
    let st = ThicknessStats::of(&s, 1e-4, 0.0, None, 1.0);
    assert!((st.deposited_mean - 0.002).abs() < 1e-12, "{st:?}");
    assert!((st.deposited_cv - 0.5).abs() < 1e-9, "{st:?}");
    // Over the whole square the mean is 4 % of that, and the CV is dominated by the bare cells.
    assert!((st.mean - 0.04 * 0.002).abs() < 1e-12 && st.cv > 4.0, "{st:?}");
}

/// The wall (2 m × 2 m, default cells) with one opening given by `opening` (TOML keys).
fn wall_with(opening: &str) -> Result<Scenario, String> {
    let text = wall().with(&format!("[[target.opening]]\n{opening}")).to_string();
    Scenario::from_toml(&text, "wall.toml").map_err(|e| e.to_string())
}

#[test]
fn an_opening_across_the_whole_face_is_accepted_and_one_off_it_is_refused() {
    // A slot from edge to edge: no corner on the face, no face corner in it.
    assert!(wall_with("center = [0.0, 0.3]\nsize = [3.0, 0.1]").is_ok());
    assert!(
        wall_with("shape = \"polygon\"\ncorners = [[-1.5, 0.0], [1.5, 0.0], [1.5, 0.1], [-1.5, 0.1]]")
            .is_ok()
    );
    let off = wall_with("center = [3.0, 0.0]\nsize = [0.5, 0.5]").expect_err("off the face");
    assert!(off.contains("target[0].opening[0].center") && off.contains("outside the face"), "{off}");
    let flat = wall_with("center = [0.0, 0.0]\nsize = [0.5, 0.0]").expect_err("no area");
    assert!(flat.contains("size"), "{flat}");
}
