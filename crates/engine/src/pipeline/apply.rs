//! Apply stage: the update stage's impact records are applied to the deposits and tallies in
//! particle order (so the result does not depend on the thread count), and the impacts
//! gathered as events reach the event handler in the same order.

use super::State;
use super::update::{ChunkOutcome, record};
use crate::collision::SurfaceKind;
use crate::deposit::DepositSurface;
use crate::events::EventHandler;
use crate::particles::flags;

/// Applies every chunk's records, in chunk order.
pub(super) fn run(state: &mut State, outcomes: Vec<ChunkOutcome>, events: &mut dyn EventHandler) {
    for out in outcomes {
        out.watch.iter().for_each(|w| state.watches.add(w));
        for rec in &out.impacts {
            let volume = f64::from(rec.volume);
            let stuck = rec.flags & record::STUCK != 0;
            let released = rec.flags & record::RELEASED != 0;
            let back = rec.flags & record::BACK != 0;
            match state.scene.surface(rec.surface).kind {
                SurfaceKind::Target(i) => {
                    let t = &mut state.targets[i];
                    t.hits += 1;
                    if !back {
                        t.surface.add_hit(rec.cell);
                        if let Some(e) = &mut t.erosion {
                            let area = t.surface.cell_area(rec.cell);
                            e.wear(
                                rec.cell as usize,
                                area,
                                f64::from(rec.eroded_coat),
                                f64::from(rec.eroded_sub),
                            );
                        }
                    }
                    if stuck {
                        if !back {
                            t.surface.deposit(rec.cell, volume);
                        }
                        match (released, back) {
                            (true, _) => {
                                t.received.add(volume);
                                if back {
                                    t.received_back += volume;
                                }
                            }
                            (false, true) => t.stuck_back.add(volume),
                            (false, false) => {
                                t.stuck.add(volume);
                                if rec.flags & record::LOOSE != 0 {
                                    t.loose.add(volume);
                                } else if rec.flags & record::REBOUND != 0 {
                                    t.trapped.add(volume);
                                }
                            }
                        }
                    }
                }
                SurfaceKind::Obstacle(i) => {
                    let o = &mut state.obstacles[i];
                    o.hits += 1;
                    if stuck {
                        if released { &mut o.received } else { &mut o.stuck }.add(volume);
                    }
                }
            }
            if rec.flags & record::FIRST_SUBSTRATE != 0 {
                if let SurfaceKind::Target(i) = state.scene.surface(rec.surface).kind {
                    state.targets[i].delivered.add(volume);
                }
                state.tally.substrate_first_impacts.add(volume);
                if !stuck {
                    state.tally.substrate_first_rebounds.add(volume);
                }
            }
        }
        let t = &mut state.tally;
        t.left_domain = t.left_domain + out.left_domain;
        t.expired = t.expired + out.expired;
        t.released_left = t.released_left + out.released_left;
        t.released_expired = t.released_expired + out.released_expired;
        state.retired += out.retired;
        state.particle_updates += out.updated;
        for e in &out.events {
            events.impact(e);
        }
    }
    debug_assert_eq!(state.retired, state.swarm.flags.iter().filter(|&&f| f & flags::ALIVE == 0).count());
}
