//! Watch stage: wakes the sleeping particles whose predicted flight a layer has grown under.
//!
//! A particle put to sleep over a deposited layer (see `update.rs`) watches the nodes of the
//! layer's bounds that its flight passes over, with the least height of its flight above the
//! bare surface. Once the layers have changed in a step (deposits, layer stages), every
//! watched node whose bound has reached a watcher's height wakes that watcher: it is brought
//! back to the present in closed form, and stepped and predicted again from the next step.
//! Only those particles: growth elsewhere costs nothing.

use super::State;
use crate::checkpoint::{Dec, Enc, StateError};
use crate::collision::{Aabb, Flight};
use crate::config::SimulationConfig;
use crate::deposit::{DepositSurface, Nodes};
use crate::particles::Swarm;

/// Margin around a sleeping flight's box when testing it against a grown zone, m.
const ZONE_MARGIN: f64 = 1e-6;

/// Entries below which stale ones are kept.
const PRUNE_FLOOR: usize = 4096;

/// One sleeping flight's watch over nodes of one target's bounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Watch {
    /// The sleeping particle's emission index (its `Swarm::id`).
    pub id: u32,
    /// The step it sleeps until: once it has woken, the watch is stale.
    pub wake: u32,
    /// Index of the target.
    pub target: u32,
    /// The nodes under the flight.
    pub nodes: Nodes,
    /// Least height of the flight above the bare surface, m, rounded down.
    pub height: f32,
}

/// A watcher of one node.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Entry {
    id: u32,
    wake: u32,
    height: f32,
}

/// The watched nodes of one level of a target's bounds, by node index (row-major).
#[derive(Clone, Debug, Default)]
struct Level {
    /// Nodes per row.
    stride: u32,
    /// Per node, the lowest height watched, m (infinite: none).
    low: Vec<f32>,
    /// Per node, its watchers.
    entries: Vec<Vec<Entry>>,
    /// The nodes with watchers, in the order they gained their first.
    active: Vec<u32>,
}

impl Level {
    /// Wakes (pushes to `woken`) the watchers of node `n` at or below `bound` (m); true if
    /// none is left.
    fn trip(&mut self, n: usize, bound: f64, woken: &mut Vec<(u32, u32)>) -> bool {
        let entries = &mut self.entries[n];
        entries.retain(|e| {
            let keep = f64::from(e.height) > bound;
            if !keep {
                woken.push((e.id, e.wake));
            }
            keep
        });
        self.low[n] = lowest(entries);
        trim(entries);
        entries.is_empty()
    }
}

/// Gives back the room of a list that has shrunk to under a quarter of it.
fn trim(entries: &mut Vec<Entry>) {
    if entries.capacity() > 4 * entries.len() {
        entries.shrink_to(2 * entries.len());
    }
}

/// The lowest height of `entries`, m (infinite if none).
fn lowest(entries: &[Entry]) -> f32 {
    entries.iter().map(|e| e.height).fold(f32::INFINITY, f32::min)
}

/// Every target's watched nodes, by target and level; visited in that fixed order. An entry
/// whose particle was woken and sleeps again until the same step counts again: at worst it
/// wakes the particle early, never too late.
#[derive(Clone, Debug, Default)]
pub(crate) struct Watches {
    targets: Vec<Vec<Level>>,
    /// Entries held, stale ones included.
    entries: usize,
    /// Entries past which the stale ones are dropped.
    prune_at: usize,
}

impl Watches {
    /// No watches, over `targets` targets.
    pub(crate) fn new(targets: usize) -> Watches {
        Watches { targets: vec![Vec::new(); targets], entries: 0, prune_at: PRUNE_FLOOR }
    }

