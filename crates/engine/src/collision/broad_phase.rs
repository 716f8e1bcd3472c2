//! Broad phase: a uniform grid over the bounded surfaces, walked cell by cell along a segment
//! (3D DDA), so that a particle in free flight tests nothing and one near a surface tests only
//! the few surfaces that share its cells, whatever their total number.

use super::Aabb;
use glam::{DVec3, IVec3};
use std::sync::Arc;

/// Most grid cells; the cell size grows to respect it.
const MAX_CELLS: f64 = 2_097_152.0;
/// Smallest cell edge, m.
const MIN_CELL: f64 = 0.01;
/// Margin by which each surface's box is grown when it is binned, m: far above rounding in the
/// walk, far below any feature.
const BIN_MARGIN: f64 = 1e-6;

/// Bits of [`Grid::flags`].
mod cell {
    /// The cell holds a surface or lies in a marked zone.
    pub const OCCUPIED: u8 = 1;
    /// The cell or one of its 26 neighbours is occupied.
    pub const CROWDED: u8 = 2;
}

/// Surfaces binned into the cells their bounding boxes overlap (compressed rows), plus zones
/// marked later (a layer growing in front of a surface) that make cells occupied without
/// listing anything in them.
///
/// The binned surfaces never change, so a clone shares them; the occupancy maps are shared
/// until a clone marks a zone (copy on write).
#[derive(Clone, Debug, Default)]
pub struct Grid {
    origin: DVec3,
    cell: f64,
    inv_cell: f64,
    dims: IVec3,
    /// Upper corner of the grid, m.
    end: DVec3,
    /// `dims - 1` as floats: the largest cell coordinate.
    last: DVec3,
    /// `items[start[c]..start[c + 1]]` are the surfaces in cell `c`.
    start: Arc<[u32]>,
    items: Arc<[u32]>,
    /// Per cell: [`cell::OCCUPIED`], [`cell::CROWDED`].
    flags: Arc<[u8]>,
    /// Per block of 2 × 2 × 2 cells: Chebyshev distance in blocks to the nearest block holding
    /// an occupied cell, capped at [`DISTANCE_CAP`]: the blocks within `d − 1` of it hold none.
    /// Blocks keep its cost to build small beside the grid's.
    distance: Arc<[u8]>,
    /// `flags` and `distance` as binned, before any zone was marked.
    binned: (Arc<[u8]>, Arc<[u8]>),
    /// Blocks along each axis.
    blocks: IVec3,
}

/// Largest distance the distance map records, blocks: a free flight crosses open space in
/// jumps of up to twice this many blocks.
const DISTANCE_CAP: u8 = 8;

/// Most jumps of one free-flight query.
const MAX_JUMPS: usize = 64;

impl Grid {
    /// Bins `boxes[i]` (surface `i`; `None`: unbounded, not binned). The grid covers `bounds`
    /// and every box, so every point of every binned surface lies inside it.
    pub fn new(boxes: &[Option<Aabb>], bounds: Aabb) -> Grid {
        let bounds = boxes.iter().flatten().fold(bounds, |b, s| {
            let s = s.inflate(BIN_MARGIN);
            Aabb { min: b.min.min(s.min), max: b.max.max(s.max) }
        });
        let extent = (bounds.max - bounds.min).max(DVec3::splat(MIN_CELL));
        let cell = cell_size(extent);
        let dims = (extent / cell).ceil().as_ivec3().max(IVec3::ONE);
        let last = (dims - 1).as_dvec3();
        let mut grid = Grid {
            origin: bounds.min,
            cell,
            inv_cell: 1.0 / cell,
            dims,
            end: bounds.min + dims.as_dvec3() * cell,
            last,
            start: Arc::default(),
            items: Arc::default(),
            flags: Arc::default(),
            distance: Arc::default(),
            binned: Default::default(),
            blocks: (dims + 1) / 2,
        };
        let n = (dims.x * dims.y * dims.z) as usize;
        // Two passes, count then fill, build the compressed rows without a list per cell.
        let mut count = vec![0u32; n + 1];
        grid.for_each_binned_cell(boxes, |c, _| count[c + 1] += 1);
        for c in 0..n {
            count[c + 1] += count[c];
        }
        let mut fill = count.clone();
        let mut items = vec![0u32; count[n] as usize];
        grid.for_each_binned_cell(boxes, |c, i| {
            items[fill[c] as usize] = i;
            fill[c] += 1;
        });
        drop(fill);
        let occupied: Vec<u8> = count[..n].iter().zip(&count[1..]).map(|(a, b)| u8::from(a != b)).collect();
        grid.start = count.into();
        grid.items = items.into();
        let crowded = dilate3(&occupied, grid.dims);
        grid.distance = grid.distances(&occupied).into();
        grid.flags = occupied
            .iter()
            .zip(&crowded)
            .map(|(&o, &c)| (o * cell::OCCUPIED) | (c * cell::CROWDED))
            .collect();
        grid.binned = (grid.flags.clone(), grid.distance.clone());
        grid
    }

