//! `spraysim run` and `spraysim resume`: a run stepped to its end (or to Ctrl-C) with its
//! progress shown, checkpoints written on the way, and its outputs, 3D views included, written
//! into the output directory as one set.

use super::{load, lock, print_warnings, strict_refusal, warn_size};
use crate::cli::{ResumeArgs, RunArgs};
use crate::control::{self, INTERRUPTED, RunControl};
use crate::recorder::{self, Recorder};
use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use spraysim::output::OutputDir;
use spraysim::output::checkpoint;
use spraysim::scenario::sanity;
use spraysim::{Scenario, Simulation};
use std::io::Write;
use std::path::Path;
use std::time::Instant;

/// Runs the scenario `args` name (the default scene without one) and writes its outputs.
pub fn run(args: &RunArgs) -> Result<()> {
    let scenario = load(args.scenario.as_deref(), &args.set)?;
    // The resolved scenario records the backend that ran it.
    let scenario = match args.backend {
        Some(b) => scenario.with("simulation.backend", b.name())?,
        None => scenario,
    };
    // The resolved scenario written with the outputs names the directory they went to (in
    // TOML, which holds UTF-8 only).
    let scenario = &match &args.output {
        Some(dir) => {
            let Some(text) = dir.to_str() else {
                anyhow::bail!(
                    "output directory {}: not valid UTF-8, which the resolved scenario cannot record: \
                     choose a name in UTF-8",
                    dir.display()
                );
            };
            scenario.with("output.directory", text)?
        }
        None => scenario,
    };
    warn_size(scenario);
    if args.strict {
        let warnings = sanity::before_run(scenario);
        if let Some(refusal) = strict_refusal(&warnings) {
            print_warnings(&warnings);
            return Err(refusal.context("not starting the run"));
        }
    }
    // Refused or set up before anything is written: a build without 3D views, or no graphics
    // adapter, a thread count beyond the machine's.
    let recorder = recorder::recorder(scenario)?;
    let mut sim = scenario.build()?;
    sim.set_threads(args.threads)?;
    let backend = crate::backend::attach(&mut sim, scenario)?;
    let every = args.checkpoint_every.map(|t| (t / scenario.simulation().dt).round().max(1.0) as u64);
    let dir = lock(Path::new(&scenario.output().directory))?;
    // A new run replaces the directory's run: an earlier run's checkpoint no longer applies.
    checkpoint::remove_checkpoint(&dir);
    dir.record_run(&scenario.to_toml())?;
    execute(scenario, sim, &dir, (every, recorder), (args.quiet, args.strict), backend.as_deref())
}

/// Continues the run whose checkpoint is in `args.dir`.
pub fn resume(args: &ResumeArgs) -> Result<()> {
    let (path, quiet) = (args.dir.as_path(), args.quiet);
    spraysim::check_threads(args.threads)?;
    if !path.is_dir() {
        anyhow::bail!("cannot resume: {} is not a directory", path.display());
    }
    // Locked first: a second resume of the same run is refused before it reads anything.
    let dir = lock(path).context("cannot resume")?;
    let ck = checkpoint::read_checkpoint(path).context("cannot resume")?;
    if let Some(warning) = checkpoint::check_belongs(&dir, &ck).context("cannot resume")? {
        eprintln!("warning: {warning}");
    }
    let origin = path.join(checkpoint::CHECKPOINT_FILE).display().to_string();
    let scenario = Scenario::from_toml(&ck.scenario, &origin)?;
    let mut recorder = recorder::recorder(&scenario)?;
    let mut sim = scenario.build()?;
    sim.restore_state(&ck.state).with_context(|| format!("{origin}: cannot resume"))?;
    // Views due before the checkpoint's time show states this process never had.
    recorder.skip_before(sim.time());
    sim.set_threads(args.threads)?;
    let backend = crate::backend::attach(&mut sim, &scenario)?;
    if !quiet {
        say!("resuming at t = {:.3} s of {} s", sim.time(), scenario.simulation().duration);
    }
    let every = (ck.every_steps > 0).then_some(ck.every_steps);
    execute(&scenario, sim, &dir, (every, recorder), (quiet, false), backend.as_deref())
}

