//! What flies a run's particles (`[simulation] backend`, `--backend`), as
//! [`spraysim::backend`] chooses, said the command's way.

use anyhow::Result;
use spraysim::backend::{self, Chosen};
use spraysim::{Scenario, Simulation};

/// Sets `sim`'s flight stage as `scenario`'s backend asks and returns what runs the flights, in
/// words, where it is not the CPU. `gpu` is refused, naming why, where the build, the adapter or
/// the scenario does not allow it; `auto` then runs on the CPU and says why in one line on
/// stderr.
pub fn attach(sim: &mut Simulation, scenario: &Scenario) -> Result<Option<String>> {
    let chosen = backend::choose(scenario.simulation().backend, scenario)
        .map_err(|e| anyhow::anyhow!(e).context("backend \"gpu\" (simulation.backend)"))?;
    if let Some(why) = &chosen.fallback {
        eprintln!("backend \"auto\": running on the CPU: {why}");
    }
    let name = chosen.stage.is_some().then(|| chosen.describe());
    let Chosen { stage, .. } = chosen;
    if stage.is_some() {
        sim.set_flight_stage(stage);
    }
    Ok(name)
}
