//! Deposit resolution by default: a target without `splat_radius` spreads each particle over
//! the smallest footprint that expects about ten particles, so the painting preset on the
//! default 1024 × 1024 grid lays a film, not a field of single-particle spikes; an explicit
//! radius is kept, and an explicit 0 keeps single-cell deposits. Volume is conserved either way.

use spraysim::deposit::{DepositSurface, footprint_cells};
use spraysim::scenario::PARTICLES_PER_SPLAT;
use spraysim::{Scenario, Simulation};

/// Standoff of the painting gun, m: inside the preset's 0.15–0.3 m window.
const STANDOFF: f64 = 0.25;
/// Side of the square panel, m; the default grid puts 1024 × 1024 cells on it.
const SIDE: f64 = 1.0;
/// Spraying time, s: 10⁴ particles at the preset's 5 × 10⁴ /s.
const DURATION: f64 = 0.2;

/// The painting preset square onto a 1 m panel from 0.25 m for 0.2 s, at the default grid,
/// with `splat` (a `splat_radius = …` line, or nothing) added to the panel.
fn painting(splat: &str) -> Scenario {
    let text = format!(
        "[simulation]\nduration = {DURATION:?}\n[process]\npreset = \"painting\"\n\
         [nozzle]\nposition = [{:?}, 0.0, 1.0]\naxis = [1.0, 0.0, 0.0]\n\
         [[target]]\nname = \"panel\"\ncenter = [0.0, 0.0, 1.0]\nnormal = [-1.0, 0.0, 0.0]\n\
         up = [0.0, 0.0, 1.0]\nsize = [{SIDE:?}, {SIDE:?}]\n{splat}\n",
        -STANDOFF
    );
    Scenario::from_toml(&text, "painting").unwrap_or_else(|e| panic!("{e}"))
}

fn run(sc: &Scenario) -> Simulation {
    let mut sim = sc.build().unwrap_or_else(|e| panic!("{e}"));
    sim.run(|_| {});
    sim
}

/// The panel's cell side, m.
const CELL: f64 = SIDE / 1024.0;

/// Radius of the spray cone's spot on the panel, m: 0.25 m × tan 20°.
fn spot_radius() -> f64 {
    STANDOFF * 20f64.to_radians().tan()
}

/// Over the cells whose centres lie `from`–`to` spot radii from the spot's centre, in radial
/// bins 2 cells wide: the share of cells with any deposit, and the coefficient of variation of
/// the thickness about each bin's mean (the film's roughness, without its radial profile),
/// each bin weighted by its cells; also the least mean thickness of a bin, m.
fn film_in_ring(thickness: &[f64], from: f64, to: f64) -> (f64, f64, f64) {
    let r0 = spot_radius();
    let bins = ((to - from) * r0 / (2.0 * CELL)).ceil() as usize;
    let mut cells: Vec<Vec<f64>> = vec![Vec::new(); bins];
    for (k, &t) in thickness.iter().enumerate() {
        let (x, y) = (((k % 1024) as f64 + 0.5) * CELL - 0.5, ((k / 1024) as f64 + 0.5) * CELL - 0.5);
        let r = x.hypot(y) / r0;
        if (from..to).contains(&r) {
            let bin = (((r - from) * r0) / (2.0 * CELL)) as usize;
            cells[bin.min(bins - 1)].push(t);
        }
    }
    let (mut n, mut nonzero, mut squared, mut least) = (0.0, 0.0, 0.0, f64::INFINITY);
    for bin in cells.iter().filter(|b| !b.is_empty()) {
        let count = bin.len() as f64;
        let mean = bin.iter().sum::<f64>() / count;
        let var = bin.iter().map(|t| (t - mean).powi(2)).sum::<f64>() / count;
        n += count;
        nonzero += bin.iter().filter(|&&t| t > 0.0).count() as f64;
        squared += count * var / (mean * mean);
        least = least.min(mean);
    }
    (nonzero / n, (squared / n).sqrt(), least)
}

#[test]
fn painting_on_the_default_grid_derives_a_splat_that_expects_ten_particles() {
    let sc = painting("");
    let splat = sc.targets()[0].shape.splat_radius().expect("a heightfield");
    assert!(splat.derived);
    // 10⁴ particles over the spot, π (0.25 tan 20°)²: about 0.37 per 0.98 mm cell.
    let per_cell =
        sc.emitter().spawn_rate * DURATION * CELL * CELL / (std::f64::consts::PI * spot_radius().powi(2));
    let cells = (splat.radius / CELL).round();
    assert!((splat.radius / CELL - cells).abs() < 1e-9, "a whole number of cells: {}", splat.radius);
    let within = |r: f64| footprint_cells((CELL, CELL), r) as f64 * per_cell;
    assert!(within(splat.radius) >= PARTICLES_PER_SPLAT, "{} particles", within(splat.radius));
    assert!(within(splat.radius - CELL) < PARTICLES_PER_SPLAT, "not the smallest: {}", splat.radius);
    assert_eq!(cells, 3.0);
    // The run and its outputs report it.
    let sim = run(&sc);
    assert_eq!(sim.metrics().targets[0].splat_radius, Some(splat.radius));
}

