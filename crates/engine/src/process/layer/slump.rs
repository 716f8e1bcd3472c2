//! Slump: a fresh yield-stress layer (wet shotcrete) flows where its own weight shears it past
//! its yield stress, and stops where it no longer does.
//!
//! In the shallow-layer theory of a Bingham layer the layer is static where the shear stress at
//! its base, ρ g h |∇e|, stays within the yield stress τ_y; `e` is the elevation of the layer's
//! free surface (Liu & Mei 1989; Balmforth, Craster & Sassi 2002; Coussot 2005). Its special
//! cases: on a floor, Nye's (1951) plastic heap, h dh/dx = τ_y/(ρ g); on a wall, the thickness
//! limit τ_y/(ρ g); on a slope at φ from horizontal, τ_y/(ρ g sin φ). On an overhang the
//! thickness does not raise `e`: the layer hangs from the surface and fails by pull-off, which
//! the cohesion stage judges (with the thickness counted, a hanging layer would flow towards its
//! thick spots and grow needles).
//!
//! The relaxation is a cellular automaton of Gauss–Seidel sweeps over the cells near a change,
//! highest first. Each cell asks every lower neighbour whose edge is unstable for the transfer
//! that alone would bring that edge just under the limit, and sends its largest request at
//! once, shared in proportion to the requests: no edge gets more than it asked for, so none
//! overshoots, and what a cell sends is passed further down in the same sweep. The order (by
//! elevation, then by cell) makes the result deterministic; every transfer is taken from one
//! cell and added to another, so volume is conserved up to rounding. Material sent past the
//! surface's edge runs off and falls.

use super::{LayerContext, LayerStage, RELEASE_OFFSET, Release};
use crate::deposit::DepositSurface;
use glam::DVec3;

/// Relative excess of the basal stress over the yield stress that is tolerated, and the margin
/// under it a transfer aims for: without it the last sweeps would chase ever smaller excesses.
const TOLERANCE: f64 = 1e-2;

/// Slump of the fresh layer: every interval, each target's layer is relaxed until no edge
/// between neighbouring cells carries more than the yield stress (or `max_sweeps` is reached:
/// the rest of the flow continues at the next run, like a slow slump). What flows over a
/// surface's edge leaves as one released particle per edge cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlumpStage {
    /// Yield stress of the fresh layer, Pa.
    pub yield_stress: f64,
    /// Most Jacobi sweeps per run.
    pub max_sweeps: u32,
}

/// Material that flowed over a surface's edge from one cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunOff {
    /// The edge cell it left from.
    pub cell: u32,
    /// Volume, m³.
    pub volume: f64,
    /// Where it crossed the edge, m: on the bare surface, the volume-weighted mean of the
    /// midpoints between the cell's centre and those of the missing neighbours it flowed to.
    pub edge: DVec3,
    /// Unit direction along the surface in which it left.
    pub direction: DVec3,
}

/// What one relaxation did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Relaxation {
    /// Sweeps that moved material.
    pub sweeps: u32,
    /// True if the layer is stable everywhere it was examined.
    pub settled: bool,
    /// Material that left over the edges, in cell order.
    pub run_off: Vec<RunOff>,
}

/// One request of a cell: where to (`None`: over the edge), the unit direction and the centre
/// of the receiving cell (m), and the thickness to send, m.
type Request = (Option<u32>, DVec3, DVec3, f64);