    /// Makes every cell that `b` overlaps occupied, as if a surface filled `b`, without
    /// listing anything in those cells: the free-flight tests then send particles there to the
    /// full search, which finds what they meet by other means (a deposited layer). Costs the
    /// cells of `b` and the blocks near it, not the grid.
    pub fn mark(&mut self, b: &Aabb) {
        if self.start.is_empty() {
            return;
        }
        let b = b.inflate(BIN_MARGIN);
        let (lo, hi) = (self.cell_of(b.min), self.cell_of(b.max));
        let (dims, blocks) = (self.dims, self.blocks);
        let (from, to) = ((lo - 1).max(IVec3::ZERO), (hi + 1).min(dims - 1));
        let flags = Arc::make_mut(&mut self.flags);
        for z in from.z..=to.z {
            for y in from.y..=to.y {
                for x in from.x..=to.x {
                    let c = IVec3::new(x, y, z);
                    let inside = c.cmpge(lo).all() && c.cmple(hi).all();
                    flags[flat(c, dims)] |= cell::CROWDED | if inside { cell::OCCUPIED } else { 0 };
                }
            }
        }
        // The distance to the nearest occupied block is the least over occupied blocks, so it
        // only needs the distance to the marked ones where that is below the cap.
        let (blo, bhi) = (lo / 2, hi / 2);
        let reach = i32::from(DISTANCE_CAP) - 1;
        let (from, to) = ((blo - reach).max(IVec3::ZERO), (bhi + reach).min(blocks - 1));
        let distance = Arc::make_mut(&mut self.distance);
        for z in from.z..=to.z {
            for y in from.y..=to.y {
                for x in from.x..=to.x {
                    let c = IVec3::new(x, y, z);
                    let d = (blo - c).max(c - bhi).max(IVec3::ZERO).max_element() as u8;
                    let i = flat(c, blocks);
                    distance[i] = distance[i].min(d);
                }
            }
        }
    }

    /// Forgets every zone [`Grid::mark`] added: the grid as binned.
    pub fn clear_marks(&mut self) {
        (self.flags, self.distance) = self.binned.clone();
    }

    /// Calls `f(cell, surface)` for every cell each bounded surface's box overlaps, in surface
    /// order (so each cell lists its surfaces in order).
    fn for_each_binned_cell(&self, boxes: &[Option<Aabb>], mut f: impl FnMut(usize, u32)) {
        for (i, b) in boxes.iter().enumerate() {
            let Some(b) = b else { continue };
            let b = b.inflate(BIN_MARGIN);
            let (lo, hi) = (self.cell_of(b.min), self.cell_of(b.max));
            for z in lo.z..=hi.z {
                for y in lo.y..=hi.y {
                    for x in lo.x..=hi.x {
                        f(self.index(IVec3::new(x, y, z)), i as u32);
                    }
                }
            }
        }
    }

    /// Index of block `c` in the distance map.
    #[inline]
    fn block_index(&self, c: IVec3) -> usize {
        flat(c, self.blocks)
    }

