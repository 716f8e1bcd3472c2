//! A simulation's state to bytes and back (see [`crate::checkpoint`]).

use super::{Simulation, State};
use crate::checkpoint::{Dec, Enc, STATE_VERSION, StateError};
use crate::collision::SurfaceId;
use crate::config::{MAX_COORD, SimulationConfig};
use crate::deposit::DepositSurface;
use crate::emission::NozzlePath;
use crate::events::{FailureEvent, ImpactEvent};
use crate::particles::{MAX_IMPACTS, Swarm};
use crate::tally::{Gauge, Tallied, Tally};
use crate::world::{Target, TargetTally};

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
        check(&state, &self.config, self.plan.total_steps).map_err(StateError::Invalid)?;
        self.state = state;
        Ok(())
    }

    /// The whole state as text, for tests that compare two simulations field by field.
    #[doc(hidden)]
    pub fn state_debug(&self) -> String {
        format!("{:?}", self.state)
    }
}

fn tallied(e: &mut Enc, a: Tallied) {
    e.u64(a.count);
    e.u128(a.quanta);
}

fn read_tallied(d: &mut Dec<'_>) -> Result<Tallied, StateError> {
    Ok(Tallied { count: d.u64()?, quanta: d.u128()? })
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

/// The amounts of a target's tally, in a fixed order (its hits and the volume on its back
/// aside).
fn target_amounts(t: &mut TargetTally) -> [&mut Tallied; 7] {
    [
        &mut t.stuck,
        &mut t.loose,
        &mut t.trapped,
        &mut t.delivered,
        &mut t.stuck_back,
        &mut t.received,
        &mut t.detached,
    ]
}

/// The run's totals, in a fixed order.
fn totals(t: &mut Tally) -> [&mut Tallied; 11] {
    [
        &mut t.emitted,
        &mut t.left_domain,
        &mut t.expired,
        &mut t.overspray,
        &mut t.substrate_first_impacts,
        &mut t.substrate_first_rebounds,
        &mut t.released,
        &mut t.released_left,
        &mut t.released_expired,
        &mut t.dripped,
        &mut t.ran_off,
    ]
}

fn save(s: &State, e: &mut Enc) {
    e.u64(s.step);
    e.u64(s.settled);
    s.swarm.save_state(e);
    e.usize(s.retired);
    e.f64(s.spawn_carry);
    s.nozzle.save_state(e);
    e.list(s.scene.surfaces(), |e, r| e.f64(r.layer));
    e.list(&s.targets, |e, t| save_target(t, e));
    e.list(&s.touched, |e, cells| {
        e.list(cells, |e, &c| e.u32(c));
    });
    e.list(&s.obstacles, |e, o| {
        e.u64(o.tally.hits);
        tallied(e, o.tally.stuck);
        tallied(e, o.tally.received);
    });
    save_totals(s, e);
}

fn save_target(t: &Target, e: &mut Enc) {
    e.str(&t.name);
    let mut tally = t.tally;
    e.u64(tally.hits);
    for a in target_amounts(&mut tally) {
        tallied(e, *a);
    }
    e.u128(tally.received_back);
    e.list(&t.failure_mask, |e, &m| e.u8(m));
    e.bool(t.at_risk);
    e.bool(t.erosion.is_some());
    if let Some(m) = &t.erosion {
        e.list(&m.coating, |e, &x| e.f64(x));
        e.list(&m.substrate, |e, &x| e.f64(x));
    }
    t.surface.save_state(e);
    t.pending.save_state(e);
}

/// The run's totals, failures, path statistics and impact log.
fn save_totals(s: &State, e: &mut Enc) {
    let mut t = s.tally.clone();
    for a in totals(&mut t) {
        tallied(e, *a);
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
    s.settled = d.u64()?;
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
    s.touched = d.list_of(n, "the cells touched", 8, |d| d.list(4, Dec::u32))?;
    if d.len(8)? != s.obstacles.len() {
        return Err(StateError::Mismatch(format!("expected {} obstacles", s.obstacles.len())));
    }
    for o in &mut s.obstacles {
        o.tally.hits = d.u64()?;
        o.tally.stuck = read_tallied(d)?;
        o.tally.received = read_tallied(d)?;
    }
    load_totals(s, d)
}

fn load_target(t: &mut Target, d: &mut Dec<'_>) -> Result<(), StateError> {
    let name = d.str()?;
    if name != t.name {
        return Err(StateError::Mismatch(format!("target `{name}` where `{}` was expected", t.name)));
    }
    let mut tally = TargetTally { hits: d.u64()?, ..TargetTally::default() };
    for a in target_amounts(&mut tally) {
        *a = read_tallied(d)?;
    }
    tally.received_back = d.u128()?;
    t.tally = tally;
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
    t.surface.load_state(d)?;
    t.pending.load_state(d)
}

fn load_totals(s: &mut State, d: &mut Dec<'_>) -> Result<(), StateError> {
    for a in totals(&mut s.tally) {
        *a = read_tallied(d)?;
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

/// Checks a state read from a checkpoint as a scenario is checked before a run, so that a
/// state edited by hand (with a checksum made anew) cannot crash, hang or mislead a resumed
/// run: every number finite, positions inside the domain, speeds below anything a run can
/// reach, thicknesses and volumes not negative, counters within what the run can count.
/// The error says what is wrong, and where.
fn check(s: &State, config: &SimulationConfig, total_steps: u64) -> Result<(), String> {
    if s.step > total_steps {
        return Err(format!("step {} is past the run's end at step {total_steps}", s.step));
    }
    if s.settled > s.step {
        return Err(format!("the last epoch ended at step {}, after the present step {}", s.settled, s.step));
    }
    if !(s.spawn_carry.is_finite() && (0.0..1.0).contains(&s.spawn_carry)) {
        return Err(format!(
            "the emitter's carried fraction of a particle is {}, not in [0, 1)",
            s.spawn_carry
        ));
    }
    // Particle ids are 32-bit (the configuration bounds a run's particles by 4·10⁹).
    if s.next_id > u64::from(u32::MAX) || s.tally.emitted.count > s.next_id {
        return Err(format!(
            "the next particle id {} is beyond 32 bits or below the count emitted",
            s.next_id
        ));
    }
    check_swarm(s, config)?;
    s.nozzle.check(MAX_COORD).map_err(|m| format!("the nozzle's path {m}"))?;
    for (k, r) in s.scene.surfaces().iter().enumerate() {
        if !(r.layer.is_finite() && r.layer >= 0.0) {
            return Err(format!("surface {k}'s layer allowance is {} m", r.layer));
        }
    }
    for (t, touched) in s.targets.iter().zip(&s.touched) {
        check_target(t, touched)?;
    }
    check_totals(s)
}

/// A target of a checked state, with the cells the epoch under way has touched: see [`check`].
fn check_target(t: &Target, touched: &[u32]) -> Result<(), String> {
    let th = t.surface.thickness();
    if let Some((c, x)) = th.iter().enumerate().find(|(_, x)| !(x.is_finite() && **x >= 0.0)) {
        return Err(format!("target `{}` has thickness {x} m in cell {c}", t.name));
    }
    let max = th.iter().copied().fold(0.0, f64::max);
    if !(t.surface.max_thickness().is_finite() && t.surface.max_thickness() >= max) {
        return Err(format!("target `{}`'s thickness bound is below its thickest cell", t.name));
    }
    if let Some(&c) = touched.iter().find(|&&c| c as usize >= th.len()) {
        return Err(format!("target `{}` lists cell {c} as touched, of {} cells", t.name, th.len()));
    }
    if let Some(e) = &t.erosion {
        let worn = |x: &f64| x.is_finite() && *x >= 0.0;
        let coat = |x: &f64| worn(x) && *x <= e.initial_coating;
        if !(e.substrate.iter().all(worn) && e.coating.iter().all(coat)) {
            return Err(format!(
                "target `{}`'s wear or coating maps hold a negative, non-finite or too thick value",
                t.name
            ));
        }
    }
    Ok(())
}

/// The failures and impact log of a checked state: see [`check`].
fn check_totals(s: &State) -> Result<(), String> {
    let finite_failure = |f: &FailureEvent| {
        f.time.is_finite() && f.area.is_finite() && f.volume.is_finite() && f.volume >= 0.0
    };
    if !s.failures.iter().all(finite_failure) {
        return Err("a cohesive failure has a non-finite time, area or volume".into());
    }
    if let Some(log) = &s.impact_log
        && log
            .entries
            .iter()
            .any(|i| !(i.time.is_finite() && i.position.is_finite() && i.velocity.is_finite()))
    {
        return Err("an entry of the impact log is not finite".into());
    }
    Ok(())
}

/// The particles of a checked state: see [`check`].
fn check_swarm(s: &State, config: &SimulationConfig) -> Result<(), String> {
    let sw = &s.swarm;
    if s.retired > sw.len() {
        return Err(format!("{} particles retired of {} slots", s.retired, sw.len()));
    }
    // Faster than any particle can fly: twice the fastest emission plus a fall through the
    // whole domain, with the nozzle's own speed allowed for.
    let height = config.domain.max.z - config.domain.min.z;
    let fastest =
        2.0 * (config.emitter.speed[1] + (2.0 * config.motion.gravity.length() * height).sqrt()) + 100.0;
    let lifetime = (config.material.max_lifetime / config.dt).ceil() + 1.0;
    for p in &sw.particles {
        let (x, v) = (p.anchor, p.anchor_velocity());
        if !(x.is_finite() && v.is_finite()) {
            return Err(format!("particle {} has a non-finite position or velocity", p.id));
        }
        if u64::from(p.id) >= s.next_id {
            return Err(format!("particle {} has an id not yet given out", p.id));
        }
        if !p.is_alive() {
            continue;
        }
        let (now, _) = p.now(config.dt, config.motion.gravity);
        if !(config.domain.contains(x) && config.domain.contains(now)) {
            return Err(format!("particle {} is at {now} m, outside the domain", p.id));
        }
        if v.length() > fastest {
            return Err(format!(
                "particle {} flies at {:.4e} m/s, faster than this run can reach",
                p.id,
                v.length()
            ));
        }
        let age = s.step as f64 - f64::from(p.born);
        if !(0.0..=lifetime).contains(&age) || f64::from(p.since) > age.max(0.0) {
            return Err(format!(
                "particle {} was born at step {} and anchored {} steps ago, which the present step {} and the \
                 lifetime of {} s cannot hold",
                p.id, p.born, p.since, s.step, config.material.max_lifetime
            ));
        }
        if p.impacts() > MAX_IMPACTS {
            return Err(format!("particle {} has {} impacts", p.id, p.impacts()));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// A run of the example wall part-way, with particles in flight and a layer.
    fn running() -> Simulation {
        let mut sim = Simulation::new(SimulationConfig::example_wall(0.2)).expect("valid");
        for _ in 0..80 {
            sim.step();
        }
        assert!(sim.swarm().alive() > 0 && sim.targets()[0].tally.stuck.count > 0);
        sim
    }

    /// Restores the state of `edited` into a fresh simulation of the same configuration:
    /// the error, and whether the fresh one stayed at its start.
    fn restore(edited: &Simulation) -> StateError {
        let mut fresh = Simulation::new(edited.config().clone()).expect("valid");
        let err = fresh.restore_state(&edited.save_state()).expect_err("an impossible state is refused");
        assert_eq!(fresh.steps_done(), 0, "a refused state changes nothing");
        err
    }

    /// The slot of a particle in flight.
    fn alive(sim: &Simulation) -> usize {
        sim.state.swarm.particles.iter().position(|p| p.is_alive()).expect("alive")
    }

    fn invalid(err: StateError, words: &str) {
        match err {
            StateError::Invalid(m) => assert!(m.contains(words), "{m}"),
            other => panic!("refused for another reason: {other}"),
        }
    }

    #[test]
    fn a_state_saved_by_a_run_is_restored() {
        let sim = running();
        let mut fresh = Simulation::new(sim.config().clone()).expect("valid");
        fresh.restore_state(&sim.save_state()).expect("restored");
        assert_eq!(fresh.state_debug(), sim.state_debug());
    }

    #[test]
    fn a_particle_with_a_nan_position_or_velocity_is_refused() {
        let mut sim = running();
        let i = alive(&sim);
        sim.state.swarm.particles[i].anchor.y = f64::NAN;
        invalid(restore(&sim), "non-finite");
        let mut sim = running();
        sim.state.swarm.particles[i].velocity.x = f32::INFINITY;
        invalid(restore(&sim), "non-finite");
    }

    #[test]
    fn a_particle_outside_the_domain_or_impossibly_fast_is_refused() {
        let mut sim = running();
        let i = alive(&sim);
        sim.state.swarm.particles[i].anchor.x = 1e6;
        invalid(restore(&sim), "outside the domain");
        let mut sim = running();
        sim.state.swarm.particles[i].velocity = glam::Vec3::new(0.0, 3e5, 0.0);
        invalid(restore(&sim), "faster than this run can reach");
    }

    #[test]
    fn an_absurd_carried_fraction_or_counter_is_refused() {
        let mut sim = running();
        sim.state.spawn_carry = 1e12;
        invalid(restore(&sim), "carried fraction");
        let mut sim = running();
        sim.state.next_id = u64::MAX;
        invalid(restore(&sim), "beyond 32 bits");
        let mut sim = running();
        sim.state.step = sim.plan.total_steps + 1;
        invalid(restore(&sim), "past the run's end");
        let mut sim = running();
        sim.state.retired = sim.state.swarm.len() + 1;
        invalid(restore(&sim), "retired");
    }

    #[test]
    fn a_negative_thickness_or_a_touched_cell_beyond_the_surface_is_refused() {
        let sim = running();
        // The state as bytes, with one cell's thickness made negative: found by its value,
        // which only that list holds.
        let th = sim.targets()[0].surface.thickness();
        let (cell, &value) = th
            .iter()
            .enumerate()
            .filter(|(_, x)| **x > 0.0)
            .max_by(|a, b| a.1.total_cmp(b.1))
            .expect("a layer");
        let mut bytes = sim.save_state();
        let pattern = value.to_le_bytes();
        let at = bytes.windows(8).position(|w| w == pattern).expect("the thickest cell's value");
        bytes[at..at + 8].copy_from_slice(&(-value).to_le_bytes());
        let mut fresh = Simulation::new(sim.config().clone()).expect("valid");
        invalid(fresh.restore_state(&bytes).expect_err("refused"), &format!("in cell {cell}"));
        let mut sim = running();
        sim.state.touched[0].push(u32::MAX);
        invalid(restore(&sim), "as touched");
    }

    #[test]
    fn a_nozzle_path_with_a_nan_or_zero_axis_is_refused_and_kept_out_of_a_running_simulation() {
        use crate::emission::{NozzlePath, Waypoint};
        let mut sim = running();
        let bad = NozzlePath::through(
            vec![Waypoint {
                time: 0.0,
                position: DVec3::new(f64::NAN, 0.0, 1.0),
                axis: DVec3::X,
                spray: true,
            }],
            0.0,
        );
        let before = sim.nozzle().clone();
        assert!(sim.set_nozzle_path(bad.clone()).is_err());
        assert_eq!(sim.nozzle(), &before, "a refused path changes nothing");
        let zero = NozzlePath::fixed(DVec3::new(-1.0, 0.0, 1.0), DVec3::ZERO, 0.0);
        assert!(sim.set_nozzle_path(zero.clone()).is_err());
        sim.state.nozzle = bad;
        invalid(restore(&sim), "nozzle");
    }
}
