//! Robot trajectories: raster passes and CSV tool paths.

use glam::{DQuat, DVec3};
use spraysim::Scenario;
use spraysim::collision::Face;
use spraysim::deposit::DepositSurface;
use spraysim::emission::{PassDirection, RasterPlan, raster, raster_waypoints};
use spraysim::scenario::scenes;

fn wall() -> Face {
    Face::new(DVec3::new(0.0, 0.0, 1.0), DVec3::new(-1.0, 0.0, 0.0), DVec3::Z, [2.0, 2.0])
}

#[test]
fn raster_runs_bottom_up_at_constant_speed_and_standoff() {
    let r = RasterPlan { size: [1.0, 0.6], step_over: 0.2, speed: 0.4, lead: 0.1, ..RasterPlan::default() };
    let w = raster_waypoints(&wall(), &r);
    // 4 passes (0, 0.2, 0.4, 0.6 m up) of 1.2 m, 3 turns of 0.2 m: 5.4 m at 0.4 m/s.
    assert!((w[w.len() - 1].time - 5.4 / 0.4).abs() < 1e-12);
    for pair in w.windows(2) {
        let speed = pair[0].position.distance(pair[1].position) / (pair[1].time - pair[0].time);
        assert!((speed - 0.4).abs() < 1e-9, "speed {speed}");
        assert!((pair[0].position.x + 1.0).abs() < 1e-12, "standoff");
        assert_eq!(pair[0].axis, DVec3::X);
    }
    assert!((w[0].position.z - 0.7).abs() < 1e-12, "starts at the bottom edge");
    assert!((w[0].position.y - 0.6).abs() < 1e-12, "starts at the left (right = −y), lead included");
    // Spraying on passes, not on turns.
    let spraying: Vec<bool> = w.iter().map(|p| p.spray).collect();
    assert_eq!(spraying, [true, false, true, false, true, false, true, false]);
    let vertical = raster_waypoints(&wall(), &RasterPlan { passes: PassDirection::Vertical, ..r });
    assert!((vertical[1].position.z - vertical[0].position.z).abs() > 0.5, "vertical passes run along up");
}

#[test]
fn circular_motion_circles_the_raster_line() {
    let r = RasterPlan {
        size: [1.0, 0.0],
        speed: 0.5,
        lead: 0.0,
        circle_radius: 0.05,
        circle_frequency: 2.0,
        ..RasterPlan::default()
    };
    let path = raster(&wall(), &r, 0.0);
    // One pass: its two ends, the circle superposed analytically.
    assert_eq!(path.waypoints().len(), 2);
    // Spraying until the pass ends at 2 s.
    for k in 0..200 {
        let t = 2.0 * f64::from(k) / 200.0;
        // Straight line at z = 1 moving along −y: the offset from it is a 5 cm circle.
        let (frame, spraying) = path.at(t);
        let line_y = 0.5 - 0.5 * t;
        let off = DVec3::new(0.0, frame.position.y - line_y, frame.position.z - 1.0);
        assert!(spraying && (off.length() - 0.05).abs() < 1e-12, "{off} at {t} s");
        assert!((path.travel_velocity(t) - DVec3::new(0.0, -0.5, 0.0)).length() < 1e-12);
    }
}

/// The wall's middle square metre, named `panel` (100 × 100 cells).
fn panel() -> scenes::Rectangle {
    scenes::wall().named("panel").size(1.0, 1.0).resolution(100, 100)
}

/// 2 s of painting onto the [`panel`], with `extra` (TOML) after it.
fn raster_scene(extra: &str) -> String {
    format!(
        r#"
        [simulation]
        duration = 2.0
        [process]
        preset = "painting"
        {panel}
        {extra}
        "#,
        panel = panel(),
    )
}