    /// Adds `w` to each node it covers.
    pub(crate) fn add(&mut self, w: &Watch) {
        let Some(levels) = self.targets.get_mut(w.target as usize) else { return };
        let k = w.nodes.level as usize;
        if levels.len() <= k {
            levels.resize_with(k + 1, Level::default);
        }
        let level = &mut levels[k];
        level.stride = w.nodes.stride;
        let entry = Entry { id: w.id, wake: w.wake, height: w.height };
        for row in w.nodes.rows.0..=w.nodes.rows.1 {
            for col in w.nodes.cols.0..=w.nodes.cols.1 {
                let n = (row * w.nodes.stride + col) as usize;
                if level.low.len() <= n {
                    level.low.resize(n + 1, f32::INFINITY);
                    level.entries.resize_with(n + 1, Vec::new);
                }
                if level.entries[n].is_empty() {
                    level.active.push(n as u32);
                }
                level.low[n] = level.low[n].min(w.height);
                level.entries[n].push(entry);
                self.entries += 1;
            }
        }
    }

    /// Heap memory held, bytes.
    pub(crate) fn heap_bytes(&self) -> usize {
        use std::mem::size_of;
        let level = |l: &Level| {
            l.low.capacity() * size_of::<f32>()
                + l.entries.capacity() * size_of::<Vec<Entry>>()
                + l.entries.iter().map(|e| e.capacity() * size_of::<Entry>()).sum::<usize>()
                + l.active.capacity() * size_of::<u32>()
        };
        self.targets
            .iter()
            .map(|t| t.capacity() * size_of::<Level>() + t.iter().map(level).sum::<usize>())
            .sum()
    }

    /// Forgets every watch (every sleeper was woken).
    pub(crate) fn clear(&mut self) {
        self.targets.iter_mut().for_each(Vec::clear);
        self.entries = 0;
        self.prune_at = PRUNE_FLOOR;
    }

    /// Drops the entries whose step has passed by step `now` (which could wake nothing), once
    /// they are half as many again as after the last pruning. An entry whose particle was
    /// woken early and sleeps until another step stays until its own step has passed: told by
    /// the entry alone, without looking the particle up in the swarm (a search per entry,
    /// in the serial part of a step). Until then it wakes nothing, unless the particle
    /// happens to sleep until that step again, which wakes it early, never late.
    fn prune(&mut self, now: u64) {
        if self.entries <= self.prune_at {
            return;
        }
        let sleeping = |e: &Entry| u64::from(e.wake) > now;
        self.entries = 0;
        for level in self.targets.iter_mut().flatten() {
            let (low, entries) = (&mut level.low, &mut level.entries);
            level.active.retain(|&n| {
                let n = n as usize;
                entries[n].retain(sleeping);
                trim(&mut entries[n]);
                low[n] = lowest(&entries[n]);
                self.entries += entries[n].len();
                !entries[n].is_empty()
            });
        }
        self.prune_at = (self.entries + self.entries / 2).max(PRUNE_FLOOR);
    }

    pub(crate) fn save_state(&self, e: &mut Enc) {
        e.usize(self.prune_at);
        e.list(&self.targets, |e, levels| {
            e.list(levels, |e, level| {
                e.u32(level.stride);
                e.list(&level.entries, |e, entries| {
                    e.list(entries, |e, x| {
                        e.u32(x.id);
                        e.u32(x.wake);
                        e.f32(x.height);
                    });
                });
                e.list(&level.active, |e, &n| e.u32(n));
            });
        });
    }

    pub(crate) fn load_state(d: &mut Dec<'_>, targets: usize) -> Result<Watches, StateError> {
        let entry = |d: &mut Dec<'_>| Ok(Entry { id: d.u32()?, wake: d.u32()?, height: d.f32()? });
        let level = |d: &mut Dec<'_>| {
            let stride = d.u32()?;
            let entries: Vec<Vec<Entry>> = d.list(8, |d| d.list(12, entry))?;
            let active = d.list(4, Dec::u32)?;
            if active.iter().any(|&n| entries.get(n as usize).is_none_or(Vec::is_empty)) {
                return Err(StateError::Mismatch("a watched node without watchers".into()));
            }
            if stride == 0 && !active.is_empty() {
                return Err(StateError::Mismatch("watched nodes in a level without columns".into()));
            }
            Ok(Level { stride, low: entries.iter().map(|e| lowest(e)).collect(), entries, active })
        };
        let prune_at = d.usize()?;
        let levels = d.list_of(targets, "the watches", 8, |d| d.list(12, level))?;
        let entries = levels.iter().flatten().flat_map(|l| &l.entries).map(Vec::len).sum();
        Ok(Watches { targets: levels, entries, prune_at })
    }
}