/// Steps `sim` to its end or to an interrupt, with checkpoints every `every` steps and the 3D
/// views `recorder` draws, and writes its outputs, views included, into `dir` as one set; its
/// sanity warnings go into the summary (to stderr when `quiet`), and with `strict` make an
/// error once the outputs are written. `backend` says what flew the particles, where it was not
/// the CPU.
fn execute(
    scenario: &Scenario,
    mut sim: Simulation,
    dir: &OutputDir,
    (every, mut recorder): (Option<u64>, Recorder),
    (quiet, strict): (bool, bool),
    backend: Option<&str>,
) -> Result<()> {
    control::watch_interrupts()?;
    let save = |sim: &Simulation, k: u64| {
        let ck =
            checkpoint::Checkpoint { scenario: scenario.to_toml(), every_steps: k, state: sim.save_state() };
        checkpoint::write_checkpoint(dir, &ck)
            .with_context(|| format!("writing a checkpoint into {}", dir.path().display()))
    };
    let bar = progress_bar(&sim, quiet);
    let (start, redraw) = (Instant::now(), (sim.total_steps() / 200).max(1));
    recorder.observe(&sim)?;
    while !sim.is_finished() && !control::stop_requested() {
        // A call at a time (an epoch, or several on the GPU), stopping where a checkpoint, a view
        // or a pause point is due.
        let now = sim.steps_done();
        let stops = [
            every.map(|k| k - now % k),
            recorder.steps_to_next(&sim),
            control::next_pause(now).map(|s| s - now),
        ];
        let k = stops.into_iter().flatten().fold(sim.steps_to_call_end(), u64::min);
        sim.advance_call(k);
        recorder.observe(&sim)?;
        if sim.steps_done() / redraw > now / redraw || sim.is_finished() {
            show_progress(&bar, &sim, start);
        }
        if let Some(k) = every.filter(|&k| sim.steps_done().is_multiple_of(k) && !sim.is_finished()) {
            save(&sim, k)?;
        }
        control::after_step(sim.steps_done());
    }
    bar.finish_and_clear();
    let wall = start.elapsed().as_secs_f64();
    let completed = sim.is_finished();
    if !completed {
        eprintln!(
            "interrupted at t = {:.6} s of {} s: writing the outputs so far, marked \"completed\": false",
            sim.time(),
            scenario.simulation().duration
        );
        if let Some(k) = every {
            save(&sim, k)?;
        }
    }
    let views = recorder.finish(&sim, quiet)?;
    let files = spraysim::output::write_outputs_with(&sim, scenario, dir, views, &RunControl)
        .with_context(|| format!("writing outputs to {}", dir.path().display()))?;
    if control::abort_requested() {
        // A second Ctrl-C came while the files moved into place: they are, so stop now.
        std::process::exit(INTERRUPTED);
    }
    if completed {
        checkpoint::remove_checkpoint(dir);
    }
    let metrics = sim.metrics();
    let warnings = sanity::after_run(scenario, &metrics);
    if let Some(e) = sim.flight_stage_error() {
        eprintln!("warning: the GPU declined some steps, which ran on the CPU: {e}");
    }
    if quiet {
        print_warnings(&warnings);
    } else {
        crate::summary::print(&metrics, scenario, &warnings, wall)?;
        if let Some(backend) = backend {
            say!("particles flown on: {backend}");
        }
        say!("wrote {} files to {}", files.len(), dir.path().display());
    }
    if !completed {
        let resume = if every.is_some() {
            format!("; `spraysim resume {}` continues it", dir.path().display())
        } else {
            String::new()
        };
        eprintln!("run interrupted at t = {:.6} s: the outputs hold the run so far{resume}", sim.time());
        std::io::stdout().flush()?;
        std::process::exit(INTERRUPTED);
    }
    match strict_refusal(&warnings).filter(|_| strict) {
        Some(refusal) => Err(refusal.context(format!("the outputs are in {}", dir.path().display()))),
        None => Ok(()),
    }
}

/// The run's progress bar (hidden when `quiet`), at `sim`'s step.
fn progress_bar(sim: &Simulation, quiet: bool) -> ProgressBar {
    let bar = if quiet { ProgressBar::hidden() } else { ProgressBar::new(sim.total_steps()) };
    bar.set_style(
        ProgressStyle::with_template(
            "{bar:40.cyan/blue} {percent:>3}% t = {msg} [{elapsed_precise}, eta {eta}]",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_position(sim.steps_done());
    bar
}

/// Moves `bar` to `s`'s step, with its simulated time, speed against real time since `start`
/// and particles in flight.
fn show_progress(bar: &ProgressBar, s: &Simulation, start: Instant) {
    let wall = start.elapsed().as_secs_f64().max(1e-9);
    bar.set_position(s.steps_done());
    bar.set_message(format!(
        "{:.3} s, {:.2}× real time, {} in flight",
        s.time(),
        s.time() / wall,
        s.swarm().alive()
    ));
}
