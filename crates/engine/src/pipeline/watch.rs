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
use crate::collision::Arc;
use crate::config::SimulationConfig;
use crate::deposit::{DepositSurface, Nodes};
use crate::particles::Swarm;

/// Entries below which stale ones are kept.
const PRUNE_FLOOR: usize = 4096;

/// One sleeping flight's watch over nodes of one target's bounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Watch {
    /// The particle.
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

    /// Drops the entries whose particle no longer sleeps until the entry's step, after step
    /// `now` (which could wake nothing), once they are half as many again as after the last
    /// pruning.
    fn prune(&mut self, swarm: &Swarm, now: u64) {
        if self.entries <= self.prune_at {
            return;
        }
        let sleeping = |e: &Entry| {
            u64::from(e.wake) > now && swarm.id.binary_search(&e.id).is_ok_and(|i| swarm.wake[i] == e.wake)
        };
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
    state.watches.prune(&state.swarm, now);
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

/// Brings sleeping particle `i` back from the step it sleeps until to step `now` (in closed
/// form), to be updated then.
fn rewind(config: &SimulationConfig, s: &mut Swarm, i: usize, now: u64) {
    let wake = u64::from(s.wake[i]);
    if wake > now {
        let back = -((wake - now) as f64 * config.dt);
        let flight = Arc { x0: s.pos[i], v0: s.vel[i], g: config.motion.gravity, duration: 0.0 };
        s.pos[i] = flight.at(back);
        s.vel[i] = flight.velocity(back);
        s.age[i] = (f64::from(s.age[i]) + back) as f32;
    }
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

    /// Regression: a flight put to sleep over a layer must meet the layer that grows into its
    /// path while it sleeps, not the bare surface under it (which it would if nothing woke it:
    /// it would wake inside the layer, and a path that starts inside a layer never enters it).
    #[test]
    fn a_sleeping_flight_meets_the_layer_grown_into_its_path() {
        let mut config = SimulationConfig::example_wall(1.0);
        config.motion.integrator = Integrator::Exact;
        // Slow enough that particles sleep for several steps on their last stretch.
        config.emitter.speed = [2.0, 3.0];
        let mut sim = Simulation::new(config).expect("the example is valid");
        // A particle on its way to the wall that watches it, asleep for a few more steps, 2 cm
        // or more from it (the wall's receiving side faces −x from x = 0: the height above it
        // is −x).
        let (id, height) = loop {
            sim.step();
            assert!(!sim.is_finished(), "no particle slept over the wall");
            let s = &sim.state;
            let watched = s.watches.targets[0].iter().flat_map(|l| l.entries.iter().flatten());
            let asleep = watched.filter_map(|e| {
                let i = s.swarm.id.binary_search(&e.id).ok()?;
                let (x, v, _) = sim.particle_now(i);
                let height = -x.x;
                (s.swarm.wake[i] == e.wake && u64::from(e.wake) > s.step + 3 && height > 0.02 && v.x > 1.0)
                    .then_some((e.id, height))
            });
            if let Some(found) = asleep.min_by_key(|&(id, _)| id) {
                break found;
            }
        };
        // The layer rises everywhere to 5 mm below the particle.
        let layer = height - 0.005;
        let wall = &mut sim.state.targets[0].surface;
        for cell in 0..wall.thickness().len() as u32 {
            wall.add_thickness(cell, layer);
        }
        // Its watch wakes it (the broad phase would too, at the end of the step, for a layer
        // this much thicker than before: the watch must not rely on that).
        super::run(&sim.config, &mut sim.state);
        let i = sim.state.swarm.id.binary_search(&id).expect("still in flight");
        assert_eq!(sim.state.swarm.wake[i], 0, "the particle sleeps on over the grown layer");
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
}