/// Relaxes the layer of `surface` around the cells changed since the last call, for at most
/// `max_sweeps` sweeps, under `gravity` (m/s²) for a material of `density` (kg/m³) and
/// `yield_stress` (Pa). Run-off is taken off the layer and returned.
pub fn relax<S: DepositSurface + ?Sized>(
    surface: &mut S,
    density: f64,
    gravity: DVec3,
    yield_stress: f64,
    max_sweeps: u32,
) -> Relaxation {
    let g = gravity.length();
    let mut out = Relaxation { settled: true, ..Relaxation::default() };
    let changed = surface.take_changed();
    if g == 0.0 || changed.is_empty() {
        return out;
    }
    let up = -gravity / g;
    // The yield stress as a length: ρ g h Δe/ℓ ≤ τ_y ⇔ h Δe ≤ reach ℓ.
    let reach = yield_stress / (density * g);
    let mut seen = Seen { mark: vec![0; surface.thickness().len()], stamp: 0 };
    let mut active = around(surface, &changed, &mut seen);
    let (mut order, mut requests, mut touched) = (Vec::new(), Vec::new(), Vec::new());
    let mut run_off: Vec<RunOff> = Vec::new();
    out.settled = false;
    for _ in 0..max_sweeps {
        // Highest first, so that what a cell sends on is passed further down in the same sweep.
        let t = surface.thickness();
        let elevation = |c: u32| {
            let lift = surface.normal(c).dot(up).max(0.0);
            surface.point_above(c, 0.0).dot(up) + lift * t[c as usize]
        };
        order.clear();
        order.extend(active.iter().filter(|&&c| may_flow(surface, c, up, reach)).map(|&c| (elevation(c), c)));
        order.sort_unstable_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        touched.clear();
        for &(_, i) in &order {
            requests.clear();
            unstable_edges(surface, i, up, reach, &mut requests);
            if requests.is_empty() {
                continue;
            }
            let most = requests.iter().fold(0.0_f64, |m, r| m.max(r.3));
            let sum: f64 = requests.iter().map(|r| r.3).sum();
            let area = surface.cell_area(i);
            touched.push(i);
            for &(to, dir, centre, u) in &requests {
                let volume = most * u / sum * area;
                surface.add_thickness(i, -volume / area);
                match to {
                    Some(k) => {
                        surface.add_thickness(k, volume / surface.cell_area(k));
                        touched.push(k);
                    }
                    None => add_run_off(&mut run_off, surface, i, dir, centre, volume),
                }
            }
        }
        if touched.is_empty() {
            out.settled = true;
            break;
        }
        out.sweeps += 1;
        active = around(surface, &touched, &mut seen);
    }
    if out.settled {
        // Its own moves left the layer stable: nothing to look at next time.
        surface.take_changed();
    }
    for r in &mut run_off {
        r.edge /= r.volume;
        r.direction = r.direction.normalize_or_zero();
    }
    run_off.sort_by_key(|r| r.cell);
    out.run_off = run_off;
    out
}

/// The requests of cell `i`: one per neighbour (or missing neighbour past the edge) whose edge
/// with `i` is unstable, with the thickness that alone would bring that edge to the limit.
fn unstable_edges<S: DepositSurface + ?Sized>(
    surface: &S,
    i: u32,
    up: DVec3,
    reach: f64,
    requests: &mut Vec<Request>,
) {
    let t = surface.thickness();
    let h = t[i as usize];
    if h <= 0.0 {
        return;
    }
    let lift = |cell: u32| surface.normal(cell).dot(up).max(0.0);
    let lift_i = lift(i);
    let area_i = surface.cell_area(i);
    let own = surface.point_above(i, 0.0);
    let e_i = own.dot(up) + lift_i * h;
    surface.stencil(i, &mut |k, centre| {
        let (e_k, c) = match k {
            Some(k) => {
                let lift_k = lift(k);
                let grow = lift_k * area_i / surface.cell_area(k);
                (centre.dot(up) + lift_k * t[k as usize], lift_i + grow)
            }
            None => (centre.dot(up), lift_i),
        };
        let (de, l) = (e_i - e_k, centre.distance(own));
        let limit = reach * l;
        if de <= 0.0 || h * de <= limit * (1.0 + TOLERANCE) {
            return;
        }
        // The smallest u with (h − u)(Δe − c u) = target: the donor falls by c_i u and the
        // receiver rises, so the head shrinks by c u. The target lies as far under the limit as
        // the trigger lies over it, so that an edge once relaxed stays quiet while its
        // neighbours settle. In the stable form of the root (c ≥ 0), which is h − target/Δe when
        // c = 0 (a wall), and always lies in (0, h).
        let target = limit * (1.0 - TOLERANCE);
        let disc = (c * h - de).powi(2) + 4.0 * c * target;
        let u = 2.0 * (h * de - target) / (c * h + de + disc.sqrt());
        requests.push((k, (centre - own) / l, centre, u));
    });
}

