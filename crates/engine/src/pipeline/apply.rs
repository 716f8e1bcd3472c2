//! Apply stage: the update stage's impact records are applied to the deposits and tallies in
//! particle order (so the result does not depend on the thread count), and the impacts
//! gathered as events reach the event handler in the same order.

use super::State;
use super::update::{ChunkOutcome, ImpactRecord, record};
use crate::collision::{SurfaceId, SurfaceKind};
use crate::events::EventHandler;
use crate::particles::flags;
use crate::world::Impact;

/// Applies every chunk's records, in chunk order.
pub(super) fn run(state: &mut State, outcomes: Vec<ChunkOutcome>, events: &mut dyn EventHandler) {
    for out in outcomes {
        out.watch.iter().for_each(|w| state.watches.add(w));
        for rec in &out.impacts {
            book(state, rec.surface, &impact_of(rec));
        }
        add_totals(state, &out);
        for e in &out.events {
            events.impact(e);
        }
    }
    debug_assert_eq!(state.retired, state.swarm.flags.iter().filter(|&&f| f & flags::ALIVE == 0).count());
}

/// The impact a record stands for.
fn impact_of(rec: &ImpactRecord) -> Impact {
    let has = |flag: u8| rec.flags & flag != 0;
    Impact {
        cell: rec.cell,
        volume: f64::from(rec.volume),
        eroded: (f64::from(rec.eroded_coat), f64::from(rec.eroded_sub)),
        back: has(record::BACK),
        stuck: has(record::STUCK),
        released: has(record::RELEASED),
        loose: has(record::LOOSE),
        rebound: has(record::REBOUND),
        first_substrate: has(record::FIRST_SUBSTRATE),
    }
}

/// Books `impact` on the target or obstacle whose piece `surface` it struck, and a first
/// impact on a substrate in the run's tally.
fn book(state: &mut State, surface: SurfaceId, impact: &Impact) {
    match state.scene.surface(surface).kind {
        SurfaceKind::Target(i) => state.targets[i].record_impact(impact),
        SurfaceKind::Obstacle(i) => state.obstacles[i].record_impact(impact),
    }
    if impact.first_substrate {
        state.tally.first_substrate_impact(impact.volume, impact.stuck);
    }
}

/// Adds a chunk's losses (particles that left the domain or expired) and its counts of
/// retired and updated particles to the run's.
fn add_totals(state: &mut State, out: &ChunkOutcome) {
    let t = &mut state.tally;
    t.left_domain = t.left_domain + out.left_domain;
    t.expired = t.expired + out.expired;
    t.released_left = t.released_left + out.released_left;
    t.released_expired = t.released_expired + out.released_expired;
    state.retired += out.retired;
    state.particle_updates += out.updated;
}