/// Wakes the watchers of every node whose bound has reached their height, in a fixed order.
pub(super) fn run(config: &SimulationConfig, state: &mut State) {
    let mut woken = Vec::new();
    for (levels, target) in state.watches.targets.iter_mut().zip(&state.targets) {
        for (k, level) in levels.iter_mut().enumerate() {
            let mut emptied = false;
            for a in 0..level.active.len() {
                let n = level.active[a];
                let (row, col) = (n / level.stride, n % level.stride);
                let bound = target.surface.node_bound(k as u32, col, row);
                if f64::from(level.low[n as usize]) <= bound {
                    emptied |= level.trip(n as usize, bound, &mut woken);
                }
            }
            if emptied {
                let entries = &level.entries;
                level.active.retain(|&n| !entries[n as usize].is_empty());
            }
        }
    }
    state.watches.entries -= woken.len();
    let now = state.step + 1;
    for (id, wake) in woken {
        if let Ok(i) = state.swarm.id.binary_search(&id)
            && state.swarm.wake[i] == wake
        {
            rewind(config, &mut state.swarm, i, now);
        }
    }
    // Stale entries pile up where layers do not grow.
    state.watches.prune(now);
}

/// Brings back to the present the sleeping particles whose flight, from the next step to the
/// one they sleep until, comes near one of `zones` (boxes, m: where a layer's allowance in the
/// broad phase has grown, which their sleep did not allow for).
pub(super) fn wake_near(config: &SimulationConfig, state: &mut State, zones: &[Aabb]) {
    let now = state.step + 1;
    let s = &mut state.swarm;
    for i in 0..s.len() {
        let Some(rest) = rest_of_flight(config, s, i, now) else { continue };
        // Grown by far more than the rounding between this flight and the one stepped later.
        let near = rest.aabb().inflate(ZONE_MARGIN);
        if zones.iter().any(|z| z.overlaps(&near)) {
            resume(s, i, &rest);
        }
    }
}

/// Brings every sleeping particle back to the present (in closed form) so that it is updated
/// next step, and forgets every watch.
pub(super) fn wake_all(config: &SimulationConfig, state: &mut State) {
    let now = state.step + 1;
    for i in 0..state.swarm.len() {
        rewind(config, &mut state.swarm, i, now);
    }
    state.watches.clear();
}

/// The rest of sleeping particle `i`'s flight, from step `now` to the step it sleeps until (in
/// closed form, back from where it sleeps); `None` if it does not sleep past `now`.
fn rest_of_flight(config: &SimulationConfig, s: &Swarm, i: usize, now: u64) -> Option<Flight> {
    let wake = u64::from(s.wake[i]);
    (wake > now).then(|| {
        let back = (wake - now) as f64 * config.dt;
        let end = Flight { x0: s.pos[i], v0: s.vel[i], g: config.motion.gravity, duration: 0.0 };
        Flight { x0: end.at(-back), v0: end.velocity(-back), g: end.g, duration: back }
    })
}

/// Brings sleeping particle `i` back from the step it sleeps until to step `now` (in closed
/// form), to be updated then.
fn rewind(config: &SimulationConfig, s: &mut Swarm, i: usize, now: u64) {
    match rest_of_flight(config, s, i, now) {
        Some(rest) => resume(s, i, &rest),
        None => s.wake[i] = 0,
    }
}

/// Puts sleeping particle `i` at the start of `rest`, the rest of its flight, awake.
fn resume(s: &mut Swarm, i: usize, rest: &Flight) {
    s.pos[i] = rest.x0;
    s.vel[i] = rest.v0;
    s.age[i] = (f64::from(s.age[i]) - rest.duration) as f32;
    s.wake[i] = 0;
}

#[cfg(test)]
mod tests {
    use crate::deposit::DepositSurface;
    use crate::events::{EventHandler, ImpactEvent};
    use crate::motion::Integrator;
    use crate::{Simulation, SimulationConfig};

    /// The impacts of one particle.
    struct Impacts(u32, Vec<ImpactEvent>);