/// Counts `volume` (m³) sent from `cell` towards the missing neighbour centred at `centre`.
fn add_run_off<S: DepositSurface + ?Sized>(
    run_off: &mut Vec<RunOff>,
    surface: &S,
    cell: u32,
    dir: DVec3,
    centre: DVec3,
    volume: f64,
) {
    let edge = 0.5 * (surface.point_above(cell, 0.0) + centre);
    match run_off.iter_mut().find(|r| r.cell == cell) {
        Some(r) => {
            r.volume += volume;
            r.edge += edge * volume;
            r.direction += dir * volume;
        }
        None => run_off.push(RunOff { cell, volume, edge: edge * volume, direction: dir * volume }),
    }
}

/// False if `cell` is stable by a bound that needs no neighbour (most cells): the head to any
/// neighbour is at most the surface's drop over the distance (ℓ sin β, β its tilt) plus the
/// cell's own lift.
fn may_flow<S: DepositSurface + ?Sized>(surface: &S, cell: u32, up: DVec3, reach: f64) -> bool {
    let h = surface.thickness()[cell as usize];
    let up_n = surface.normal(cell).dot(up);
    let tilt = (1.0 - up_n * up_n).max(0.0).sqrt();
    h * (tilt + up_n.max(0.0) * h / surface.spacing(cell)) > reach * (1.0 + TOLERANCE)
}

/// `cells` and every cell in their stencils, once each (in no particular order: the sweeps
/// order them); `seen` marks them, one entry per cell of the surface.
fn around<S: DepositSurface + ?Sized>(surface: &S, cells: &[u32], seen: &mut Seen) -> Vec<u32> {
    let stamp = seen.next();
    let mut out = Vec::with_capacity(cells.len() * 9);
    let mut add = |c: u32| {
        if seen.mark[c as usize] != stamp {
            seen.mark[c as usize] = stamp;
            out.push(c);
        }
    };
    for &c in cells {
        add(c);
        surface.stencil(c, &mut |k, _| k.into_iter().for_each(&mut add));
    }
    out
}

/// Marks of [`around`], by stamp: a stamp per call, so that the marks need no clearing.
struct Seen {
    mark: Vec<u32>,
    stamp: u32,
}

impl Seen {
    fn next(&mut self) -> u32 {
        self.stamp += 1;
        self.stamp
    }
}

