//! The flight stage's seam: a stage that declines a call, or answers another job than it was
//! given, leaves the call to the engine's own flight, with the same results to the bit, and the
//! simulation keeps why.

use spraysim_engine::deposit::DepositSurface;
use spraysim_engine::pipeline::{FlightJob, FlightReport, FlightStage};
use spraysim_engine::{Simulation, SimulationConfig};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A stage that declines every call (and counts them, with the epochs they spanned), offering
/// to take calls of up to `epochs` epochs and `particles` particles.
#[derive(Debug, Default)]
struct Declining {
    calls: AtomicUsize,
    spanned: AtomicUsize,
    epochs: u64,
    particles: usize,
    /// Each call's steps and steps per epoch.
    jobs: std::sync::Mutex<Vec<(u64, u64, u64)>>,
}

impl Declining {
    fn new(epochs: u64, particles: usize) -> Declining {
        Declining { epochs, particles, ..Declining::default() }
    }
}

impl FlightStage for Declining {
    fn fly(&self, job: &FlightJob<'_>) -> Result<FlightReport, String> {
        self.calls.fetch_add(1, Ordering::Relaxed);
        let epochs = job.to.div_ceil(job.epoch) - job.from / job.epoch;
        self.spanned.fetch_add(epochs as usize, Ordering::Relaxed);
        self.jobs.lock().expect("not poisoned").push((job.from, job.to, job.epoch));
        assert!(job.particles.len() <= self.particles.max(1000), "{} particles", job.particles.len());
        Err("no device".into())
    }

    fn describe(&self) -> String {
        "a stage that declines".into()
    }

    fn epochs_per_call(&self) -> u64 {
        self.epochs
    }

    fn particles_per_call(&self) -> usize {
        self.particles
    }
}

/// A stage that hands back none of the particles it was given, and counts no fate for them
/// (or, `inventing`, hands back one it was not given).
#[derive(Debug)]
struct Losing {
    inventing: bool,
}

impl FlightStage for Losing {
    fn fly(&self, job: &FlightJob<'_>) -> Result<FlightReport, String> {
        let n = job.targets.len();
        let mut particles = Vec::new();
        if self.inventing {
            let mut p = job.newborns().pop().ok_or("no newborn")?;
            p.id += 1;
            particles.push(p);
        }
        Ok(FlightReport {
            particles,
            targets: vec![Default::default(); n],
            cells: vec![Vec::new(); n],
            obstacles: vec![Default::default(); job.config.obstacles.len()],
            ..FlightReport::default()
        })
    }

    fn describe(&self) -> String {
        "a stage that loses particles".into()
    }
}

fn run(stage: Option<Arc<dyn FlightStage>>) -> Simulation {
    run_config(SimulationConfig::example_wall(0.1), stage)
}

fn run_config(config: SimulationConfig, stage: Option<Arc<dyn FlightStage>>) -> Simulation {
    let mut sim = Simulation::new(config).expect("valid");
    sim.set_flight_stage(stage);
    sim.run(|_| {});
    sim
}

fn same(a: &Simulation, b: &Simulation) {
    assert_eq!(format!("{:?}", a.metrics()), format!("{:?}", b.metrics()));
    assert_eq!(a.swarm().particles, b.swarm().particles);
    let layers =
        |s: &Simulation| s.targets().iter().map(|t| t.surface.thickness().to_vec()).collect::<Vec<_>>();
    assert_eq!(layers(a), layers(b));
}

#[test]
fn a_declined_call_flies_on_the_engine_with_the_same_bits_and_the_reason_is_kept() {
    let own = run(None);
    let declining = Arc::new(Declining::new(1, usize::MAX));
    let declined = run(Some(declining.clone()));
    assert_eq!(declining.calls.load(Ordering::Relaxed) as u64, own.total_steps() / own.epoch_steps());
    assert_eq!(declined.flight_stage_error(), Some("no device"));
    same(&declined, &own);
    for (inventing, why) in [(false, "fates count 0 particles retired"), (true, "other particles")] {
        let lost = run(Some(Arc::new(Losing { inventing })));
        assert!(
            lost.flight_stage_error().is_some_and(|e| e.contains(why)),
            "{:?}",
            lost.flight_stage_error()
        );
        assert_eq!(format!("{:?}", lost.metrics()), format!("{:?}", own.metrics()));
    }
    assert_eq!(own.flight_stage_error(), None);
}