#[test]
fn painting_on_the_default_grid_lays_a_smooth_film_and_keeps_every_particle() {
    let sc = painting("");
    let radius = sc.targets()[0].shape.splat_radius().map_or(0.0, |s| s.radius);
    let sim = run(&sc);
    let m = sim.metrics();
    let panel = &sim.targets()[0].surface;
    // Where the spot expects at least ten particles per footprint (0.2–0.5 of its radius, for
    // the preset's direction law), every cell holds film, and the film's roughness is the
    // Poisson scatter of the ten or more particles a footprint shares: 1/√10 ≈ 0.32, with
    // 30 % for the spread of the count across a bin.
    let (nonzero, cv, least) = film_in_ring(panel.thickness(), 0.2, 0.5);
    let particle = m.emitted.volume / m.emitted.count as f64;
    let footprint = footprint_cells((CELL, CELL), radius) as f64;
    let expected = least * footprint * CELL * CELL / particle;
    assert!(expected >= PARTICLES_PER_SPLAT, "{expected} particles per footprint at least");
    assert!(nonzero > 0.999, "share of cells with film {nonzero}");
    assert!(cv < 1.3 / PARTICLES_PER_SPLAT.sqrt(), "roughness {cv}");
    // Σ thickness × cell area is every stuck particle's volume, and the balance closes.
    let stuck = m.targets[0].stuck.volume;
    assert!((panel.volume() - stuck).abs() <= 1e-9 * stuck, "{} vs {stuck} m³", panel.volume());
    let b = &m.volume_balance;
    assert!(b.residual.abs() <= 1e-9 * b.emitted, "{b:?}");
}

#[test]
fn an_explicit_zero_keeps_single_cell_deposits_and_their_spikes() {
    let sc = painting("splat_radius = 0");
    let splat = sc.targets()[0].shape.splat_radius().expect("a heightfield");
    assert!(!splat.derived);
    assert_eq!(splat.radius, 0.0);
    let sim = run(&sc);
    let m = sim.metrics();
    let panel = &sim.targets()[0].surface;
    // One particle in a cell is 1e-10 m³ over 0.95 mm²: 104.9 µm, in a 20–50 µm film.
    let particle = m.emitted.volume / m.emitted.count as f64;
    let spike = particle / (CELL * CELL);
    assert!((spike - 104.9e-6).abs() < 0.1e-6, "{spike}");
    let (nonzero, cv, _) = film_in_ring(panel.thickness(), 0.2, 0.5);
    assert!(nonzero < 0.9, "share of cells with film {nonzero}");
    assert!(cv > 1.0, "roughness {cv}");
    // Every stuck cell holds whole particles.
    let whole = panel.thickness().iter().all(|&t| (t / spike - (t / spike).round()).abs() < 1e-6);
    assert!(whole);
    assert!((panel.volume() - m.targets[0].stuck.volume).abs() <= 1e-9 * m.targets[0].stuck.volume);
}

#[test]
fn an_explicit_radius_is_kept() {
    let sc = painting("splat_radius = 0.005");
    let splat = sc.targets()[0].shape.splat_radius().expect("a heightfield");
    assert!(!splat.derived);
    assert_eq!(splat.radius, 0.005);
    assert_eq!(run(&sc).metrics().targets[0].splat_radius, Some(0.005));
    // Written back with its derived radius, a scenario reads back the same.
    let derived = painting("");
    let again = Scenario::from_toml(&derived.to_toml(), "written back").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(again, derived);
    assert_eq!(again.targets()[0].shape.splat_radius().map(|s| s.radius), Some(3.0 * CELL));
}

#[test]
fn a_pass_spreads_its_particles_over_the_band_it_sweeps() {
    // A 0.6 m pass along the panel in 1 s: the spot sweeps a band 2 R wide with round ends.
    let text = format!(
        "[simulation]\nduration = 1.0\n[process]\npreset = \"painting\"\n\
         [[nozzle.waypoints]]\ntime = 0.0\nposition = [{x:?}, -0.3, 1.0]\naxis = [1.0, 0.0, 0.0]\n\
         [[nozzle.waypoints]]\ntime = 1.0\nposition = [{x:?}, 0.3, 1.0]\naxis = [1.0, 0.0, 0.0]\n\
         [[target]]\nname = \"panel\"\ncenter = [0.0, 0.0, 1.0]\nnormal = [-1.0, 0.0, 0.0]\n\
         up = [0.0, 0.0, 1.0]\nsize = [{SIDE:?}, {SIDE:?}]\n",
        x = -STANDOFF
    );
    let sc = Scenario::from_toml(&text, "a pass").unwrap_or_else(|e| panic!("{e}"));
    let splat = sc.targets()[0].shape.splat_radius().expect("a heightfield");
    let r = spot_radius();
    let band = 0.6 * 2.0 * r + std::f64::consts::PI * r * r;
    let per_cell = sc.emitter().spawn_rate * 1.0 * CELL * CELL / band;
    let expected = footprint_cells((CELL, CELL), splat.radius) as f64 * per_cell;
    let derived = splat.expected_particles.expect("derived");
    assert!((derived / expected - 1.0).abs() < 0.02, "{derived} particles per splat, {expected} by hand");
    assert!(derived >= PARTICLES_PER_SPLAT);
    // Spread over a band about 5 times the spot, each cell expects less than from the
    // nozzle standing still for the same time: the splat is wider.
    let still = painting("").with("simulation.duration", 1.0).unwrap_or_else(|e| panic!("{e}"));
    let still_radius = still.targets()[0].shape.splat_radius().map_or(0.0, |s| s.radius);
    assert!(splat.radius > still_radius, "{} m against {still_radius} m", splat.radius);
}
