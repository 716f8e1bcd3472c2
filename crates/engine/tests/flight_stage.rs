//! The flight stage's seam: a stage that declines a call, or answers another job than it was
//! given, leaves the call to the engine's own flight, with the same results to the bit, and the
//! simulation keeps why.

use spraysim_engine::pipeline::{FlightJob, FlightReport, FlightStage};
use spraysim_engine::{Simulation, SimulationConfig};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A stage that declines every call (and counts them).
#[derive(Debug, Default)]
struct Declining(AtomicUsize);

impl FlightStage for Declining {
    fn fly(&self, _: &FlightJob<'_>) -> Result<FlightReport, String> {
        self.0.fetch_add(1, Ordering::Relaxed);
        Err("no device".into())
    }

    fn describe(&self) -> String {
        "a stage that declines".into()
    }
}

/// A stage that hands back none of the particles it was given.
#[derive(Debug)]
struct Losing;

impl FlightStage for Losing {
    fn fly(&self, job: &FlightJob<'_>) -> Result<FlightReport, String> {
        let n = job.targets.len();
        Ok(FlightReport {
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
    let mut sim = Simulation::new(SimulationConfig::example_wall(0.1)).expect("valid");
    sim.set_flight_stage(stage);
    sim.run(|_| {});
    sim
}

#[test]
fn a_declined_call_flies_on_the_engine_with_the_same_bits_and_the_reason_is_kept() {
    let own = run(None);
    let declining = Arc::new(Declining::default());
    let declined = run(Some(declining.clone()));
    assert_eq!(declining.0.load(Ordering::Relaxed) as u64, own.total_steps() / own.epoch_steps());
    assert_eq!(declined.flight_stage_error(), Some("no device"));
    assert_eq!(format!("{:?}", declined.metrics()), format!("{:?}", own.metrics()));
    assert_eq!(declined.swarm().particles, own.swarm().particles);
    let lost = run(Some(Arc::new(Losing)));
    assert!(
        lost.flight_stage_error().is_some_and(|e| e.contains("other particles")),
        "{:?}",
        lost.flight_stage_error()
    );
    assert_eq!(format!("{:?}", lost.metrics()), format!("{:?}", own.metrics()));
    assert_eq!(own.flight_stage_error(), None);
}