    /// Per block: the Chebyshev distance in blocks to the nearest block holding an `occupied`
    /// cell, capped at [`DISTANCE_CAP`], by growing the occupied blocks one block at a time.
    fn distances(&self, occupied: &[u8]) -> Vec<u8> {
        let b = self.blocks;
        let mut reached = vec![0u8; (b.x * b.y * b.z) as usize];
        for (i, &o) in occupied.iter().enumerate() {
            if o != 0 {
                let (x, rest) = (i as i32 % self.dims.x, i as i32 / self.dims.x);
                let (y, z) = (rest % self.dims.y, rest / self.dims.y);
                reached[self.block_index(IVec3::new(x, y, z) / 2)] = 1;
            }
        }
        let mut distance = vec![DISTANCE_CAP; reached.len()];
        for d in 0..DISTANCE_CAP {
            if d > 0 {
                reached = dilate3(&reached, b);
            }
            for (out, &r) in distance.iter_mut().zip(&reached) {
                // Reached at this growth for the first time: at distance `d`.
                *out = if r != 0 { (*out).min(d) } else { *out };
            }
        }
        distance
    }

    /// How long (s) the arc from `x` with velocity `v` under acceleration `g` certainly touches
    /// no binned surface, up to `horizon` (s): it jumps from box to empty box of the distance
    /// map, each jump to where the arc leaves the box of cells around it that holds nothing.
    /// The answer is conservative: 0 at the grid's edge or next to a surface.
    pub fn free_flight(&self, x: DVec3, v: DVec3, g: DVec3, horizon: f64) -> f64 {
        if self.start.is_empty() {
            return horizon;
        }
        let mut t = 0.0;
        for _ in 0..MAX_JUMPS {
            if t >= horizon {
                return horizon;
            }
            let arc = super::Flight { x0: x + v * t + 0.5 * g * t * t, v0: v + g * t, g, duration: 0.0 };
            let p = arc.x0;
            if !(self.origin.cmple(p).all() && p.cmplt(self.end).all()) {
                return t;
            }
            let c = self.cell_of(p) / 2;
            let d = self.distance[self.block_index(c)];
            if d == 0 {
                return t;
            }
            // The blocks within `d − 1` of `c` hold nothing; the grid's edge bounds the box, as
            // what lies beyond it is not known to be empty.
            let (r, block) = (i32::from(d) - 1, 2.0 * self.cell);
            let lo = (self.origin + (c - r).as_dvec3() * block).max(self.origin);
            let hi = (self.origin + (c + r + 1).as_dvec3() * block).min(self.end);
            let jump = arc.exit_time(&super::Aabb { min: lo, max: hi });
            // No progress (on a box's face, heading out): stop rather than spin.
            if jump <= 1e-12 {
                return t;
            }
            t += jump;
        }
        t.min(horizon)
    }

    /// Cell containing `p`, clamped to the grid. Clamping first makes the truncating cast a
    /// floor, without a call to `floor`.
    #[inline]
    fn cell_of(&self, p: DVec3) -> IVec3 {
        ((p - self.origin) * self.inv_cell).clamp(DVec3::ZERO, self.last).as_ivec3()
    }

    #[inline]
    fn index(&self, c: IVec3) -> usize {
        flat(c, self.dims)
    }

    #[inline]
    fn cell_items(&self, c: IVec3) -> &[u32] {
        let i = self.index(c);
        &self.items[self.start[i] as usize..self.start[i + 1] as usize]
    }

    /// True if the segment certainly touches no binned surface: it is shorter than a cell
    /// along every axis and starts in a cell whose whole neighbourhood is empty (so it ends in
    /// that neighbourhood), or it lies within one empty cell.
    #[inline]
    pub fn is_clear(&self, p0: DVec3, p1: DVec3) -> bool {
        if self.start.is_empty() {
            return true;
        }
        if !(self.origin.cmple(p0).all() && p0.cmplt(self.end).all()) {
            return false;
        }
        let c = self.cell_of(p0);
        let i = self.index(c);
        let flags = self.flags[i];
        if flags & cell::CROWDED == 0 && (p1 - p0).abs().max_element() < self.cell {
            return true;
        }
        flags & cell::OCCUPIED == 0 && c == self.cell_of(p1)
    }

