//! The GPU backend against the CPU engine on whole runs: fates, rebound, the layers' moments,
//! obstacles, openings, shells, erosion, and material released by cohesive failures, over
//! several seeds, within derived statistical tolerances; conservation and determinism exactly.

mod common;

use common::{mean_sd, run};
use spraysim_engine::deposit::{DepositSurface, Opening, Surface};
use spraysim_engine::{Metrics, Simulation};
use spraysim_gpu::GpuFlight;
use spraysim_scenario::Scenario;
use spraysim_scenario::scenes::{NOZZLE_AT_WALL, bar, failing_layer, floor, scenario, wall};
use std::sync::Arc;

/// Seeds per backend.
const SEEDS: u64 = 4;

/// Two shares from `n1` and `n2` independent particles differ by more than this many standard
/// errors of their difference about once in 10⁵ (a normal tail), if both come from one law.
const Z: f64 = 4.4;

/// Student's t at 99.9 % (two-sided) for 2 × 4 − 2 = 6 degrees of freedom: means of 4 seeds per
/// backend farther apart than this many standard errors are a real difference.
const T: f64 = 5.96;

/// The default scene (shotcrete, the cushion law, onto the wall and the floor in front of it)
/// for 0.3 s at 2·10⁴ particles/s, with a rebar in front of the wall, and `seed`.
fn shotcrete(seed: u64) -> Scenario {
    let text = format!(
        "[simulation]\nduration = 0.3\nseed = {seed}\n[emitter]\nspawn_rate = 20000.0\n{NOZZLE_AT_WALL}{}{}{}",
        wall(),
        floor(),
        bar("rebar", [-0.05, -1.0, 1.02], [-0.05, 1.0, 1.02], 0.008)
    );
    scenario(&text, "shotcrete with a bar")
}

/// Asserts that the shares `a` of `na` and `b` of `nb` particles agree as binomial shares.
fn same_share(what: &str, (a, na): (f64, f64), (b, nb): (f64, f64)) {
    let p = (a * na + b * nb) / (na + nb);
    let se = (p * (1.0 - p) * (1.0 / na + 1.0 / nb)).sqrt().max(1e-12);
    assert!((a - b).abs() <= Z * se, "{what}: GPU {b:.4} against CPU {a:.4} (tolerance {:.4})", Z * se);
}

/// Asserts that the per-seed values `a` (CPU) and `b` (GPU) have the same mean, to `T` standard
/// errors, plus `floor` for what the GPU resolves differently by construction.
fn same_mean(what: &str, a: &[f64], b: &[f64], floor: f64) {
    let ((ma, sa), (mb, sb)) = (mean_sd(a), mean_sd(b));
    let se = ((sa * sa + sb * sb) / a.len() as f64).sqrt();
    assert!(
        (ma - mb).abs() <= T * se + floor,
        "{what}: GPU {mb:.5e} ± {sb:.1e} against CPU {ma:.5e} ± {sa:.1e}"
    );
}

/// A figure of a run's metrics.
type Figure = dyn Fn(&Metrics) -> f64;

/// Volume, centroid (across and up its grid) and radius of gyration of the first target's
/// layer, m³ and m.
fn moments(sim: &Simulation) -> [f64; 4] {
    let wall = &sim.targets()[0];
    let thickness = wall.surface.thickness();
    let field = match &wall.surface {
        Surface::Rectangle(r) => &r.field,
        Surface::Cylinder(c) => &c.field,
        Surface::Mesh(_) => panic!("the first target has a grid"),
    };
    let (mut v, mut u1, mut v1, mut r2) = (0.0, 0.0, 0.0, 0.0);
    for (c, &t) in thickness.iter().enumerate() {
        let (u, w) = field.cell_center(c as u32);
        v += t;
        u1 += t * u;
        v1 += t * w;
        r2 += t * (u * u + w * w);
    }
    let (cu, cv) = (u1 / v, v1 / v);
    [v * field.cell_area(), cu, cv, (r2 / v - cu * cu - cv * cv).sqrt()]
}

