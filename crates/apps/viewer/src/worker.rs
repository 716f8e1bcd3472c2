//! The simulation thread: it owns the [`Simulation`], steps it at the chosen speed, watches it
//! through the engine's observer seam ([`EventHandler`]) and publishes what the window shows
//! (a [`Scene`] and the metrics) for the window to pick up. The window never waits for a step.

use spraysim::events::{EmissionEvent, EventHandler, FailureEvent};
use spraysim::{Metrics, Simulation};
use spraysim_render::{Scene, SceneOptions};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// What the window asks of the simulation thread.
#[derive(Clone, Debug)]
pub enum Command {
    /// Run (true) or pause (false).
    Play(bool),
    /// One step, then pause.
    Step,
    /// Simulated seconds per real second; `None`: as fast as possible.
    Speed(Option<f64>),
    /// Back to time 0.
    Restart,
    /// New drawing options.
    Options(SceneOptions),
}

/// What the simulation thread learns through the observer seam.
#[derive(Clone, Debug, Default)]
pub struct Watched {
    /// Particles emitted so far.
    pub emitted: u64,
    /// Cohesive failures so far (time, target, area in m²).
    pub failures: Vec<(f64, String, f64)>,
    /// End of the last step, s.
    pub time: f64,
}

impl EventHandler for Watched {
    fn emission(&mut self, event: &EmissionEvent) {
        self.emitted += event.count;
    }

    fn failure(&mut self, event: &FailureEvent) {
        self.failures.push((event.time, event.target.clone(), event.area));
    }

    fn step_end(&mut self, time: f64) {
        self.time = time;
    }
}

/// One published state of the run.
pub struct Published {
    /// What to draw.
    pub scene: Scene,
    /// The run's metrics (refreshed a few times a second).
    pub metrics: Arc<Metrics>,
    /// What the observer saw.
    pub watched: Watched,
    /// Whether the run is going.
    pub playing: bool,
    /// Whether the run has reached its duration.
    pub finished: bool,
    /// Simulated seconds per wall second over the last second.
    pub achieved_speed: f64,
}

/// The mailbox between the threads: the latest state, and the most particles to draw.
#[derive(Default)]
pub struct Shared {
    /// The latest published state, taken by the window.
    pub latest: Mutex<Option<Published>>,
    /// Most particles drawn (set by the window from its frame rate).
    pub max_particles: AtomicUsize,
}

/// Most wall time spent stepping before publishing, so the view keeps moving.
const BUDGET: Duration = Duration::from_millis(40);

/// The simulation thread's state.
pub struct Worker {
    initial: Simulation,
    sim: Simulation,
    watched: Watched,
    options: SceneOptions,
    playing: bool,
    speed: Option<f64>,
    /// Wall time and simulated time when the pace was last set.
    anchor: (Instant, f64),
    metrics: (Instant, Arc<Metrics>),
    rate: (Instant, f64, f64),
    shared: Arc<Shared>,
    wake: Box<dyn Fn() + Send>,
}

impl Worker {
    /// A worker over `sim` (restarts go back to it), publishing into `shared` and calling
    /// `wake` after each publication.
    pub fn new(
        sim: Simulation,
        options: SceneOptions,
        shared: Arc<Shared>,
        wake: Box<dyn Fn() + Send>,
    ) -> Worker {
        let now = Instant::now();
        let metrics = Arc::new(sim.metrics());
        Worker {
            initial: sim.clone(),
            sim,
            watched: Watched::default(),
            options,
            playing: true,
            speed: Some(1.0),
            anchor: (now, 0.0),
            metrics: (now, metrics),
            rate: (now, 0.0, 0.0),
            shared,
            wake,
        }
    }

    /// Runs until the window hangs up.
    pub fn run(mut self, commands: Receiver<Command>) {
        self.publish();
        let mut published = Instant::now();
        let mut changed = false;
        loop {
            let wait = if self.playing { Duration::ZERO } else { Duration::from_millis(100) };
            match commands.recv_timeout(wait) {
                Ok(c) => changed |= self.apply(c),
                Err(RecvTimeoutError::Disconnected) => return,
                Err(RecvTimeoutError::Timeout) => {}
            }
            while let Ok(c) = commands.try_recv() {
                changed |= self.apply(c);
            }
            if self.playing {
                changed |= self.advance();
            }
            // At most one scene a frame of a 30 Hz display: building one costs time too.
            if changed && (!self.playing || published.elapsed() >= Duration::from_millis(33)) {
                self.publish();
                published = Instant::now();
                changed = false;
            }
        }
    }

    /// Applies a command; true if the view changes.
    fn apply(&mut self, c: Command) -> bool {
        match c {
            Command::Play(on) => {
                self.playing = on && !self.sim.is_finished();
                self.anchor = (Instant::now(), self.sim.time());
            }
            Command::Step => {
                self.playing = false;
                self.sim.step_with(&mut self.watched);
            }
            Command::Speed(s) => {
                self.speed = s;
                self.anchor = (Instant::now(), self.sim.time());
            }
            Command::Restart => {
                self.sim = self.initial.clone();
                self.watched = Watched::default();
                self.anchor = (Instant::now(), 0.0);
                self.metrics.0 = Instant::now() - Duration::from_secs(1);
            }
            Command::Options(o) => self.options = o,
        }
        true
    }

    /// Steps towards where real time (times the speed) says the run should be, for at most
    /// [`BUDGET`]; true if it stepped.
    fn advance(&mut self) -> bool {
        let start = Instant::now();
        let target = self.speed.map(|s| self.anchor.1 + self.anchor.0.elapsed().as_secs_f64() * s);
        let mut stepped = false;
        while !self.sim.is_finished()
            && target.is_none_or(|t| self.sim.time() < t)
            && start.elapsed() < BUDGET
        {
            self.sim.step_with(&mut self.watched);
            stepped = true;
        }
        if let (Some(t), Some(s)) = (target, self.speed)
            && t - self.sim.time() > 0.25 * s
        {
            // Slower than asked: go on from here rather than racing to catch up.
            self.anchor = (Instant::now(), self.sim.time());
        }
        if self.sim.is_finished() {
            self.playing = false;
            stepped = true;
        }
        if !stepped {
            std::thread::sleep(Duration::from_millis(2));
        }
        stepped
    }

    fn publish(&mut self) {
        let now = Instant::now();
        if now.duration_since(self.metrics.0) > Duration::from_millis(250) || !self.playing {
            self.metrics = (now, Arc::new(self.sim.metrics()));
        }
        let elapsed = now.duration_since(self.rate.0).as_secs_f64();
        if elapsed > 1.0 {
            self.rate = (now, self.sim.time(), (self.sim.time() - self.rate.1).max(0.0) / elapsed);
        }
        let mut options = self.options.clone();
        options.max_particles = self.shared.max_particles.load(Ordering::Relaxed).max(1);
        let published = Published {
            scene: Scene::build(&self.sim, &options),
            metrics: self.metrics.1.clone(),
            watched: self.watched.clone(),
            playing: self.playing,
            finished: self.sim.is_finished(),
            achieved_speed: self.rate.2,
        };
        if let Ok(mut slot) = self.shared.latest.lock() {
            *slot = Some(published);
        }
        (self.wake)();
    }
}