    /// True if everything inside `b` certainly misses every binned surface: `b` is smaller than
    /// a cell along every axis and its lower corner lies in a cell with an empty neighbourhood.
    #[inline]
    pub fn box_is_clear(&self, b: &Aabb) -> bool {
        if self.start.is_empty() {
            return true;
        }
        if !(self.origin.cmple(b.min).all() && b.min.cmplt(self.end).all()) {
            return false;
        }
        (b.max - b.min).max_element() < self.cell
            && self.flags[self.index(self.cell_of(b.min))] & cell::CROWDED == 0
    }

    /// True if the box `b`, inside the grid, lies within one empty neighbourhood of the
    /// distance map: the blocks within the distance of the block at its centre, less one, hold
    /// nothing, and `b` lies inside them. False when anything is binned near it, or it reaches
    /// past the grid's edge (what lies beyond is not known to be empty).
    pub fn box_is_empty(&self, b: &Aabb) -> bool {
        if self.start.is_empty() {
            return true;
        }
        if !(self.origin.cmple(b.min).all() && b.max.cmplt(self.end).all()) {
            return false;
        }
        let (lo, hi) = (self.cell_of(b.min) / 2, self.cell_of(b.max) / 2);
        let c = (lo + hi) / 2;
        let d = i32::from(self.distance[self.block_index(c)]);
        let r = d - 1;
        d > 0 && (c - lo).max_element() <= r && (hi - c).max_element() <= r
    }

    /// Calls `visit` with the surfaces of every cell that `b` overlaps (a surface spanning
    /// several of them is visited once per cell).
    pub fn for_each_in_box(&self, b: &Aabb, mut visit: impl FnMut(&[u32])) {
        if self.start.is_empty() || !b.overlaps(&Aabb { min: self.origin, max: self.end }) {
            return;
        }
        let (lo, hi) = (self.cell_of(b.min), self.cell_of(b.max));
        for z in lo.z..=hi.z {
            for y in lo.y..=hi.y {
                for x in lo.x..=hi.x {
                    visit(self.cell_items(IVec3::new(x, y, z)));
                }
            }
        }
    }

    /// Calls `visit` with the surfaces of each cell the segment `p0 → p1` passes through, in
    /// order along it, with the segment fraction at which that cell is left. `visit` returns the
    /// fraction of the best hit so far; the walk stops once no later cell can beat it.
    ///
    /// A segment with a non-finite end meets nothing and visits no cell: the checks at every
    /// way in (configuration, nozzle paths, checkpoints) keep such a state out of a run, and
    /// the walk must end whatever it is given. It visits at most one cell per grid line it can
    /// cross, so it ends for any input.
    #[inline]
    pub fn walk(&self, p0: DVec3, p1: DVec3, mut visit: impl FnMut(&[u32]) -> f64) {
        if self.start.is_empty() || !(p0.is_finite() && p1.is_finite()) {
            return;
        }
        let c0 = self.cell_of(p0);
        let c1 = self.cell_of(p1);
        if c0 == c1 {
            // The common case: a short segment inside one cell (clamping is harmless here, as
            // the outer cells also hold whatever lies beyond the grid's edge).
            visit(self.cell_items(c0));
            return;
        }
        let d = p1 - p0;
        // Clip the segment to the grid's box.
        let (lo, hi) = (self.origin, self.end);
        let (mut t_in, mut t_out) = (0.0_f64, 1.0_f64);
        for a in 0..3 {
            if d[a] == 0.0 {
                if p0[a] < lo[a] || p0[a] > hi[a] {
                    return;
                }
                continue;
            }
            let inv = 1.0 / d[a];
            let (t0, t1) = ((lo[a] - p0[a]) * inv, (hi[a] - p0[a]) * inv);
            t_in = t_in.max(t0.min(t1));
            t_out = t_out.min(t0.max(t1));
        }
        if t_in > t_out {
            return;
        }
        let mut c = self.cell_of(p0 + d * t_in);
        let step = IVec3::new(d.x.signum() as i32, d.y.signum() as i32, d.z.signum() as i32);
        let mut t_max = DVec3::INFINITY;
        let mut t_delta = DVec3::INFINITY;
        for a in 0..3 {
            if d[a] != 0.0 {
                let next = self.origin[a] + (c[a] + i32::from(d[a] > 0.0)) as f64 * self.cell;
                t_max[a] = (next - p0[a]) / d[a];
                t_delta[a] = self.cell / d[a].abs();
            }
        }
        let most = self.dims.x + self.dims.y + self.dims.z;
        for _ in 0..most {
            let best = visit(self.cell_items(c));
            let exit = t_max.min_element();
            if best <= exit || exit >= t_out {
                return;
            }
            let a = if t_max.x <= t_max.y && t_max.x <= t_max.z {
                0
            } else if t_max.y <= t_max.z {
                1
            } else {
                2
            };
            c[a] += step[a];
            if c[a] < 0 || c[a] >= self.dims[a] {
                return;
            }
            t_max[a] += t_delta[a];
        }
    }
}