/// `scene`'s runs over `SEEDS` seeds on the CPU (seeds 1 on) and on the GPU (seeds 101 on), each
/// GPU run's particles and volume conserved.
fn both(gpu: &Arc<GpuFlight>, scene: impl Fn(u64) -> Scenario) -> (Vec<Simulation>, Vec<Simulation>) {
    let cpu = (1..=SEEDS).map(|seed| run(&scene(seed), None)).collect();
    let on_gpu: Vec<Simulation> = (1..=SEEDS).map(|seed| run(&scene(100 + seed), Some(gpu))).collect();
    on_gpu.iter().for_each(|s| conserved(&s.metrics()));
    (cpu, on_gpu)
}

/// Asserts that each case's figure, as a share of the particles emitted over the runs, agrees
/// between the CPU's runs and the GPU's as binomial shares; on the CPU each must be at least
/// `least`, so that the case tests something.
fn same_shares(cases: &[(&str, &Figure)], cpu: &[Simulation], gpu: &[Simulation], least: f64) {
    let share = |runs: &[Simulation], f: &Figure| {
        let ms: Vec<Metrics> = runs.iter().map(Simulation::metrics).collect();
        let n: f64 = ms.iter().map(|m| m.emitted.count as f64).sum();
        (ms.iter().map(f).sum::<f64>() / n, n)
    };
    for &(what, f) in cases {
        let (c, g) = (share(cpu, f), share(gpu, f));
        assert!(c.0 >= least, "{what}: {:.4} on the CPU, too few to test", c.0);
        same_share(what, c, g);
    }
}

/// Asserts that the first target's layer moments `which` (index into [`moments`], name, floor
/// in m or m³) agree between the CPU's runs and the GPU's, seed by seed.
fn same_moments(which: &[(usize, &str, f64)], cpu: &[Simulation], gpu: &[Simulation]) {
    let per_seed = |runs: &[Simulation], k: usize| runs.iter().map(|s| moments(s)[k]).collect::<Vec<_>>();
    for &(k, what, floor) in which {
        same_mean(what, &per_seed(cpu, k), &per_seed(gpu, k), floor);
    }
}

/// Cells are 10 mm or so: the GPU's f32 and flat-layer contact move a centroid by far less than
/// a millimetre.
const LAYER_MOMENTS: [(usize, &str, f64); 4] = [
    (0, "layer volume", 0.0),
    (1, "centroid across", 1e-3),
    (2, "centroid up", 1e-3),
    (3, "radius of gyration", 1e-3),
];

/// The first target's layer as (distance from its grid's centre, where the spray's axis
/// strikes, m; volume, m³) per cell that holds material.
fn radial(sim: &Simulation) -> Vec<(f64, f64)> {
    let wall = &sim.targets()[0];
    let Surface::Rectangle(r) = &wall.surface else { panic!("the first target is a rectangle") };
    let area = r.field.cell_area();
    wall.surface
        .thickness()
        .iter()
        .enumerate()
        .filter(|&(_, &t)| t > 0.0)
        .map(|(c, &t)| {
            let (u, w) = r.field.cell_center(c as u32);
            (u.hypot(w), t * area)
        })
        .collect()
}

/// Asserts that the first target's radial thickness profile agrees between the CPU's runs and
/// the GPU's, seed by seed: the share of the layer's volume in each of five rings round the
/// spray's axis, their edges where the CPU's runs together reach 20, 40, 60 and 80 % of it.
fn same_profile(cpu: &[Simulation], gpu: &[Simulation]) {
    let mut pooled: Vec<(f64, f64)> = cpu.iter().flat_map(radial).collect();
    pooled.sort_by(|a, b| a.0.total_cmp(&b.0));
    let total: f64 = pooled.iter().map(|p| p.1).sum();
    let mut edges = Vec::new();
    let mut sum = 0.0;
    for &(r, v) in &pooled {
        sum += v;
        if sum >= total * 0.2 * (edges.len() + 1) as f64 && edges.len() < 4 {
            edges.push(r);
        }
    }
    assert_eq!(edges.len(), 4, "the CPU's layer has a profile");
    let shares = |sim: &Simulation| {
        let cells = radial(sim);
        let volume: f64 = cells.iter().map(|c| c.1).sum();
        let mut rings = [0.0; 5];
        for (r, v) in cells {
            rings[edges.partition_point(|&e| e < r)] += v / volume;
        }
        rings
    };
    let (on_cpu, on_gpu): (Vec<[f64; 5]>, Vec<[f64; 5]>) =
        (cpu.iter().map(shares).collect(), gpu.iter().map(shares).collect());
    for ring in 0..5 {
        let column = |runs: &[[f64; 5]]| runs.iter().map(|s| s[ring]).collect::<Vec<_>>();
        let what = format!("share of the layer's volume in ring {ring} (edges {edges:.3?} m)");
        same_mean(&what, &column(&on_cpu), &column(&on_gpu), 0.0);
    }
}

