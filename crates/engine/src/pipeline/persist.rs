//! A simulation's state to bytes and back (see [`crate::checkpoint`]).

use super::{Simulation, State};
use crate::checkpoint::{Dec, Enc, STATE_VERSION, StateError};
use crate::collision::SurfaceId;
use crate::emission::NozzlePath;
use crate::events::{FailureEvent, ImpactEvent};
use crate::particles::Swarm;
use crate::tally::{Amount, Gauge};

impl Simulation {
    /// Everything this run has changed since it was set up, as bytes (see
    /// [`crate::checkpoint`]): with [`Simulation::restore_state`] on a simulation of the same
    /// configuration, the run continues bit for bit as this one would.
    pub fn save_state(&self) -> Vec<u8> {
        let mut e = Enc::default();
        e.u32(STATE_VERSION);
        save(&self.state, &mut e);
        e.0
    }

    /// Replaces this simulation's state with one [`Simulation::save_state`] wrote for a
    /// simulation of the same configuration. On an error the simulation is left unchanged.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), StateError> {
        let mut d = Dec::new(bytes);
        let found = d.u32()?;
        if found != STATE_VERSION {
            return Err(StateError::Version { found });
        }
        let mut state = self.state.clone();
        load(&mut state, &mut d)?;
        d.finish()?;
        if state.step > self.plan.total_steps.max(1) * 2 {
            return Err(StateError::Mismatch(format!("step {} is far past the run's end", state.step)));
        }
        self.state = state;
        Ok(())
    }

    /// The whole state as text, for tests that compare two simulations field by field.
    #[doc(hidden)]
    pub fn state_debug(&self) -> String {
        format!("{:?}", self.state)
    }
}

fn amount(e: &mut Enc, a: Amount) {
    e.u64(a.count);
    e.f64(a.volume);
}

fn read_amount(d: &mut Dec<'_>) -> Result<Amount, StateError> {
    Ok(Amount { count: d.u64()?, volume: d.f64()? })
}

fn gauge(e: &mut Enc, g: &Gauge) {
    e.u64(g.n);
    e.f64(g.sum);
    e.f64(g.min);
    e.f64(g.max);
    e.u64(g.outside);
}

fn read_gauge(d: &mut Dec<'_>) -> Result<Gauge, StateError> {
    Ok(Gauge { n: d.u64()?, sum: d.f64()?, min: d.f64()?, max: d.f64()?, outside: d.u64()? })
}

fn save(s: &State, e: &mut Enc) {
    e.u64(s.step);
    s.swarm.save_state(e);
    e.usize(s.retired);
    e.f64(s.spawn_carry);
    s.nozzle.save_state(e);
    e.list(s.scene.surfaces(), |e, r| e.f64(r.layer));
    e.list(&s.targets, |e, t| {
        e.str(&t.name);
        e.u64(t.hits);
        for a in [t.stuck, t.loose, t.trapped, t.delivered, t.stuck_back, t.received, t.detached] {
            amount(e, a);
        }
        e.f64(t.received_back);
        e.list(&t.failure_mask, |e, &m| e.u8(m));
        e.bool(t.at_risk);
        e.bool(t.erosion.is_some());
        if let Some(m) = &t.erosion {
            e.list(&m.coating, |e, &x| e.f64(x));
            e.list(&m.substrate, |e, &x| e.f64(x));
        }
        t.surface.save_state(e);
    });
    e.list(&s.obstacles, |e, o| {
        e.u64(o.hits);
        amount(e, o.stuck);
        amount(e, o.received);
    });
    save_totals(s, e);
    s.watches.save_state(e);
}

/// The run's totals, failures, path statistics and impact log.
fn save_totals(s: &State, e: &mut Enc) {
    let t = &s.tally;
    for a in [
        t.emitted,
        t.left_domain,
        t.expired,
        t.substrate_first_impacts,
        t.substrate_first_rebounds,
        t.released,
        t.released_left,
        t.released_expired,
        t.dripped,
        t.ran_off,
    ] {
        amount(e, a);
    }
    e.u64(s.next_id);
    e.u64(s.particle_steps);
    e.u64(s.particle_updates);
    e.list(&s.failures, |e, f| {
        e.f64(f.time);
        e.str(&f.target);
        e.usize(f.cells);
        e.f64(f.area);
        e.f64(f.volume);
    });
    e.u64(s.path.samples);
    for g in [&s.path.standoff, &s.path.angle, &s.path.travel_speed, &s.path.nozzle_speed] {
        gauge(e, g);
    }
    e.bool(s.impact_log.is_some());
    if let Some(log) = &s.impact_log {
        e.list(&log.entries, |e, i| {
            e.f64(i.time);
            e.vec3(i.position);
            e.vec3(i.normal);
            e.vec3(i.velocity);
            e.u32(i.surface.0);
            e.bool(i.stuck);
            e.f32(i.eroded);
            e.u32(i.particle);
            e.u16(i.impact);
        });
    }
}