/// Index of `c` in an array laid out x fastest over `dims`.
#[inline]
fn flat(c: IVec3, dims: IVec3) -> usize {
    (c.x + dims.x * (c.y + dims.y * c.z)) as usize
}

/// Cells along each axis of a grid of cubes of edge `cell` over `extent`, at least one each.
fn cell_counts(extent: DVec3, cell: f64) -> DVec3 {
    (extent / cell).ceil().max(DVec3::ONE)
}

/// The edge of the grid's cubes over `extent` (m, each axis at least [`MIN_CELL`]): the
/// smallest, from [`MIN_CELL`] up, whose grid has at most [`MAX_CELLS`] cells. An axis thinner
/// than a cell still takes one, so a thin, wide box needs larger cells than the volume alone
/// says; the count only falls as the cell grows, so bisection finds it.
fn cell_size(extent: DVec3) -> f64 {
    let fits = |cell: f64| {
        let n = cell_counts(extent, cell);
        n.x * n.y * n.z <= MAX_CELLS
    };
    let guess = (extent.x * extent.y * extent.z / MAX_CELLS).cbrt().max(MIN_CELL);
    if !guess.is_finite() {
        // Beyond any scene a scenario accepts; one cell keeps the grid valid.
        return extent.max_element().min(f64::MAX);
    }
    if fits(guess) {
        return guess;
    }
    // A cube as large as the longest axis gives a single cell, which fits.
    let (mut lo, mut hi) = (guess, extent.max_element());
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if fits(mid) { hi = mid } else { lo = mid }
    }
    hi
}

/// `cells`, laid out over `dims`, dilated by one cell along every axis: each cell set if it or
/// any of its 26 neighbours is. Separable: one pass along x, then y, then z instead of 27
/// lookups per cell, each a plain loop over rows so that it runs at memory speed on millions
/// of cells.
fn dilate3(cells: &[u8], dims: IVec3) -> Vec<u8> {
    let (dx, dy) = (dims.x as usize, dims.y as usize);
    let along_x = dilate(cells, 1, dx);
    let along_y = dilate(&along_x, dx, dy);
    dilate(&along_y, dx * dy, dims.z as usize)
}