fn conserved(m: &Metrics) {
    assert_eq!(m.emitted.count, m.fates.total().count, "every particle has one fate");
    let b = &m.volume_balance;
    assert!(b.residual.abs() <= 1e-12 * b.emitted, "the volume balance closes: {b:?}");
}

#[test]
fn shotcrete_on_the_gpu_agrees_with_the_cpu_engine_within_statistics() {
    let Some(gpu) = common::gpu() else { return };
    let (cpu, on_gpu) = both(&gpu, shotcrete);
    let cases: [(&str, &Figure); 5] = [
        ("stuck on the wall", &|m| m.targets[0].stuck.count as f64),
        ("stuck on the floor", &|m| m.targets[1].stuck.count as f64),
        ("bounced at first impact", &|m| m.bounce_ratio.unwrap_or(0.0) * m.emitted.count as f64),
        ("struck the bar", &|m| m.obstacles[0].hits as f64),
        ("in flight at the end", &|m| m.fates.in_flight.count as f64),
    ];
    same_shares(&cases, &cpu, &on_gpu, 0.0);
    same_moments(&LAYER_MOMENTS, &cpu, &on_gpu);
    same_profile(&cpu, &on_gpu);
}

#[test]
fn the_same_seed_on_the_same_adapter_gives_the_same_bits() {
    let Some(gpu) = common::gpu() else { return };
    let a = run(&shotcrete(7), Some(&gpu));
    let b = run(&shotcrete(7), Some(&gpu));
    let c = run(&shotcrete(8), Some(&gpu));
    let layer =
        |s: &Simulation| s.targets()[0].surface.thickness().iter().map(|t| t.to_bits()).collect::<Vec<_>>();
    assert_eq!(layer(&a), layer(&b));
    assert_eq!(format!("{:?}", a.metrics()), format!("{:?}", b.metrics()));
    assert_eq!(a.swarm().particles, b.swarm().particles);
    assert_ne!(layer(&a), layer(&c), "another seed gives another layer");
}

#[test]
fn material_released_by_cohesive_failures_flies_on_the_gpu_as_on_the_cpu() {
    let Some(gpu) = common::gpu() else { return };
    // A weak layer fails as it grows, and its failures feed each other as released material
    // lands on the layer below and on the floor.
    let weak = |seed: u64| failing_layer(1.4, seed);
    let figures = |m: &Metrics| {
        [
            m.failures.events.len() as f64,
            m.failures.released.volume,
            m.targets[0].received.volume,
            m.targets[1].received.volume,
        ]
    };
    let (mut cpu, mut gpu_figures) = (Vec::new(), Vec::new());
    for seed in 1..=2 {
        cpu.push(figures(&run(&weak(seed), None).metrics()));
        let m = run(&weak(10 + seed), Some(&gpu)).metrics();
        conserved(&m);
        gpu_figures.push(figures(&m));
    }
    // Seeds scatter these by a few per cent; a released particle that re-stuck where it left
    // the layer (or fell through it) moved them by 50 to 150 %. What the floor receives is the
    // tail of the cascade, which began 0.2 s before the end: it must only be there.
    assert!(gpu_figures.iter().chain(&cpu).all(|f| f[3] > 0.0), "released material reaches the floor");
    let names = ["failures", "released volume", "received by the wall"];
    for (k, what) in names.iter().enumerate() {
        let mean = |f: &[[f64; 4]]| f.iter().map(|x| x[k]).sum::<f64>() / f.len() as f64;
        let (c, g) = (mean(&cpu), mean(&gpu_figures));
        assert!(c > 0.0 && (g - c).abs() <= 0.2 * c, "{what}: GPU {g:.4e} against CPU {c:.4e}");
    }
}