fn load(s: &mut State, d: &mut Dec<'_>) -> Result<(), StateError> {
    s.step = d.u64()?;
    s.swarm = Swarm::load_state(d)?;
    s.retired = d.usize()?;
    s.spawn_carry = d.f64()?;
    s.nozzle = NozzlePath::load_state(d)?;
    let layers = d.list_of(s.scene.surfaces().len(), "the surfaces", 8, Dec::f64)?;
    let ids: Vec<(SurfaceId, f64)> =
        layers.iter().enumerate().map(|(i, &l)| (SurfaceId(i as u32), l)).collect();
    if layers.iter().zip(s.scene.surfaces()).any(|(&l, r)| l != r.layer) {
        s.scene.set_layer_allowances(&ids);
    }
    let n = s.targets.len();
    if d.len(8)? != n {
        return Err(StateError::Mismatch(format!("expected {n} targets")));
    }
    for t in &mut s.targets {
        load_target(t, d)?;
    }
    if d.len(8)? != s.obstacles.len() {
        return Err(StateError::Mismatch(format!("expected {} obstacles", s.obstacles.len())));
    }
    for o in &mut s.obstacles {
        o.hits = d.u64()?;
        o.stuck = read_amount(d)?;
        o.received = read_amount(d)?;
    }
    load_totals(s, d)?;
    s.watches = super::watch::Watches::load_state(d, s.targets.len())?;
    Ok(())
}

fn load_target(t: &mut crate::world::Target, d: &mut Dec<'_>) -> Result<(), StateError> {
    let name = d.str()?;
    if name != t.name {
        return Err(StateError::Mismatch(format!("target `{name}` where `{}` was expected", t.name)));
    }
    t.hits = d.u64()?;
    let mut amounts = [Amount::default(); 7];
    for a in &mut amounts {
        *a = read_amount(d)?;
    }
    [t.stuck, t.loose, t.trapped, t.delivered, t.stuck_back, t.received, t.detached] = amounts;
    t.received_back = d.f64()?;
    t.failure_mask = d.list_of(t.failure_mask.len(), "a failure map", 1, Dec::u8)?;
    t.at_risk = d.bool()?;
    match (d.bool()?, &mut t.erosion) {
        (false, None) => {}
        (true, Some(m)) => {
            m.coating = d.list_of(m.coating.len(), "a coating map", 8, Dec::f64)?;
            m.substrate = d.list_of(m.substrate.len(), "a wear map", 8, Dec::f64)?;
        }
        _ => return Err(StateError::Mismatch(format!("target `{}`'s erosion", t.name))),
    }
    t.surface.load_state(d)
}

fn load_totals(s: &mut State, d: &mut Dec<'_>) -> Result<(), StateError> {
    let t = &mut s.tally;
    for a in [
        &mut t.emitted,
        &mut t.left_domain,
        &mut t.expired,
        &mut t.substrate_first_impacts,
        &mut t.substrate_first_rebounds,
        &mut t.released,
        &mut t.released_left,
        &mut t.released_expired,
        &mut t.dripped,
        &mut t.ran_off,
    ] {
        *a = read_amount(d)?;
    }
    s.next_id = d.u64()?;
    s.particle_steps = d.u64()?;
    s.particle_updates = d.u64()?;
    s.failures = d.list(40, |d| {
        Ok(FailureEvent {
            time: d.f64()?,
            target: d.str()?,
            cells: d.usize()?,
            area: d.f64()?,
            volume: d.f64()?,
        })
    })?;
    s.path.samples = d.u64()?;
    for g in [&mut s.path.standoff, &mut s.path.angle, &mut s.path.travel_speed, &mut s.path.nozzle_speed] {
        *g = read_gauge(d)?;
    }
    let surfaces = s.scene.surfaces().len() as u32;
    match (d.bool()?, &mut s.impact_log) {
        (false, None) => {}
        (true, Some(log)) => {
            log.entries = d.list(90, |d| {
                Ok(ImpactEvent {
                    time: d.f64()?,
                    position: d.vec3()?,
                    normal: d.vec3()?,
                    velocity: d.vec3()?,
                    surface: match d.u32()? {
                        id if id < surfaces => SurfaceId(id),
                        id => return Err(StateError::Mismatch(format!("an impact on surface {id}"))),
                    },
                    stuck: d.bool()?,
                    eroded: d.f32()?,
                    particle: d.u32()?,
                    impact: d.u16()?,
                })
            })?;
        }
        _ => return Err(StateError::Mismatch("the impact log".into())),
    }
    Ok(())
}