/// `cells` dilated by one step of `stride` along an axis of `len` cells: a cell is set if it or
/// its neighbour before or after along that axis is (no wrap-around at the axis ends). The
/// cells come in blocks of `len` lines of `stride` cells; within a block, shifting by one line
/// is shifting the slice by `stride`, so each block is two vectorisable slice passes.
fn dilate(cells: &[u8], stride: usize, len: usize) -> Vec<u8> {
    let span = stride * len;
    let mut out = cells.to_vec();
    for (o, c) in out.chunks_exact_mut(span).zip(cells.chunks_exact(span)) {
        for (a, &b) in o[stride..].iter_mut().zip(&c[..span - stride]) {
            *a |= b;
        }
        for (a, &b) in o[..span - stride].iter_mut().zip(&c[stride..]) {
            *a |= b;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_walk_with_a_non_finite_end_ends_at_once_and_visits_nothing() {
        let b = Aabb { min: DVec3::splat(-1.0), max: DVec3::splat(1.0) };
        let small = Aabb { min: DVec3::splat(-0.1), max: DVec3::splat(0.1) };
        let grid = Grid::new(&[Some(small), Some(b)], b);
        let finite = DVec3::new(-0.9, 0.0, 0.0);
        for bad in [DVec3::new(f64::NAN, 0.0, 0.0), DVec3::new(0.0, f64::INFINITY, 0.0), DVec3::NEG_INFINITY]
        {
            for (p0, p1) in [(finite, bad), (bad, finite), (bad, bad)] {
                let mut visits = 0;
                grid.walk(p0, p1, |_| {
                    visits += 1;
                    f64::INFINITY
                });
                assert_eq!(visits, 0, "{p0} → {p1}");
            }
        }
        // A finite segment across the grid still visits the cells on its way.
        let mut visits = 0;
        grid.walk(finite, DVec3::new(0.9, 0.3, -0.2), |_| {
            visits += 1;
            f64::INFINITY
        });
        assert!(visits > 1);
    }

    /// Issue 17, defect 1: a thin, wide box or a huge one kept the cap on cells.
    #[test]
    fn cell_cap_is_honoured_for_thin_wide_and_huge_extents() {
        for (min, max) in [
            (DVec3::new(-1e4, -1e4, -0.005), DVec3::new(1e4, 1e4, 0.005)),
            (DVec3::new(-1e6, -1e6, -1.0), DVec3::new(1e6, 1e6, 1.0)),
            (DVec3::new(-1e30, -0.005, -1e30), DVec3::new(1e30, 0.005, 1e30)),
            (DVec3::new(-1e4, -0.001, -0.001), DVec3::new(1e4, 0.001, 0.001)),
        ] {
            let b = Aabb { min, max };
            let grid = Grid::new(&[Some(b)], b);
            let cells = i64::from(grid.dims.x) * i64::from(grid.dims.y) * i64::from(grid.dims.z);
            assert!(
                grid.dims.min_element() >= 1 && cells as f64 <= MAX_CELLS,
                "{min} … {max}: {}",
                grid.dims
            );
            assert!(!grid.is_clear(min * 0.5, max * 0.5));
        }
    }

    #[test]
    fn empty_neighbourhoods_match_a_direct_27_cell_check() {
        let boxes: Vec<Option<Aabb>> = [
            (DVec3::new(0.1, 0.1, 0.1), DVec3::new(0.12, 0.3, 0.11)),
            (DVec3::new(0.5, 0.45, 0.0), DVec3::new(0.51, 0.46, 0.9)),
            (DVec3::new(0.95, 0.0, 0.7), DVec3::new(1.0, 1.0, 0.71)),
        ]
        .into_iter()
        .map(|(min, max)| Some(Aabb { min, max }))
        .collect();
        let grid = Grid::new(&boxes, Aabb { min: DVec3::ZERO, max: DVec3::ONE });
        let d = grid.dims;
        let occupied = |x: i32, y: i32, z: i32| {
            let c = grid.index(IVec3::new(x, y, z));
            grid.start[c] != grid.start[c + 1]
        };
        let mut checked = 0;
        for z in 0..d.z {
            for y in 0..d.y {
                for x in 0..d.x {
                    let mut any = false;
                    for (i, j, k) in
                        (-1..=1).flat_map(|i| (-1..=1).flat_map(move |j| (-1..=1).map(move |k| (i, j, k))))
                    {
                        let (a, b, c) = (x + i, y + j, z + k);
                        if (0..d.x).contains(&a) && (0..d.y).contains(&b) && (0..d.z).contains(&c) {
                            any |= occupied(a, b, c);
                        }
                    }
                    let clear = grid.flags[grid.index(IVec3::new(x, y, z))] & cell::CROWDED == 0;
                    assert_eq!(clear, !any, "cell {x},{y},{z}");
                    checked += 1;
                }
            }
        }
        let crowded = |f: &u8| f & cell::CROWDED != 0;
        assert!(checked > 100_000 && grid.flags.iter().any(crowded) && !grid.flags.iter().all(crowded));
    }

    /// A zone marked after binning occupies the grid exactly as a surface binned with that box
    /// would, and clearing the marks gives back the grid as binned.
    #[test]
    fn marking_a_zone_equals_binning_its_box() {
        let bounds = Aabb { min: DVec3::ZERO, max: DVec3::ONE };
        let wall = Aabb { min: DVec3::new(0.8, 0.1, 0.1), max: DVec3::new(0.8, 0.9, 0.9) };
        let bar = Aabb { min: DVec3::new(0.1, 0.5, 0.0), max: DVec3::new(0.12, 0.52, 1.0) };
        let layer = Aabb { min: DVec3::new(0.66, 0.1, 0.1), max: wall.max };
        let binned = Grid::new(&[Some(wall), Some(bar), Some(layer)], bounds);
        let mut marked = Grid::new(&[Some(wall), Some(bar)], bounds);
        let before = marked.clone();
        assert_eq!(marked.dims, binned.dims);
        // Twice, as a layer's zone grows: the smaller zone lies inside the larger.
        marked.mark(&Aabb { min: DVec3::new(0.75, 0.1, 0.1), max: wall.max });
        marked.mark(&layer);
        assert_eq!(marked.flags, binned.flags);
        assert_eq!(marked.distance, binned.distance);
        // The clone taken before still sees the grid as it was (copy on write).
        assert_ne!(before.flags, marked.flags);
        marked.clear_marks();
        assert_eq!((marked.flags, marked.distance), (before.flags, before.distance));
    }

    #[test]
    fn distances_match_a_direct_search_and_free_flights_stay_in_empty_cells() {
        let boxes = vec![
            Some(Aabb { min: DVec3::new(0.3, 0.3, 0.3), max: DVec3::new(0.32, 0.35, 0.31) }),
            Some(Aabb { min: DVec3::new(0.7, 0.1, 0.5), max: DVec3::new(0.71, 0.9, 0.52) }),
        ];
        let grid = Grid::new(&boxes, Aabb { min: DVec3::ZERO, max: DVec3::ONE });
        let b = grid.blocks;
        let occupied: Vec<IVec3> = (0..grid.dims.z)
            .flat_map(|z| {
                (0..grid.dims.y).flat_map(move |y| (0..grid.dims.x).map(move |x| IVec3::new(x, y, z)))
            })
            .filter(|&c| !grid.cell_items(c).is_empty())
            .map(|c| c / 2)
            .collect();
        for z in (0..b.z).step_by(2) {
            for y in 0..b.y {
                for x in 0..b.x {
                    let c = IVec3::new(x, y, z);
                    let nearest =
                        occupied.iter().map(|&o| (o - c).abs().max_element()).min().unwrap_or(i32::MAX);
                    let expected = nearest.min(i32::from(DISTANCE_CAP)) as u8;
                    assert_eq!(grid.distance[grid.block_index(c)], expected, "block {c}");
                }
            }
        }
        // Arcs through the unit box: before the free-flight time runs out, every point of the
        // arc lies in a cell holding nothing (at the end it may touch such a cell's face).
        let g = DVec3::new(0.0, 0.0, -9.81);
        let mut state = 0x9E37_79B9_7F4A_7C15_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut long = 0;
        for _ in 0..2000 {
            let x = DVec3::new(next(), next(), next());
            let v = (DVec3::new(next(), next(), next()) - 0.5) * 8.0;
            let t = grid.free_flight(x, v, g, 1.0);
            for k in (0..200).filter(|_| t > 0.0) {
                let tau = t * f64::from(k) / 200.0;
                let p = x + v * tau + 0.5 * g * tau * tau;
                assert!(grid.cell_items(grid.cell_of(p)).is_empty(), "{p} at {tau} of {t} s from {x}, {v}");
            }
            long += usize::from(t > 0.05);
        }
        assert!(long > 500, "most flights through open space are long ({long})");
    }
}
