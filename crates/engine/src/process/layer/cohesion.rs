//! Cohesive failure of a deposited layer (the paper's "cells that exceed local support
//! thresholds are flagged and clustered into connected regions").
//!
//! Each cell's self-weight per area, ρ g t, is resolved against the face's orientation into a
//! pull-off stress (the part of gravity along the face's outward normal) and a shear stress (the
//! part along the face). A cell is over-loaded when either exceeds the adhesive strength of the
//! layer on the substrate. Over-loaded cells are clustered into 8-connected regions. The load
//! a region's substrate cannot carry, Σ A · max(σ − f_t, τ − f_s), must be handed on through the
//! layer around it: across each ring of cells around the region in turn, the layer carries at
//! most cohesion × Σ (edge length × shared thickness) (the thinner of the two cells'), and each
//! ring's own substrate takes what its adhesion has to spare, Σ A · min(f_t − σ, f_s − τ). The
//! region holds if the load is absorbed before it meets a ring boundary too thin to pass it on,
//! and falls otherwise. Large patches therefore fall while small ones on a thick enough layer
//! hang on, a lump cannot hang from a thin rim, a uniform layer on a ceiling fails once
//! ρ g t > f_t, on a wall once ρ g t > f_s, and a floor never fails.

use super::{LayerContext, LayerStage, Release};
use crate::deposit::DepositSurface;
use crate::events::FailureEvent;
use glam::DVec3;

/// Strengths of a fresh layer, Pa.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Strength {
    /// Adhesive tensile (pull-off) strength, Pa.
    pub tensile: f64,
    /// Adhesive shear strength, Pa.
    pub shear: f64,
    /// Cohesion of the layer along a region's boundary, Pa.
    pub cohesion: f64,
}

/// One connected over-loaded region.
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    /// Cell indices, ascending.
    pub cells: Vec<u32>,
    /// Load the substrate cannot carry, N.
    pub driving: f64,
    /// Largest load the surrounding layer could take from it, N.
    pub holding: f64,
}

impl Region {
    /// True if the region falls off.
    pub fn fails(&self) -> bool {
        self.driving > self.holding
    }
}

/// Over-loaded regions of one deposit.
#[derive(Clone, Debug, Default)]
pub struct Analysis {
    /// Regions, in order of their first cell.
    pub regions: Vec<Region>,
    /// Over-loaded cells in total.
    pub overloaded_cells: usize,
}

/// Pull-off and shear stress per metre of thickness on a surface with outward unit `normal`,
/// Pa/m.
pub fn stress_per_thickness(density: f64, gravity: DVec3, normal: DVec3) -> (f64, f64) {
    let g = gravity.length();
    if g == 0.0 {
        return (0.0, 0.0);
    }
    let down = gravity / g;
    let pull = down.dot(normal).max(0.0);
    let shear = (down - normal * down.dot(normal)).length();
    (density * g * pull, density * g * shear)
}

/// Pull-off and shear stress per metre of thickness at every cell, Pa/m: one value for a flat
/// surface, one per cell otherwise.
struct Stresses(Vec<(f64, f64)>);

impl Stresses {
    fn of(surface: &impl DepositSurface, density: f64, gravity: DVec3) -> Stresses {
        match surface.uniform_normal() {
            Some(n) => Stresses(vec![stress_per_thickness(density, gravity, n)]),
            None => Stresses(
                (0..surface.thickness().len() as u32)
                    .map(|c| stress_per_thickness(density, gravity, surface.normal(c)))
                    .collect(),
            ),
        }
    }

    #[inline]
    fn at(&self, cell: usize) -> (f64, f64) {
        if self.0.len() == 1 { self.0[0] } else { self.0[cell] }
    }
}

/// Finds the over-loaded regions of a deposit.
pub fn analyse(surface: &impl DepositSurface, density: f64, gravity: DVec3, s: &Strength) -> Analysis {
    // A flat surface whose thickest cell is within both strengths has nothing to analyse.
    if let Some(n) = surface.uniform_normal() {
        let (pull, shear) = stress_per_thickness(density, gravity, n);
        let top = surface.max_thickness();
        if top * pull <= s.tensile && top * shear <= s.shear {
            return Analysis::default();
        }
    }
    let stress = Stresses::of(surface, density, gravity);
    let t = surface.thickness();
    let over = |i: usize| {
        let (pull, shear) = stress.at(i);
        t[i] * pull > s.tensile || t[i] * shear > s.shear
    };
    let mut label = vec![u32::MAX; t.len()];
    let mut seen = Seen { mark: vec![0; t.len()], next: 1 };
    let mut out = Analysis::default();
    let mut stack = Vec::new();
    for start in 0..t.len() {
        if label[start] != u32::MAX || !over(start) {
            continue;
        }
        let id = out.regions.len() as u32;
        let mut cells = Vec::new();
        label[start] = id;
        stack.push(start);
        while let Some(c) = stack.pop() {
            cells.push(c as u32);
            surface.neighbours(c as u32, &mut |n, _| {
                let n = n as usize;
                if label[n] == u32::MAX && over(n) {
                    label[n] = id;
                    stack.push(n);
                }
            });
        }
        cells.sort_unstable();
        out.overloaded_cells += cells.len();
        let mut driving = 0.0;
        for &c in &cells {
            let (pull, shear) = stress.at(c as usize);
            let tc = t[c as usize];
            driving += surface.cell_area(c) * (tc * pull - s.tensile).max(tc * shear - s.shear).max(0.0);
        }
        let holding = support(surface, &stress, s, &cells, &mut seen);
        out.regions.push(Region { cells, driving, holding });
    }
    out
}