#[test]
fn calls_of_several_epochs_end_where_a_layer_stage_falls_due_and_fly_epoch_by_epoch_when_declined() {
    use spraysim_engine::config::ScheduledStage;
    use spraysim_engine::process::layer::{CohesionStage, Strength};
    // Cohesion every 25 ms over 0.1 s (four stretches of five 5-ms epochs), so weak that the
    // layer fails and its material flies again.
    let mut config = SimulationConfig::example_wall(0.1);
    let strength = Strength { tensile: 0.01, shear: 0.01, cohesion: 0.01 };
    config.layer_stages.push(ScheduledStage { interval: 0.025, stage: Arc::new(CohesionStage { strength }) });
    let own = run_config(config.clone(), None);
    assert!(!own.failures().is_empty(), "the layer fails");
    let epochs = own.total_steps() / own.epoch_steps();
    let declining = Arc::new(Declining::new(1000, usize::MAX));
    let declined = run_config(config.clone(), Some(declining.clone()));
    assert_eq!(declining.calls.load(Ordering::Relaxed), 4, "a call per stretch between cohesion runs");
    assert_eq!(declining.spanned.load(Ordering::Relaxed) as u64, epochs, "the calls cover every epoch once");
    same(&declined, &own);
    // At most three epochs a call: each stretch of five epochs in two calls.
    let three = Arc::new(Declining::new(3, usize::MAX));
    same(&run_config(config.clone(), Some(three.clone())), &own);
    assert_eq!(three.calls.load(Ordering::Relaxed), 8);
    // At most 1000 particles a call, at 10⁴ particles/s (50 an epoch): calls end early.
    let small = Arc::new(Declining::new(1000, 1000));
    same(&run_config(config.clone(), Some(small.clone())), &own);
    assert!(small.calls.load(Ordering::Relaxed) > 4);
    // A call of several epochs ends at an epoch's end: advancing by 23 steps (epochs of 5) from
    // the start hands the stage the epochs of steps 0..20 in one call, then 20..23 alone.
    let mut partial = Simulation::new(config.clone()).expect("valid");
    let recorder = Arc::new(Declining::new(1000, usize::MAX));
    partial.set_flight_stage(Some(recorder.clone()));
    partial.advance(23);
    partial.advance(own.total_steps() - 23);
    same(&partial, &own);
    let jobs = recorder.jobs.lock().expect("not poisoned").clone();
    assert_eq!(jobs[..2], [(0, 20, 5), (20, 23, 5)], "{jobs:?}");
    for &(from, to, epoch) in &jobs {
        assert!(to - from <= epoch || to % epoch == 0, "a call of several epochs ends within one: {jobs:?}");
    }
    // Advancing step by step never hands a stage more than the epoch under way.
    let mut stepped = Simulation::new(SimulationConfig::example_wall(0.1)).expect("valid");
    let single = Arc::new(Declining::new(1000, usize::MAX));
    stepped.set_flight_stage(Some(single.clone()));
    while !stepped.is_finished() {
        stepped.step();
    }
    assert_eq!(single.calls.load(Ordering::Relaxed), single.spanned.load(Ordering::Relaxed));
}

#[test]
fn a_run_whose_target_erodes_hands_a_stage_one_epoch_a_call() {
    use spraysim_engine::config::ErosionConfig;
    use spraysim_engine::process::erosion::Finnie;
    // Wear settles at each epoch's end, the coating first: a call's wear summed over several
    // epochs would wear the coating as one impact.
    let mut config = SimulationConfig::example_wall(0.05);
    let law = Arc::new(Finnie { k: 1e-9 });
    config.targets[0].erosion =
        Some(ErosionConfig { coating: 1e-4, coating_law: law.clone(), substrate_law: law });
    let own = run_config(config.clone(), None);
    let declining = Arc::new(Declining::new(1000, usize::MAX));
    let declined = run_config(config, Some(declining.clone()));
    let epochs = own.total_steps() / own.epoch_steps();
    assert_eq!(declining.calls.load(Ordering::Relaxed) as u64, epochs, "a call per epoch");
    assert_eq!(declining.spanned.load(Ordering::Relaxed) as u64, epochs);
    same(&declined, &own);
}
