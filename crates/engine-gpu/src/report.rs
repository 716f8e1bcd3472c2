//! What the kernels read back for one member of a dispatch, turned into the engine's
//! [`FlightReport`]: its particles, fates, per-target and per-obstacle tallies, and the cells it
//! listed (with their deposits, impacts and wear), in cell order.

use crate::dispatch::Raw;
use crate::pack::{GpuParticle, OBSTACLE_COUNTER_WORDS, SceneWords, TALLY_WORDS, TARGET_COUNTER_WORDS};
use rayon::prelude::*;
use spraysim_engine::pipeline::{CellBook, FlightJob, FlightReport};
use spraysim_engine::tally::{Quanta, Tallied, Tally};
use spraysim_engine::world::{ObstacleTally, TargetTally};

/// A Tallied from a counter slot (count, quanta low, quanta high).
fn tallied(w: &[u32], at: usize) -> Tallied {
    Tallied { count: u64::from(w[at]), quanta: Quanta::from(w[at + 1]) | (Quanta::from(w[at + 2]) << 32) }
}

/// The report of `job` (laid out as `scene`) from what its member of a dispatch read back: its
/// particles still in flight, its counter block, and the cells it listed with their wear (none where no
/// target erodes).
pub(crate) fn report(job: &FlightJob<'_>, scene: &SceneWords, raw: &Raw) -> FlightReport {
    let (w, listed, wear) = (&raw.counters, &raw.listed, &raw.wear);
    let particles = raw.slots.par_iter().filter(|g| g.is_alive()).map(GpuParticle::particle).collect();
    let slot = |k: usize| tallied(w, 4 + 4 * k);
    let tally = Tally {
        left_domain: slot(0),
        expired: slot(1),
        overspray: slot(2),
        substrate_first_impacts: slot(3),
        substrate_first_rebounds: slot(4),
        released_left: slot(5),
        released_expired: slot(6),
        ..Tally::default()
    };
    let targets = (0..job.targets.len())
        .map(|t| {
            let at = TALLY_WORDS + TARGET_COUNTER_WORDS * t;
            let s = |k: usize| tallied(w, at + 4 * k);
            TargetTally {
                hits: u64::from(w[at]),
                stuck: s(1),
                loose: s(2),
                trapped: s(3),
                delivered: s(4),
                stuck_back: s(5),
                received: s(6),
                // A volume alone: its low and high words start the slot.
                received_back: Quanta::from(w[at + 28]) | (Quanta::from(w[at + 29]) << 32),
                detached: Tallied::default(),
            }
        })
        .collect();
    let base = TALLY_WORDS + TARGET_COUNTER_WORDS * job.targets.len();
    let obstacles = (0..job.config.obstacles.len())
        .map(|o| {
            let at = base + OBSTACLE_COUNTER_WORDS * o;
            ObstacleTally { hits: u64::from(w[at]), stuck: tallied(w, at + 4), received: tallied(w, at + 8) }
        })
        .collect();
    let mut cells: Vec<Vec<CellBook>> = vec![Vec::new(); job.targets.len()];
    let pair = |lo: u32, hi: u32| u64::from(lo) | (u64::from(hi) << 32);
    for (k, &[cell, lo, hi, hits]) in listed.iter().enumerate() {
        // The target whose grid holds the cell: the last whose first cell is not past it.
        let t = scene.first_cells.partition_point(|&f| f <= cell).saturating_sub(1);
        let wear = wear.get(k).map_or([0, 0], |w| [pair(w[0], w[1]), pair(w[2], w[3])]);
        cells[t].push(CellBook { cell: cell - scene.first_cells[t], quanta: pair(lo, hi), hits, wear });
    }
    // In cell order, whatever order the invocations listed them in.
    cells.iter_mut().for_each(|c| c.sort_unstable_by_key(|b| b.cell));
    let steps = u64::from(w[0]) | (u64::from(w[1]) << 32);
    FlightReport { particles, tally, targets, obstacles, cells, steps, updates: steps }
}