/// Marks of the cells the support search has reached: `mark[c]` is the stamp of the ring `c`
/// was found in; stamps only grow, so a search sees the marks of earlier ones as unmarked.
struct Seen {
    mark: Vec<u32>,
    next: u32,
}

impl Seen {
    fn stamp(&mut self) -> u32 {
        self.next += 1;
        self.next - 1
    }
}

/// The largest load (N) the layer around the region `cells` can take from it: the smallest,
/// over the rings of cells around it, of what crosses that ring's inner boundary plus what the
/// rings inside it absorb.
fn support(
    surface: &impl DepositSurface,
    stress: &Stresses,
    s: &Strength,
    cells: &[u32],
    seen: &mut Seen,
) -> f64 {
    let t = surface.thickness();
    let spare = |c: u32| {
        let (pull, shear) = stress.at(c as usize);
        let tc = t[c as usize];
        surface.cell_area(c) * (s.tensile - tc * pull).min(s.shear - tc * shear).max(0.0)
    };
    let first = seen.stamp();
    cells.iter().for_each(|&c| seen.mark[c as usize] = first);
    let (mut holding, mut absorbed) = (f64::INFINITY, 0.0);
    let mut frontier = cells.to_vec();
    let mut ring = Vec::new();
    while absorbed < holding {
        let stamp = seen.stamp();
        let mut crossing = 0.0;
        ring.clear();
        for &c in &frontier {
            surface.neighbours(c, &mut |n, edge| {
                let (tn, m) = (t[n as usize], seen.mark[n as usize]);
                // Edges into cells not yet reached, or reached by this ring.
                if edge > 0.0 && tn > 0.0 && (m < first || m == stamp) {
                    crossing += s.cohesion * edge * t[c as usize].min(tn);
                    if m != stamp {
                        seen.mark[n as usize] = stamp;
                        ring.push(n);
                    }
                }
            });
        }
        holding = holding.min(absorbed + crossing);
        if ring.is_empty() {
            break;
        }
        absorbed += ring.iter().map(|&c| spare(c)).sum::<f64>();
        std::mem::swap(&mut frontier, &mut ring);
    }
    // Left by the loop's test, or by running out of rings (where nothing crossed), holding is
    // at most what was absorbed.
    holding
}

/// Cohesive failure: every interval, each target's layer is analysed; failing regions leave the
/// deposit and fall as particles, one per cell carrying that cell's volume, released at rest
/// just in front of the surface (in target, region and cell order, so deterministically).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CohesionStage {
    /// Strengths of the fresh layer.
    pub strength: Strength,
}

impl LayerStage for CohesionStage {
    fn name(&self) -> &'static str {
        "cohesion"
    }

    fn run(&self, ctx: &mut LayerContext<'_>) {
        for t in ctx.targets.iter_mut() {
            let analysis = analyse(&t.surface, ctx.density, ctx.gravity, &self.strength);
            // Cells over-loaded at the last analysis are cleared first (the mask keeps failures).
            if t.at_risk {
                t.failure_mask.iter_mut().filter(|m| **m == 1).for_each(|m| *m = 0);
            }
            t.at_risk = analysis.regions.iter().any(|r| !r.fails());
            for region in &analysis.regions {
                if !region.fails() {
                    for &cell in &region.cells {
                        let m = &mut t.failure_mask[cell as usize];
                        *m = (*m).max(1);
                    }
                    continue;
                }
                let area = t.surface.area_of(&region.cells);
                let mut volume = 0.0;
                for &cell in &region.cells {
                    t.failure_mask[cell as usize] = 2;
                    volume += ctx.release.release(t, cell, f64::INFINITY, Release::Failure);
                }
                ctx.failures.push(FailureEvent {
                    time: ctx.time,
                    target: t.name.clone(),
                    cells: region.cells.len(),
                    area,
                    volume,
                });
            }
        }
    }
}