#[test]
fn the_gpu_copy_of_the_layers_follows_them_cell_for_cell() {
    // Its own stage: the other tests' calls would replace the copy between two of this one's.
    let Some(gpu) = common::own_gpu().map(std::sync::Arc::new) else { return };
    // Deposits every epoch, and a weak layer that fails (cells emptied) every 0.1 s.
    let sc = failing_layer(0.8, 1);
    let mut sim = sc.build().expect("builds");
    sim.set_flight_stage(Some(gpu.clone()));
    gpu.take_profile();
    let layers = |s: &Simulation| -> Vec<f32> {
        s.targets().iter().flat_map(|t| t.surface.thickness().iter().map(|&x| x as f32)).collect()
    };
    let mut checked = 0;
    while !sim.is_finished() {
        // A call that ends short of the epoch's end settles nothing on the CPU: the layers stand
        // as the GPU copied them at its start.
        let k = sim.steps_to_epoch_end();
        sim.advance(k - 1);
        let copy = gpu.read_layers().expect("reads back");
        let now = layers(&sim);
        assert_eq!(&copy[..now.len()], &now[..], "the GPU's layers at step {}", sim.steps_done());
        checked += 1;
        sim.advance(1);
    }
    assert!(
        checked > 50 && !sim.failures().is_empty(),
        "{checked} epochs, {} failures",
        sim.failures().len()
    );
    // The split calls list few cells and the rest many, so that some calls read back all their
    // listed cells with the kernels' results and others (those that listed more than twice as
    // many as the call before, or 256) the first of them, and the rest in a second copy.
    let p = gpu.take_profile();
    assert!(p.second_copies > 0 && p.second_copies < p.calls, "{} of {} calls", p.second_copies, p.calls);
    // The same run handed an epoch a call gives the same bits: the second part of a split
    // epoch reads the layers as the epoch found them, not with the first part's deposits.
    let mut whole = sc.build().expect("builds");
    whole.set_flight_stage(Some(gpu.clone()));
    while !whole.is_finished() {
        whole.advance(whole.steps_to_epoch_end());
    }
    let bits = |s: &Simulation| -> Vec<u64> {
        s.targets().iter().flat_map(|t| t.surface.thickness().iter().map(|x| x.to_bits())).collect()
    };
    let differ = bits(&whole).iter().zip(&bits(&sim)).filter(|(a, b)| a != b).count();
    assert_eq!(differ, 0, "cells of the layers that differ");
    assert_eq!(format!("{:?}", whole.metrics()), format!("{:?}", sim.metrics()));
}

#[test]
fn a_call_of_many_epochs_settles_each_on_the_gpu_as_the_engine_does() {
    let Some(gpu) = common::own_gpu().map(std::sync::Arc::new) else { return };
    // Cohesion every 0.1 s, strong enough that nothing fails, and no slump: calls of twenty
    // 5-ms epochs, each depositing on the layer that the next reads, and the layers change only
    // by deposits.
    let strong = [
        ("process.cohesion.shear_strength", 1e7),
        ("process.cohesion.tensile_strength", 1e7),
        ("process.slump.interval", 0.0),
    ];
    let sc = failing_layer(0.4, 3)
        .with_all(&strong.map(|(k, v)| (k.to_string(), v.into())))
        .expect("a valid override");
    let mut sim = sc.build().expect("builds");
    sim.set_flight_stage(Some(gpu.clone()));
    gpu.take_profile();
    let mut calls = 0;
    while !sim.is_finished() {
        sim.advance_call(sim.steps_to_call_end());
        calls += 1;
        // The GPU's layers after the call's last epoch, against the engine's once it booked and
        // settled the call: the same deposits, added in f32 on one side and f64 on the other.
        let settled = gpu.read_settled_layers().expect("reads back");
        let layers: Vec<f64> = sim.targets().iter().flat_map(|t| t.surface.thickness().to_vec()).collect();
        let worst = layers
            .iter()
            .zip(&settled)
            .map(|(&t, &g)| (f64::from(g) - t).abs() / (t + 1e-9))
            .fold(0.0, f64::max);
        let covered = layers.iter().filter(|&&t| t > 0.0).count();
        assert!(
            covered > 100 && worst < 1e-5,
            "call {calls}: {covered} cells, worst relative difference {worst:e}"
        );
    }
    assert!(sim.failures().is_empty());
    let p = gpu.take_profile();
    assert_eq!(calls, 4, "a call per cohesion interval");
    assert_eq!((p.calls, p.epochs), (4, 80), "every epoch flown once, in 4 calls");
}

