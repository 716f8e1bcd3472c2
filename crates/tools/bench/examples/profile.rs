//! Runs the reference scene (or its 60 s raster) once and prints what the run measured: the
//! workload to put under a profiler (`perf record`, `valgrind --tool=callgrind`), where
//! `spraysim bench` times many.
//!
//! ```sh
//! cargo build --release -p spraysim-bench --example profile
//! target/release/examples/profile [--euler] [--raster] [--rate R] [--duration T] [--resolution N] [-j THREADS] [--set KEY=VALUE]…
//! ```
//!
//! By default: the exact integrator at 10⁶ particles/s for 0.5 s on
//! every core; `--raster` runs the raster at 10⁵ particles/s unless `--rate` says otherwise;
//! `--resolution` sets the reference wall's cells per side (1024 by default).

use spraysim_bench::{ReferenceScene, measure, raster_pass};
use spraysim_engine::motion::Integrator;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (mut euler, mut raster, mut rate, mut duration, mut threads) = (false, false, None, 0.5, 0);
    let mut resolution = ReferenceScene::default().resolution;
    let mut sets = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        let mut value = |name: &str| args.next().ok_or_else(|| format!("{name} needs a value"));
        match arg.as_str() {
            "--euler" => euler = true,
            "--raster" => raster = true,
            "--rate" => rate = Some(value("--rate")?.parse::<f64>()?),
            "--duration" => duration = value("--duration")?.parse()?,
            "-j" => threads = value("-j")?.parse()?,
            "--resolution" => resolution = value("--resolution")?.parse()?,
            "--set" => sets.push(value("--set")?),
            other => return Err(format!("unknown argument {other:?}").into()),
        }
    }
    let integrator = if euler { Integrator::Euler } else { Integrator::Exact };
    let mut scenario = if raster {
        raster_pass(rate.unwrap_or(1e5))?.with("simulation.duration", duration)?
    } else {
        let spawn_rate = rate.unwrap_or(1e6);
        ReferenceScene { integrator, spawn_rate, duration, resolution, ..ReferenceScene::default() }
            .scenario()?
    };
    if !euler {
        scenario = scenario.with("simulation.integrator", "exact")?;
    }
    for set in sets {
        let (key, value) = set.split_once('=').ok_or_else(|| format!("--set {set:?}: expected KEY=VALUE"))?;
        scenario = scenario.with(key, value.parse::<f64>().map_err(|e| format!("--set {set:?}: {e}"))?)?;
    }
    let r = measure(&scenario, threads)?;
    println!(
        "wall {:.3} s, particle-steps {}, updated {} ({:.1} %), retired {}, in flight {}, {:.3e} particles/s to fate",
        r.wall,
        r.particle_steps,
        r.particle_updates,
        100.0 * r.worked_share(),
        r.retired,
        r.in_flight,
        r.particles_per_second()
    );
    Ok(())
}