#[test]
fn a_raster_covers_its_rectangle_and_nothing_far_outside() {
    let sc = Scenario::from_toml(
        &raster_scene(
            "[nozzle.raster]\ntarget = \"panel\"\nsize = [0.6, 0.4]\nstandoff = 0.25\nspeed = 2.0\nstep_over = 0.1\nlead = 0.0",
        ),
        "raster",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let mut sim = sc.build().expect("valid");
    sim.run(|_| {});
    let t = sim.targets()[0].surface.thickness();
    let at = |u: f64, v: f64| t[((v + 0.5) * 100.0) as usize * 100 + ((u + 0.5) * 100.0) as usize];
    for (u, v) in [(0.0, 0.0), (0.25, 0.15), (-0.25, -0.15)] {
        assert!(at(u, v) > 0.0, "no paint at ({u}, {v})");
    }
    for (u, v) in [(0.0, 0.45), (0.45, 0.0), (-0.45, -0.45)] {
        assert_eq!(at(u, v), 0.0, "paint far outside the raster at ({u}, {v})");
    }
}

#[test]
fn a_csv_tool_path_and_the_same_waypoints_give_identical_outputs() {
    let tmp = tempfile::tempdir().expect("tempdir");
    // A pass along the panel, tilting the tool about its path, spray off for the last leg.
    let poses = [
        (0.0, [-0.3, 0.4, 1.0], DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2), true),
        (0.5, [-0.3, 0.0, 1.1], DQuat::from_rotation_y(1.4) * DQuat::from_rotation_x(0.1), true),
        (1.0, [-0.3, -0.4, 0.9], DQuat::from_rotation_y(1.7), false),
        (1.5, [-0.3, -0.4, 0.9], DQuat::from_rotation_y(1.7), false),
    ];
    let mut csv = String::from("t,x,y,z,qx,qy,qz,qw,spray\n");
    let mut waypoints = String::new();
    for (t, p, q, spray) in poses {
        csv.push_str(&format!(
            "{t:?},{:?},{:?},{:?},{:?},{:?},{:?},{:?},{}\n",
            p[0],
            p[1],
            p[2],
            q.x,
            q.y,
            q.z,
            q.w,
            u8::from(spray)
        ));
        let axis = q.normalize() * DVec3::Z;
        waypoints.push_str(&format!(
            "[[nozzle.waypoints]]\ntime = {t:?}\nposition = {p:?}\naxis = [{:?}, {:?}, {:?}]\nspray = {spray}\n",
            axis.x, axis.y, axis.z
        ));
    }
    std::fs::write(tmp.path().join("path.csv"), csv).expect("write");
    std::fs::write(tmp.path().join("csv.toml"), raster_scene("[nozzle]\npath_csv = \"path.csv\""))
        .expect("write");
    let from_csv = Scenario::from_path(&tmp.path().join("csv.toml")).unwrap_or_else(|e| panic!("{e}"));
    let from_waypoints =
        Scenario::from_toml(&raster_scene(&waypoints), "waypoints").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(from_csv, from_waypoints);
    let run = |sc: &Scenario, dir: &str| {
        let mut sim = sc.build().expect("valid");
        sim.run(|_| {});
        assert!(sim.metrics().emitted.count > 10_000);
        let files = spraysim::output::write_outputs(&sim, sc, &tmp.path().join(dir)).expect("written");
        files.iter().map(|f| std::fs::read(f).expect("read")).collect::<Vec<_>>()
    };
    assert_eq!(run(&from_csv, "a"), run(&from_waypoints, "b"));
}

#[test]
fn bad_tool_paths_name_the_file_line_and_column() {
    let tmp = tempfile::tempdir().expect("tempdir");
    for (csv, expect) in [
        ("t,x,y,z,qx,qy,qw\n0,0,0,1,0,0,1\n", "path.csv:1: missing column `qz`"),
        (
            "t,x,y,z,qx,qy,qz,qw\n0,0,0,1,0,0,0,1\n0.5,0,zero,1,0,0,0,1\n",
            "path.csv:3: column `y`: \"zero\" is not a finite number",
        ),
        ("t,x,y,z,qx,qy,qz,qw\n0,0,0,1,0,0,0,0\n", "path.csv:2: the quaternion"),
        ("t,x,y,z,qx,qy,qz,qw,spray\n0,0,0,1,0,0,0,1,maybe\n", "path.csv:2: column `spray`"),
    ] {
        std::fs::write(tmp.path().join("path.csv"), csv).expect("write");
        std::fs::write(tmp.path().join("s.toml"), raster_scene("[nozzle]\npath_csv = \"path.csv\""))
            .expect("write");
        let err = Scenario::from_path(&tmp.path().join("s.toml")).expect_err("refused").to_string();
        assert!(err.contains(expect), "{err}");
    }
}