#[test]
fn shotcrete_onto_a_turned_box_rebounds_on_the_gpu_as_on_the_cpu() {
    let Some(gpu) = common::gpu() else { return };
    // A block of formwork (0.12 × 0.16 × 0.2 m, turned 37° about z) over half of the spray,
    // 0.75 m from the nozzle: what strikes it sticks or rebounds off its faces onto the wall or
    // away, so the shares test the faces' normals as well as their places.
    let scene = |seed: u64| {
        let text = format!(
            "[simulation]\nduration = 0.3\nseed = {seed}\n[emitter]\nspawn_rate = 20000.0\n{NOZZLE_AT_WALL}{}{}\
             [[obstacle]]\nname = \"block\"\nshape = \"box\"\ncenter = [-0.25, 0.1, 1.02]\n\
             size = [0.12, 0.16, 0.2]\nx_axis = [0.8, 0.6, 0.0]\ny_axis = [-0.6, 0.8, 0.0]\n",
            wall(),
            floor()
        );
        scenario(&text, "shotcrete onto a box")
    };
    let (cpu, on_gpu) = both(&gpu, scene);
    // (Rebounds take longer than the run to fall to the floor.)
    let cases: [(&str, &Figure); 3] = [
        ("stuck on the block", &|m| m.obstacles[0].stuck.count as f64),
        ("stuck on the wall", &|m| m.targets[0].stuck.count as f64),
        ("in flight at the end", &|m| m.fates.in_flight.count as f64),
    ];
    same_shares(&cases, &cpu, &on_gpu, 0.005);
}

#[test]
fn shotcrete_through_a_window_and_beside_it_agrees_with_the_cpu_engine() {
    let Some(gpu) = common::gpu() else { return };
    // A window 0.2 m wide and 0.3 m tall just off the nozzle's aim: part of the spray passes,
    // onto a collector 0.6 m behind the wall, and the rest builds a layer up to its edges.
    let window = Opening::rectangle((0.08, 0.0), (0.2, 0.3));
    let scene = |seed: u64| {
        let text = format!(
            "[simulation]\nduration = 0.3\nseed = {seed}\n[emitter]\nspawn_rate = 20000.0\n{NOZZLE_AT_WALL}{}{}{}",
            wall().with("[[target.opening]]\ncenter = [0.08, 0.0]\nsize = [0.2, 0.3]"),
            floor(),
            wall().named("backstop").collector().at([0.6, 0.0, 1.0]),
        );
        scenario(&text, "shotcrete through a window")
    };
    let (cpu, gpu_runs) = both(&gpu, scene);
    // The wall's cells in the window hold nothing; the solid cells within two cells of its edge
    // hold the layer beside it.
    let Surface::Rectangle(r) = &cpu[0].targets()[0].surface else { panic!("the wall is a rectangle") };
    let (field, dx) = (&r.field, r.field.cell_size().0);
    let cells = 0..field.thickness().len() as u32;
    let holes: Vec<u32> = cells.clone().filter(|&c| field.is_hole(c)).collect();
    let rim: Vec<u32> = cells
        .filter(|&c| {
            !field.is_hole(c) && {
                let (u, v) = field.cell_center(c);
                window.distance(u, v) < 2.0 * dx
            }
        })
        .collect();
    assert!(!holes.is_empty() && rim.len() > 100, "{} cells cut away, {} on the rim", holes.len(), rim.len());
    let rim_mean = |s: &Simulation| {
        let t = s.targets()[0].surface.thickness();
        assert!(holes.iter().all(|&c| t[c as usize] == 0.0), "a cell in the window holds a layer");
        rim.iter().map(|&c| t[c as usize]).sum::<f64>() / rim.len() as f64
    };
    let (rim_cpu, rim_gpu): (Vec<f64>, Vec<f64>) =
        (cpu.iter().map(rim_mean).collect(), gpu_runs.iter().map(rim_mean).collect());
    let cases: [(&str, &Figure); 4] = [
        ("stuck on the wall", &|m| m.targets[0].stuck.count as f64),
        ("through the window, onto the backstop", &|m| m.targets[2].stuck.count as f64),
        ("bounced at first impact", &|m| m.bounce_ratio.unwrap_or(0.0) * m.emitted.count as f64),
        ("in flight at the end", &|m| m.fates.in_flight.count as f64),
    ];
    same_shares(&cases, &cpu, &gpu_runs, 0.02);
    same_moments(&LAYER_MOMENTS[..3], &cpu, &gpu_runs);
    same_mean("mean thickness beside the window", &rim_cpu, &rim_gpu, 0.0);
}