    impl EventHandler for Impacts {
        fn wants_impacts(&self) -> bool {
            true
        }
        fn impact(&mut self, e: &ImpactEvent) {
            if e.particle == self.0 {
                self.1.push(*e);
            }
        }
    }

    /// The example wall with the exact integrator and particles slow enough (2 to 3 m/s) to
    /// sleep for several steps near the wall.
    fn slow_wall() -> Simulation {
        let mut config = SimulationConfig::example_wall(1.0);
        config.motion.integrator = Integrator::Exact;
        config.emitter.speed = [2.0, 3.0];
        Simulation::new(config).expect("the example is valid")
    }

    /// Steps `sim` until a particle on its way to the wall (the wall's receiving side faces −x
    /// from x = 0: the height above it is −x), asleep for a few more steps, at a height within
    /// `heights` (m), watches the wall or not as `watched` says; returns its id and height, the
    /// lowest id if several.
    fn sleeper(sim: &mut Simulation, watched: bool, heights: (f64, f64)) -> (u32, f64) {
        loop {
            sim.step();
            assert!(!sim.is_finished(), "no such sleeper");
            let s = &sim.state;
            let nodes = s.watches.targets[0].iter().flat_map(|l| l.entries.iter().flatten());
            let watching: Vec<(u32, u32)> = nodes.map(|e| (e.id, e.wake)).collect();
            let found = (0..s.swarm.len()).filter_map(|i| {
                let (x, v, _) = sim.particle_now(i);
                let (id, wake) = (s.swarm.id[i], s.swarm.wake[i]);
                let watches = watching.contains(&(id, wake));
                let height = -x.x;
                let within = height > heights.0 && height < heights.1;
                (u64::from(wake) > s.step + 3 && within && v.x > 1.0 && watches == watched)
                    .then_some((id, height))
            });
            if let Some(found) = found.min_by_key(|&(id, _)| id) {
                return found;
            }
        }
    }

    /// Raises the wall's layer everywhere by `layer` (m).
    fn raise_wall(sim: &mut Simulation, layer: f64) {
        let wall = &mut sim.state.targets[0].surface;
        for cell in 0..wall.thickness().len() as u32 {
            wall.add_thickness(cell, layer);
        }
    }

    /// Steps `sim` until particle `id` strikes something and asserts that it is the layer's top,
    /// `layer` (m) in front of the wall.
    fn strikes_the_layer(sim: &mut Simulation, id: u32, layer: f64) {
        let mut seen = Impacts(id, Vec::new());
        while seen.1.is_empty() && !sim.is_finished() {
            sim.step_with(&mut seen);
        }
        let first = seen.1.first().expect("the particle strikes something");
        assert!(
            (-first.position.x - layer).abs() < 1e-3,
            "struck {} m in front of the wall, the layer's top is at {layer} m",
            -first.position.x
        );
    }

    /// True if particle `id` is awake (or gone).
    fn awake(sim: &Simulation, id: u32) -> bool {
        let s = &sim.state;
        s.swarm.id.binary_search(&id).ok().is_none_or(|i| u64::from(s.swarm.wake[i]) <= s.step + 1)
    }

    /// Finds a sleeper (see [`sleeper`]), raises the wall's layer to 5 mm below it, lets `wake`
    /// react, and asserts that the particle is awake and then strikes the layer's top.
    fn meets_the_grown_layer(watched: bool, heights: (f64, f64), wake: fn(&mut Simulation)) {
        let mut sim = slow_wall();
        let (id, height) = sleeper(&mut sim, watched, heights);
        let layer = height - 0.005;
        raise_wall(&mut sim, layer);
        wake(&mut sim);
        assert!(awake(&sim, id), "the particle sleeps on into the grown layer");
        strikes_the_layer(&mut sim, id, layer);
    }

    /// Regression: a flight put to sleep over a layer must meet the layer that grows into its
    /// path while it sleeps, not the bare surface under it (which it would if nothing woke it:
    /// it would wake inside the layer, and a path that starts inside a layer never enters it).
    /// Its watch wakes it (the broad phase would too, at the end of the step, for a layer this
    /// much thicker than before: the watch must not rely on that).
    #[test]
    fn a_sleeping_flight_meets_the_layer_grown_into_its_path() {
        meets_the_grown_layer(true, (0.02, 1.0), |sim| super::run(&sim.config, &mut sim.state));
    }