#[test]
fn a_tool_path_with_a_repeated_column_is_refused() {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("p.csv"), "t,t,x,y,z,qx,qy,qz,qw\n0,0,-1,0,1,0,0.7071068,0,0.7071068\n")
        .expect("write");
    let text = format!("{}\n[nozzle]\npath_csv = \"p.csv\"\n", scenes::wall_scene(0.05, 32));
    std::fs::write(tmp.path().join("s.toml"), text).expect("write");
    let Err(e) = Scenario::from_path(&tmp.path().join("s.toml")) else { panic!("accepted") };
    assert!(e.to_string().contains("column `t` appears twice"), "{e}");
}

#[test]
fn path_metrics_report_standoff_angle_and_speed_against_the_window() {
    let mut sim = Scenario::default_scene().build().expect("valid");
    sim.run(|_| {});
    let p = sim.metrics().path;
    let standoff = p.standoff.expect("a wall ahead");
    assert!((standoff.min - 1.0).abs() < 1e-12 && (standoff.max - 1.0).abs() < 1e-12);
    assert_eq!(standoff.outside_share, 0.0, "1 m is inside shotcrete's 1–2 m window");
    assert!(p.angle.expect("a wall ahead").max < 1e-6);
    assert_eq!(p.travel_speed.expect("sampled").max, 0.0);
    assert_eq!(p.nozzle_speed.expect("sampled").max, 0.0);
    assert!((p.spraying_time - 2.0).abs() < 1e-9);

    // Tilted 30° off square at 0.6 m: both outside the shotcrete window.
    let a = 30f64.to_radians();
    let sc = (Scenario::default_scene().with("nozzle.position", [-0.6 * a.cos(), 0.6 * a.sin(), 1.0]))
        .and_then(|sc| sc.with("nozzle.axis", [a.cos(), -a.sin(), 0.0]))
        .and_then(|sc| sc.with("simulation.duration", 0.1))
        .expect("valid");
    let mut sim = sc.build().expect("valid");
    sim.run(|_| {});
    let p = sim.metrics().path;
    let (s, g) = (p.standoff.expect("wall"), p.angle.expect("wall"));
    assert!((s.mean - 0.6).abs() < 1e-9 && s.outside_share == 1.0);
    assert!((g.mean - 30.0).abs() < 1e-9 && g.outside_share == 1.0);
}

#[test]
fn the_nozzle_velocity_carries_over_to_the_particles_when_asked() {
    let centroid_y = |carry: bool| {
        let text = format!(
            r#"
            [simulation]
            duration = 0.3
            gravity = [0.0, 0.0, 0.0]
            [process]
            preset = "painting"
            [emitter]
            shape = "point"
            cone_angle = 0.0
            speed = [20.0, 20.0]
            [nozzle]
            add_velocity = {carry}
            [[nozzle.waypoints]]
            time = 0.0
            position = [-1.0, -0.25, 1.0]
            axis = [1.0, 0.0, 0.0]
            [[nozzle.waypoints]]
            time = 0.1
            position = [-1.0, 0.25, 1.0]
            axis = [1.0, 0.0, 0.0]
            spray = false
            {panel}
            "#,
            panel = panel(),
        );
        let sc = Scenario::from_toml(&text, "carry").unwrap_or_else(|e| panic!("{e}"));
        let mut sim = sc.build().expect("valid");
        sim.run(|_| {});
        let f = &sim.targets()[0].surface.as_rectangle().expect("a rectangle").field;
        let (mut m, mut my) = (0.0, 0.0);
        for (c, &t) in f.thickness().iter().enumerate() {
            let (u, _) = f.cell_center(c as u32);
            m += t;
            my += t * -u; // right = −y
        }
        my / m
    };
    // The nozzle moves at 5 m/s along +y; a 1 m flight at 20 m/s takes 0.05 s: 0.25 m further.
    let shift = centroid_y(true) - centroid_y(false);
    assert!((shift - 0.25).abs() < 0.011, "shift {shift}");
}