#[test]
fn blasting_wears_the_coat_and_the_steel_on_the_gpu_as_on_the_cpu() {
    let Some(gpu) = common::gpu() else { return };
    // Grit square onto a 0.6 m wall under a 5 µm coat, worn by Oka's law (which wears most near
    // square incidence): in 0.3 s the middle of the spot (7 % of the wall) is cleaned to bare
    // steel, which then wears too.
    let scene = |seed: u64| {
        let text = format!(
            "[simulation]\nduration = 0.3\nseed = {seed}\n[process]\npreset = \"blasting\"\n\
             [process.erosion]\nmodel = \"oka\"\n[emitter]\nspawn_rate = 20000.0\n{NOZZLE_AT_WALL}{}",
            wall().size(0.6, 0.6).resolution(60, 60).coating(5e-6),
        );
        scenario(&text, "blasting")
    };
    let (cpu, on_gpu) = both(&gpu, scene);
    let metrics = |runs: &[Simulation]| runs.iter().map(Simulation::metrics).collect::<Vec<_>>();
    let (cpu, gpu_runs) = (metrics(&cpu), metrics(&on_gpu));
    type Worn = fn(&spraysim_engine::metrics::ErosionStats) -> f64;
    let figures: [(&str, Worn); 4] = [
        ("mean depth removed", |e| e.mean_depth),
        ("coating left", |e| e.coating_left_mean),
        ("share cleaned to steel", |e| e.cleaned_fraction.unwrap_or(0.0)),
        ("steel worn", |e| e.substrate_mean_depth),
    ];
    for (what, figure) in figures {
        let per_seed = |ms: &[Metrics]| {
            ms.iter().map(|m| m.targets[0].erosion.as_ref().map_or(f64::NAN, figure)).collect::<Vec<_>>()
        };
        let (c, g) = (per_seed(&cpu), per_seed(&gpu_runs));
        assert!(c.iter().all(|&x| x > 0.0), "{what}: {c:?} on the CPU, nothing to test");
        same_mean(what, &c, &g, 0.0);
    }
}

#[test]
fn shotcrete_onto_a_tunnel_arch_agrees_with_the_cpu_engine() {
    let Some(gpu) = common::gpu() else { return };
    // A 1.5 m arch (45° to 135°, sprayed from inside) from a nozzle 1.3 m under its crown, over
    // an invert that catches the rebound: the shares, and the layer's moments on the unrolled arch.
    let scene = |seed: u64| {
        let text = format!(
            "[simulation]\nduration = 0.3\nseed = {seed}\n[emitter]\nspawn_rate = 20000.0\n\
             [nozzle]\nposition = [0.0, 0.0, 0.2]\naxis = [0.0, 0.0, 1.0]\n\
             [[target]]\nname = \"arch\"\nshape = \"cylinder\"\ncenter = [0.0, 0.0, 0.0]\naxis = [0.0, 1.0, 0.0]\n\
             radius = 1.5\nlength = 2.0\nangles = [45.0, 135.0]\nside = \"inside\"\nresolution = [236, 200]\n{}",
            floor().named("invert").at([0.0, 0.0, -1.0]).size(3.0, 3.0),
        );
        scenario(&text, "shotcrete onto an arch")
    };
    let (cpu, on_gpu) = both(&gpu, scene);
    let cases: [(&str, &Figure); 3] = [
        ("stuck on the arch", &|m| m.targets[0].stuck.count as f64),
        ("bounced at first impact", &|m| m.bounce_ratio.unwrap_or(0.0) * m.emitted.count as f64),
        ("in flight at the end", &|m| m.fates.in_flight.count as f64),
    ];
    same_shares(&cases, &cpu, &on_gpu, 0.02);
    // Across: along the arc; up: along the axis.
    same_moments(&LAYER_MOMENTS, &cpu, &on_gpu);
}
