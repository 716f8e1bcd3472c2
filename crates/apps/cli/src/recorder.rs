//! The 3D views a run's `[output] render` asks for, drawn as the run steps and written with
//! its outputs. A build without the `render` feature refuses such a scenario before the run
//! starts, saying how to build one that draws them.

use anyhow::Result;
use spraysim::{Scenario, Simulation};

/// Stands in for the recorder of a build without 3D views: there is nothing to draw.
#[cfg(not(feature = "render"))]
pub struct Recorder;

/// The views a run's `[output] render` asks for, if any.
#[cfg(feature = "render")]
pub struct Recorder(Option<spraysim_render::record::Recorder>);

/// Refuses a scenario with `[output] render`: this build cannot draw it.
#[cfg(not(feature = "render"))]
pub fn recorder(scenario: &Scenario) -> Result<Recorder> {
    use crate::commands::render::BUILD_RENDER;
    if scenario.output().render.is_some() {
        anyhow::bail!("{}: `[output] render` asks for 3D views, but {BUILD_RENDER}", scenario.origin());
    }
    Ok(Recorder)
}

/// The recorder of `scenario`'s `[output] render`; opens the graphics adapter now, before the
/// run, so that a machine without one fails at once.
#[cfg(feature = "render")]
pub fn recorder(scenario: &Scenario) -> Result<Recorder> {
    use anyhow::Context;
    let Some(p) = &scenario.output().render else { return Ok(Recorder(None)) };
    let r = spraysim_render::record::Recorder::new(scenario, p, &Default::default())
        .with_context(|| format!("{}: `[output] render`", scenario.origin()))?;
    Ok(Recorder(Some(r)))
}

#[cfg(not(feature = "render"))]
impl Recorder {
    /// Steps from `sim`'s present to the one at whose end the next view is due: none.
    pub fn steps_to_next(&self, _sim: &Simulation) -> Option<u64> {
        None
    }

    /// Draws nothing: no view is asked for.
    pub fn observe(&mut self, _sim: &Simulation) -> Result<()> {
        Ok(())
    }

    /// Skips nothing: no view is due.
    pub fn skip_before(&mut self, _time: f64) {}

    /// No files: no view was drawn.
    pub fn finish(self, _sim: &Simulation, _quiet: bool) -> Result<Vec<(String, Vec<u8>)>> {
        Ok(Vec::new())
    }
}

#[cfg(feature = "render")]
impl Recorder {
    /// Steps from `sim`'s present to the one at whose end the next view is due, if one is.
    pub fn steps_to_next(&self, sim: &Simulation) -> Option<u64> {
        self.0.as_ref()?.steps_to_next(sim)
    }

    /// Renders what is due at `sim`'s time.
    pub fn observe(&mut self, sim: &Simulation) -> Result<()> {
        if let Some(r) = &mut self.0 {
            r.observe(sim)?;
        }
        Ok(())
    }

    /// Drops the stills and frames due before `time` (s): a resumed run cannot draw them.
    pub fn skip_before(&mut self, time: f64) {
        if let Some(r) = &mut self.0 {
            r.skip_before(time);
        }
    }

    /// Renders the end stills and encodes the animation; returns the files (name, contents).
    pub fn finish(self, sim: &Simulation, quiet: bool) -> Result<Vec<(String, Vec<u8>)>> {
        let Some(mut r) = self.0 else { return Ok(Vec::new()) };
        // Stopped early: the views of times never reached are not drawn.
        if !sim.is_finished() {
            r.drop_after(sim.time());
        }
        let recording = r.finish(sim)?;
        if !quiet {
            for n in &recording.notes {
                eprintln!("note: {n}");
            }
        }
        Ok(recording.files)
    }
}