/// Regression: the reported travel speed included the superposed circle (a 0.6 m/s raster read
/// 1.33 m/s and "72 % outside the window" in the Figure-4 task).
#[test]
fn the_window_judges_the_travel_speed_not_the_circling_tip() {
    let raster = "[nozzle.raster]\ntarget = \"panel\"\nsize = [0.6, 0.4]\nstandoff = 0.25\nspeed = 0.4\n\
                  step_over = 0.1\nlead = 0.0\ncircle_radius = 0.05\ncircle_frequency = 2.0";
    let sc = Scenario::from_toml(&raster_scene(raster), "raster").unwrap_or_else(|e| panic!("{e}"));
    let mut sim = sc.build().expect("valid");
    sim.run(|_| {});
    let p = sim.metrics().path;
    let travel = p.travel_speed.expect("sampled");
    // Along the passes at 0.4 m/s (painting's window is 0.2–0.6 m/s), whatever the circle adds.
    assert!((travel.max - 0.4).abs() < 1e-9, "{travel:?}");
    assert!(travel.outside_share < 0.05, "{travel:?}");
    // The tip adds up to 2π r f = 0.63 m/s.
    let tip = p.nozzle_speed.expect("sampled");
    let most = 0.4 + std::f64::consts::TAU * 0.05 * 2.0;
    assert!(tip.max > 0.9 * most && tip.max <= most + 1e-9, "{tip:?}");
}

#[test]
fn a_path_that_runs_past_the_duration_is_reported() {
    let raster = "[nozzle.raster]\ntarget = \"panel\"\nsize = [0.6, 0.4]\nstandoff = 0.25\nspeed = 0.2\n\
                  step_over = 0.1\nlead = 0.0";
    let sc = Scenario::from_toml(&raster_scene(raster), "raster").unwrap_or_else(|e| panic!("{e}"));
    // Five passes of 0.6 m and four steps of 0.1 m at 0.2 m/s: 17 s, against 2 s simulated.
    let end = sc.path_end();
    assert!((end - 17.0).abs() < 1e-9, "path ends at {end} s");
    let warnings = sc.warnings();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains("17.000 s") && warnings[0].contains("simulation.duration"), "{warnings:?}");
    let long = sc.with("simulation.duration", 17.0).expect("valid");
    assert!(long.warnings().is_empty());
    let ends = long.spraying_ends().expect("the raster stops");
    assert!((ends - 17.0).abs() < 1e-9, "spraying ends at {ends} s");
}

/// Regression: raster times were sums of their legs, so a pass that should start on a step
/// started a hair after it (0.7500000000000001 s), and that step was lost: 2- and 3-pass
/// rasters emitted 12,490 of 12,500 and 18,740 of 18,750 particles. Each pass here lasts a
/// whole number of steps, and so does each step-over; the nozzle emits exactly
/// `spawn_rate × spraying time`, pass for pass.
#[test]
fn a_raster_emits_exactly_its_spawn_rate_times_its_spraying_time() {
    // (width covered, lead, speed): passes of 0.75 m and 0.6 m at 1 m/s (0.75 s, 0.6 s), and of
    // 0.5 m at 2 m/s (0.25 s); step-overs of 0.1 m. Summed leg by leg, their second passes
    // started a hair late (a step lost) or ended a hair late (a step too many).
    for (width, lead, speed) in [(0.5_f64, 0.125_f64, 1.0_f64), (0.4, 0.1, 1.0), (0.4, 0.05, 2.0)] {
        for passes in 1..=3_u32 {
            // A rectangle as high as the passes span (half a step-over for a single pass).
            let height = if passes == 1 { 0.05 } else { 0.1 * f64::from(passes - 1) };
            let raster = format!(
                "[emitter]\nspawn_rate = 10000.0\n[nozzle.raster]\ntarget = \"panel\"\nsize = [{width:?}, {height:?}]\n\
                 standoff = 0.25\nspeed = {speed:?}\nstep_over = 0.1\nlead = {lead:?}"
            );
            let sc = Scenario::from_toml(&raster_scene(&raster), "raster")
                .and_then(|sc| sc.with("simulation.duration", 3.0))
                .unwrap_or_else(|e| panic!("{e}"));
            let mut sim = sc.build().expect("valid");
            // Spraying time: the passes' travel, in whole milliseconds (the steps).
            let pass_ms = ((width + 2.0 * lead) / speed * 1e3).round() as u64;
            let spraying_steps = u64::from(passes) * pass_ms;
            sim.run(|_| {});
            let emitted = sim.metrics().emitted.count;
            // 10 particles a 1 ms step: 10,000/s × the spraying time.
            assert_eq!(
                emitted,
                10 * spraying_steps,
                "{passes} passes of {width} m + 2 × {lead} m lead at {speed} m/s"
            );
        }
    }
}