impl LayerStage for SlumpStage {
    fn name(&self) -> &'static str {
        "slump"
    }

    fn run(&self, ctx: &mut LayerContext<'_>) {
        for t in ctx.targets.iter_mut() {
            let r = relax(&mut t.surface, ctx.density, ctx.gravity, self.yield_stress, self.max_sweeps);
            for o in &r.run_off {
                // It leaves at mid-depth, just inside the edge, moving outwards at the speed of
                // a gravity current as deep as the layer there, so that it clears the edge.
                let h = t.surface.thickness()[o.cell as usize];
                let n = t.surface.normal(o.cell);
                let pos = o.edge - o.direction * RELEASE_OFFSET + n * (0.5 * h + RELEASE_OFFSET);
                let speed = (ctx.gravity.length() * h).sqrt();
                ctx.release.emit(t, pos, o.direction * speed, o.volume, Release::RunOff);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::Face;
    use crate::deposit::RectangleSurface;

    const RHO: f64 = 2300.0;
    const TAU: f64 = 2500.0;
    const G: DVec3 = DVec3::new(0.0, 0.0, -9.81);

    /// A `size` m square surface of 4 mm cells facing `normal`.
    fn square(size: f64, normal: DVec3, up: DVec3) -> RectangleSurface {
        let n = (size / 0.004).round() as usize;
        RectangleSurface::new(Face::new(DVec3::ZERO, normal, up, [size, size]), n, n, 0.0)
    }

    /// Relaxes until settled, at most `sweeps` sweeps; returns the run-off volume, m³.
    fn settle(s: &mut RectangleSurface, sweeps: u32) -> f64 {
        let r = relax(s, RHO, G, TAU, sweeps);
        assert!(r.settled, "not settled after {sweeps} sweeps");
        r.run_off.iter().map(|o| o.volume).sum()
    }

    /// The largest basal stress over yield stress on any edge between two cells.
    fn worst_stress_ratio(s: &RectangleSurface) -> f64 {
        let up = DVec3::Z;
        let t = s.thickness();
        let lift = s.face.normal.z.max(0.0);
        let mut worst = 0.0_f64;
        for i in 0..t.len() as u32 {
            let own = s.point_above(i, 0.0);
            s.stencil(i, &mut |k, centre| {
                if let Some(k) = k {
                    let de = own.dot(up) + lift * t[i as usize] - centre.dot(up) - lift * t[k as usize];
                    worst = worst.max(RHO * 9.81 * t[i as usize] * de / centre.distance(own) / TAU);
                }
            });
        }
        worst
    }

    #[test]
    fn a_column_on_a_floor_spreads_into_nyes_plastic_heap() {
        let mut floor = square(0.4, DVec3::Z, DVec3::Y);
        // Half a litre in a column of 20 mm radius, about 0.4 m tall.
        let mut column = Vec::new();
        for c in 0..floor.thickness().len() as u32 {
            if floor.point_above(c, 0.0).length() <= 0.02 {
                column.push(c);
            }
        }
        let volume = 5e-4;
        let h0 = volume / floor.area_of(&column);
        column.iter().for_each(|&c| floor.add_thickness(c, h0));
        assert_eq!(settle(&mut floor, 20_000), 0.0, "nothing reaches the edges");
        assert!((floor.volume() - volume).abs() < 1e-12 * volume, "volume {}", floor.volume());
        assert!(worst_stress_ratio(&floor) <= 1.0 + TOLERANCE);
        // Nye's axisymmetric heap h(r) = √(2a(R − r)), a = τ_y/(ρ g), holds
        // V = (8π/15) √(2a) R^{5/2}: R = 52.6 mm and a peak of 107.9 mm. On 4 mm cells the
        // lattice flattens the tip by a few per cent (5 % here, half that on 2 mm cells).
        let a = TAU / (RHO * 9.81);
        let radius = (15.0 * volume / (8.0 * std::f64::consts::PI * (2.0 * a).sqrt())).powf(0.4);
        let peak = (2.0 * a * radius).sqrt();
        let top = floor.thickness().iter().fold(0.0_f64, |m, &t| m.max(t));
        assert!((top / peak - 1.0).abs() < 0.05, "peak {top} m against Nye's {peak} m");
        // Annulus by annulus, within 5 % of the peak of Nye's profile (the rim's lattice step
        // aside), and nothing beyond two cells past its edge.
        let mut bins = [(0.0, 0.0, 0.0); 12];
        for c in 0..floor.thickness().len() as u32 {
            let r = floor.point_above(c, 0.0).length();
            let k = (r / 0.005) as usize;
            if k < bins.len() {
                bins[k].0 += floor.thickness()[c as usize];
                bins[k].1 += (2.0 * a * (radius - r).max(0.0)).sqrt();
                bins[k].2 += 1.0;
            }
            let beyond = r > radius + 0.01;
            assert!(!beyond || floor.thickness()[c as usize] == 0.0, "material {r} m out");
        }
        for (k, (sim, nye, n)) in bins.iter().enumerate().take(10) {
            let (sim, nye) = (sim / n, nye / n);
            assert!((sim - nye).abs() < 0.05 * peak, "annulus {k}: {sim} m against Nye's {nye} m");
        }
    }

    #[test]
    fn a_thick_layer_on_a_wall_slides_down_to_the_yield_thickness_and_runs_off_the_bottom() {
        let mut wall = square(0.2, DVec3::X, DVec3::Z);
        let cells = wall.thickness().len() as u32;
        (0..cells).for_each(|c| wall.add_thickness(c, 0.2));
        let before = wall.volume();
        let ran_off = settle(&mut wall, 20_000);
        assert!((wall.volume() + ran_off - before).abs() < 1e-12 * before);
        // τ_y/(ρ g) = 110.8 mm everywhere, to the tolerance of the yield criterion.
        let a = TAU / (RHO * 9.81);
        for (c, &t) in wall.thickness().iter().enumerate() {
            let (lo, hi) = (a * (1.0 - TOLERANCE) * (1.0 - 1e-9), a * (1.0 + TOLERANCE));
            assert!((lo..=hi).contains(&t), "cell {c}: {t} m");
        }
        assert!((ran_off - (0.2 - a) * 0.04).abs() < 0.02 * ran_off, "ran off {ran_off} m³");
    }

    #[test]
    fn a_layer_under_the_yield_thickness_stays_put_on_a_wall_and_overhead() {
        for (normal, up) in [(DVec3::X, DVec3::Z), (DVec3::NEG_Z, DVec3::Y)] {
            let mut s = square(0.2, normal, up);
            // A 100 mm lump in the middle, 50 mm around it.
            for c in 0..s.thickness().len() as u32 {
                let r = s.point_above(c, 0.0).length();
                s.add_thickness(c, if r < 0.03 { 0.1 } else { 0.05 });
            }
            let before = s.thickness().to_vec();
            let r = relax(&mut s, RHO, G, TAU, 100);
            assert!(r.settled && r.sweeps == 0 && r.run_off.is_empty(), "{normal}: {r:?}");
            assert_eq!(s.thickness(), before.as_slice());
        }
    }

    #[test]
    fn a_layer_over_the_yield_thickness_overhead_does_not_flow_to_its_thick_spots() {
        let mut ceiling = square(0.2, DVec3::NEG_Z, DVec3::Y);
        for c in 0..ceiling.thickness().len() as u32 {
            let r = ceiling.point_above(c, 0.0).length();
            ceiling.add_thickness(c, if r < 0.03 { 0.3 } else { 0.2 });
        }
        let before = ceiling.thickness().to_vec();
        assert_eq!(settle(&mut ceiling, 10), 0.0);
        assert_eq!(ceiling.thickness(), before.as_slice(), "pull-off is the cohesion stage's");
    }

    #[test]
    fn only_cells_near_a_change_are_examined_again() {
        let mut floor = square(0.2, DVec3::Z, DVec3::Y);
        let centre = floor.field.cell_at(0.0, 0.0);
        floor.add_thickness(centre, 0.3);
        // An unfinished relaxation goes on at the next call; a settled one leaves nothing to do.
        let first = relax(&mut floor, RHO, G, TAU, 2);
        assert!(!first.settled && first.sweeps == 2, "{first:?}");
        let second = relax(&mut floor, RHO, G, TAU, 20_000);
        assert!(second.settled && second.sweeps > 0, "{second:?}");
        let third = relax(&mut floor, RHO, G, TAU, 20_000);
        assert!(third.settled && third.sweeps == 0, "{third:?}");
        // A change wakes the cells around it only.
        floor.add_thickness(centre, 0.01);
        let fourth = relax(&mut floor, RHO, G, TAU, 20_000);
        assert!(fourth.settled && fourth.sweeps > 0, "{fourth:?}");
    }
}