    /// Regression: a flight asleep in open space (no watch: the broad phase's distance map let
    /// it sleep) must be woken when a layer's allowance grows into its path.
    #[test]
    fn a_grown_allowance_wakes_a_flight_asleep_in_open_space_that_comes_near_it() {
        meets_the_grown_layer(false, (0.1, 0.2), |sim| {
            super::super::layers::grow_allowances(&sim.config.clone(), &mut sim.state, true)
        });
    }

    /// Pruning, told by the entries alone, drops exactly those whose step has passed: every
    /// particle still asleep keeps each of its watches, and the lowest height of a node is
    /// that of what it keeps.
    #[test]
    fn pruning_keeps_every_watch_whose_step_is_to_come() {
        use super::{PRUNE_FLOOR, Watch, Watches};
        use crate::deposit::Nodes;
        let mut w = Watches::new(1);
        let nodes = |c: u32| Nodes { level: 2, cols: (c, c + 1), rows: (3, 3), stride: 64 };
        let count = PRUNE_FLOOR as u32 * 3;
        for id in 0..count {
            // Half the entries are due before step 100, half after.
            let wake = if id % 2 == 0 { 50 + id % 50 } else { 101 + id % 50 };
            let height = 0.001 * (1 + id % 7) as f32;
            w.add(&Watch { id, wake, target: 0, nodes: nodes(id % 10), height });
        }
        assert_eq!(w.entries, 2 * count as usize);
        w.prune(100);
        let level = &w.targets[0][2];
        let kept: Vec<(u32, u32)> = level.entries.iter().flatten().map(|e| (e.id, e.wake)).collect();
        assert_eq!(w.entries, kept.len());
        assert_eq!(kept.len(), count as usize, "each odd particle's two entries");
        assert!(kept.iter().all(|&(id, wake)| id % 2 == 1 && wake > 100));
        for &n in &level.active {
            assert_eq!(level.low[n as usize], super::lowest(&level.entries[n as usize]));
        }
    }

    /// A grown zone wakes the sleepers whose flight comes near it, and no others.
    #[test]
    fn a_zone_wakes_only_the_flights_that_come_near_it() {
        use crate::collision::Aabb;
        use glam::DVec3;
        let mut sim = slow_wall();
        for _ in 0..300 {
            sim.step();
        }
        let asleep = |sim: &Simulation| {
            (0..sim.state.swarm.len()).filter(|&i| !awake(sim, sim.state.swarm.id[i])).count()
        };
        let before = asleep(&sim);
        assert!(before > 100, "only {before} particles asleep");
        // Behind the wall, where nothing flies.
        let behind = Aabb { min: DVec3::new(0.5, -2.0, -1.0), max: DVec3::new(1.0, 2.0, 3.0) };
        super::wake_near(&sim.config.clone(), &mut sim.state, &[behind]);
        assert_eq!(asleep(&sim), before);
        // A slab across the flights' way from the nozzle (gravity is along z, so x(t) is
        // linear): the flights wholly past it sleep on, some that cross it are woken.
        let across = Aabb { min: DVec3::new(-0.95, -2.0, -1.0), max: DVec3::new(-0.9, 2.0, 3.0) };
        let past: Vec<u32> = {
            let s = &sim.state;
            (0..s.swarm.len())
                .filter(|&i| !awake(&sim, s.swarm.id[i]))
                .filter(|&i| {
                    let (x, v, _) = sim.particle_now(i);
                    let left = (u64::from(s.swarm.wake[i]) - s.step - 1) as f64 * sim.config.dt;
                    x.x.min(x.x + v.x * left) > -0.89
                })
                .map(|i| s.swarm.id[i])
                .collect()
        };
        assert!(!past.is_empty());
        super::wake_near(&sim.config.clone(), &mut sim.state, &[across]);
        assert!(asleep(&sim) < before, "nobody crossing the slab was woken");
        assert!(past.iter().all(|&id| !awake(&sim, id)), "a flight wholly past the slab was woken");
    }
}
