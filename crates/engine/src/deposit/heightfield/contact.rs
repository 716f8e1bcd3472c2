//! Where a path enters the deposited layer: a march at half a cell along the path over the
//! max-pyramid of the thickness (skipping runs of samples the pyramid shows are clear), a
//! bisection of the entry, and the layer's normal there from the thickness gradient; and the
//! pyramid's bounds of the layer under a box, for flights asleep over it.

use super::HeightField;
use crate::deposit::{Chart, LayerContact, Nodes};
use glam::DVec3;

/// Pyramid level at which the layer march first tries to skip samples: blocks of 16 × 16
/// cells. It climbs a level after each skip and descends after each failed attempt.
const SKIP_LEVEL: usize = 4;

/// Pyramid level whose blocks (16 × 16 cells) bound where the layer march starts.
const START_LEVEL: usize = 4;

/// Lowest level the march skips at (runs of 7 samples: fewer are not worth the look).
const SKIP_FLOOR: usize = 2;

/// Clearance above the blocks' maximum required to skip, m: far above the rounding of the
/// heights, so that no skipped sample could have tested inside.
const SKIP_MARGIN: f64 = 1e-9;

/// Lowest pyramid level whose nodes sleeping flights watch (blocks of 4 × 4 cells): the bound
/// under a flight close to the layer stays tight, and a single cell's growth wakes only the
/// flights over its block.
const WATCH_LEVEL: usize = 2;

impl HeightField {
    /// Thickness gradient `(∂t/∂u, ∂t/∂v)` at a cell, dimensionless: central differences
    /// across the deposit footprint (one-sided at the edges).
    pub fn gradient(&self, cell: u32) -> (f64, f64) {
        let (dx, dy) = self.cell_size();
        let (row, col) = (cell as usize / self.cols, cell as usize % self.cols);
        let at = |r: usize, c: usize| self.thickness[r * self.cols + c];
        let (r0, r1) = (row.saturating_sub(self.reach.1), (row + self.reach.1).min(self.rows - 1));
        let reach = self.reach.0.min((self.cols - 1) / 2) as isize;
        let (lo, hi) = (col as isize - reach, col as isize + reach);
        // Clamped to the grid, or across the seam of a periodic one.
        let c0 = self.column(lo).map_or((0, 0), |c| (c, lo));
        let c1 = self.column(hi).map_or((self.cols - 1, self.cols as isize - 1), |c| (c, hi));
        let span = (c1.1 - c0.1) as f64;
        let gu = if span > 0.0 { (at(row, c1.0) - at(row, c0.0)) / (span * dx) } else { 0.0 };
        let gv = if r1 > r0 { (at(r1, col) - at(r0, col)) / ((r1 - r0) as f64 * dy) } else { 0.0 };
        (gu, gv)
    }

    /// The nodes of the bounds (blocks of 4 × 4 cells or larger, or the root of a smaller field)
    /// that cover the cells under the rectangle `u` × `v` (m, in-face coordinates, clamped to
    /// the field), and the largest of their bounds, m.
    pub fn nodes_under(&self, u: (f64, f64), v: (f64, f64)) -> (Nodes, f64) {
        let (a, b) = (self.cell_at(u.0, v.0) as usize, self.cell_at(u.1, v.1) as usize);
        let ((c0, r0), (c1, r1)) = ((a % self.cols, a / self.cols), (b % self.cols, b / self.cols));
        let nodes = self.bounds.cover((c0, c1), (r0, r1), WATCH_LEVEL);
        (nodes, self.bounds.max_over(&self.thickness, &nodes))
    }

    /// An upper bound of the thickness over node `(col, row)` of level `level` of the bounds
    /// (blocks of `2ˡᵉᵛᵉˡ` cells; level 0: the cell), m.
    pub fn node_bound(&self, level: u32, col: u32, row: u32) -> f64 {
        self.bounds.bound(&self.thickness, level, col, row)
    }

    /// Column and row of the cell under `p`.
    #[inline]
    fn cell_of(&self, chart: &impl Chart, p: DVec3) -> (usize, usize) {
        let (u, v, _) = chart.local(p);
        let cell = self.cell_at(u, v) as usize;
        (cell % self.cols, cell / self.cols)
    }

    /// The segment's footprint: the columns and the rows of cells between its ends.
    fn segment_cells(&self, chart: &impl Chart, p0: DVec3, p1: DVec3) -> ((usize, usize), (usize, usize)) {
        let ((c0, r0), (c1, r1)) = (self.cell_of(chart, p0), self.cell_of(chart, p1));
        ((c0.min(c1), c0.max(c1)), (r0.min(r1), r0.max(r1)))
    }

    /// Largest bound over the 3 × 3 nodes of pyramid level `k` (blocks of `2ᵏ` cells) around
    /// the one under `p`, m.
    fn max_around(&self, chart: &impl Chart, p: DVec3, k: usize) -> f64 {
        let (c, r) = self.cell_of(chart, p);
        let (r, c) = (r >> k, c >> k);
        let (rr, cc) = ((self.rows - 1) >> k, (self.cols - 1) >> k);
        let mut top = 0.0_f64;
        for row in r.saturating_sub(1)..=(r + 1).min(rr) {
            for col in c.saturating_sub(1)..=(c + 1).min(cc) {
                top = top.max(self.bounds.node(k, col, row));
            }
        }
        top
    }

    /// Largest bound over the blocks of [`START_LEVEL`] (or the whole grid, if smaller) that
    /// hold cells of columns `cols` and rows `rows`, m.
    fn blocks_over(&self, cols: (usize, usize), rows: (usize, usize)) -> f64 {
        let height = self.bounds.height();
        if height < START_LEVEL {
            // A grid smaller than a block: its root (or its single cell) bounds it all.
            return if height == 0 { self.max_thickness } else { self.bounds.node(height, 0, 0) };
        }
        let mut top = 0.0_f64;
        for r in rows.0 >> START_LEVEL..=rows.1 >> START_LEVEL {
            for c in cols.0 >> START_LEVEL..=cols.1 >> START_LEVEL {
                top = top.max(self.bounds.node(START_LEVEL, c, r));
            }
        }
        top
    }

    /// Where the segment `p0 → p1` first enters the layer on the receiving side of the bare
    /// surface that `chart` unrolls this field onto. The layer is the surface raised by each
    /// cell's thickness; a segment that starts inside it enters only after leaving it. `None`
    /// if it does not enter before reaching the bare surface.
    #[inline]
    pub fn layer_contact(&self, chart: &impl Chart, p0: DVec3, p1: DVec3) -> Option<LayerContact> {
        let h0 = chart.local(p0).2;
        let h1 = chart.local(p1).2;
        // Most paths pass well above the thickest cell or behind the surface: that answer is
        // inlined, the search is not.
        if self.max_thickness <= 0.0 || h0 <= 0.0 || h0.min(h1) - chart.sag(p0, p1) > self.max_thickness {
            return None;
        }
        self.layer_contact_near(chart, (p0, p1), (h0, h1), true)
    }

    /// [`HeightField::layer_contact`] for a path that reaches below the thickest cell, with
    /// `h0` and `h1` its heights above the surface at its ends, m; `skip` lets the march pass
    /// over runs of samples above the layer (the answer is the same either way).
    #[inline(never)]
    fn layer_contact_near(
        &self,
        chart: &impl Chart,
        (p0, p1): (DVec3, DVec3),
        (h0, h1): (f64, f64),
        skip: bool,
    ) -> Option<LayerContact> {
        let sag = chart.sag(p0, p1);
        let (cols, rows) = self.segment_cells(chart, p0, p1);
        if h0.min(h1) - sag > self.bounds.max_in(&self.thickness, cols, rows) {
            return None;
        }
        // The thickest layer under the segment, from the blocks of 16 × 16 cells its footprint
        // covers: where the march starts (a tighter bound would move its samples).
        let top = self.blocks_over(cols, rows);
        // The part of the segment within the slab between the surface and (just above) the
        // thickest cell, so that a segment from above starts outside the layer even over its
        // peak. On a curved surface the chord may dip by `sag` between its ends: the whole
        // segment is searched then.
        let roof = top * (1.0 + 1e-9);
        let s_start = if h0 > roof && sag == 0.0 { (h0 - roof) / (h0 - h1) } else { 0.0 };
        // A chord inside a curved surface lies above the straight line between its ends' heights
        // (its sag is zero), so it reaches the slab no sooner than that line does, but may reach
        // the surface later: its search runs on to its end.
        let curved = chart.uniform_normal().is_none();
        let s_end = if h1 < 0.0 && !curved { h0 / (h0 - h1) } else { 1.0 };
        // The column over the point at fraction `s`, if it lies over the surface.
        let column = |s: f64| -> Option<(u32, f64)> {
            let (u, v, h) = chart.local(p0.lerp(p1, s));
            chart.covers(u, v).then(|| (self.cell_at(u, v), h))
        };
        // The cell whose layer holds the point at fraction `s`, if any, and whether the point
        // lies in front of the surface. On a flat surface every point does (the slab already ends
        // at the surface); a curved one's search runs on, and a point behind it is not in the
        // layer.
        let probe = |s: f64| -> (Option<u32>, bool) {
            let (u, v, h) = chart.local(p0.lerp(p1, s));
            let in_front = !(curved && h < 0.0);
            let held = chart.covers(u, v).then(|| self.cell_at(u, v));
            (held.filter(|&cell| in_front && self.holds(cell, h)), in_front)
        };
        let inside = |s: f64| probe(s).0;
        // March at half a cell along the surface.
        let (dx, dy) = self.cell_size();
        let span = chart.along(p0, p1) * (s_end - s_start);
        let n = ((span / (0.5 * dx.min(dy))).ceil() as usize).clamp(1, 1 << 16);
        // Skipping relies on steps of at most half a cell, which the clamp of `n` could break.
        let fine = span <= n as f64 * 0.5 * dx.min(dy) && sag == 0.0;
        let sample = |k: usize| s_start + (s_end - s_start) * k as f64 / n as f64;
        let height = |s: f64| chart.local(p0.lerp(p1, s)).2;
        let (held, mut was_in_front) = probe(s_start);
        let mut was_inside = held.is_some();
        let mut prev = s_start;
        let mut k = 1;
        let mut level = SKIP_LEVEL.min(self.bounds.height());
        while k <= n {
            let s = sample(k);
            // Skip a run of samples above the layer of the pyramid's nodes around this one: all
            // would test outside. A run of `2ᵏ⁺¹ − 1` samples half a cell apart stays within the
            // 3 × 3 nodes of level `k` around its first, and on a flat face its ends bound it.
            let run = ((2usize << level) - 1).min(n - k);
            if skip && fine && !was_inside && level >= SKIP_FLOOR && run >= 4 {
                let bound = self.max_around(chart, p0.lerp(p1, s), level) + SKIP_MARGIN;
                if height(s) > bound && height(sample(k + run)) > bound {
                    prev = sample(k + run);
                    was_in_front = true;
                    k += run + 1;
                    level = (level + 1).min(self.bounds.height());
                    continue;
                }
                level -= 1;
            }
            let (held, in_front) = probe(s);
            let mut now = held.is_some();
            let mut s = s;
            if !now && !was_inside && was_in_front && !in_front {
                // A curved surface's search passes behind it between two samples: a path steep
                // to the surface may have crossed the layer there, between samples half a cell
                // apart along it. The layer, if any, holds the last point in front.
                let (front, _) = bisect(prev, s, |m| height(m) < 0.0);
                if inside(front).is_some() {
                    (s, now) = (front, true);
                }
            }
            if now && !was_inside {
                let (a, b) = self.entry(chart, (p0, p1), (prev, s), |m| inside(m).is_some());
                // `b` stays inside throughout the bisection.
                let entered = inside(b)?;
                // Through the side of a taller column, the material settles in the column the
                // particle came down (as in ballistic deposition); stacking it on the taller one
                // would let every column that gets ahead catch its neighbours' flux and grow
                // into a needle.
                let cell = column(a).map_or(entered, |(c, _)| c);
                return Some(self.contact(chart, p0.lerp(p1, b), b, entered, cell));
            }
            was_inside = now;
            was_in_front = in_front;
            prev = s;
            k += 1;
        }
        None
    }

    /// Narrows `[a, b]` of the path `p0 → p1`, `a` outside the layer and `b` inside (as
    /// `inside` says), to an entry (see [`bisect`]): by [`HeightField::entry_flat`] on a flat
    /// surface, else (or where that fails) by bisecting with `inside` itself.
    fn entry(
        &self,
        chart: &impl Chart,
        path: (DVec3, DVec3),
        (a, b): (f64, f64),
        inside: impl Fn(f64) -> bool,
    ) -> (f64, f64) {
        self.entry_flat(chart, path, (a, b), &inside).unwrap_or_else(|| bisect(a, b, inside))
    }

    /// [`HeightField::entry`] on a flat surface, where the in-face coordinates and the height
    /// are affine along the path: the halvings interpolate them instead of mapping each point
    /// into the chart. The ends found are checked with `inside`; `None` where rounding makes
    /// the two disagree there, or the surface is curved. Where `[a, b]` holds several entries
    /// (past a hole, into a neighbouring column) the two bisections may settle on different
    /// ones: the contact is then another true entry within the same half cell.
    fn entry_flat(
        &self,
        chart: &impl Chart,
        (p0, p1): (DVec3, DVec3),
        (a, b): (f64, f64),
        inside: impl Fn(f64) -> bool,
    ) -> Option<(f64, f64)> {
        chart.uniform_normal()?;
        let (l0, l1) = (DVec3::from(chart.local(p0)), DVec3::from(chart.local(p1)));
        let d = l1 - l0;
        // The cell over the point at fraction `m`, if the surface covers it, and the point's
        // height above the bare surface.
        let column = |m: f64| {
            let l = l0 + d * m;
            (chart.covers(l.x, l.y).then(|| self.cell_at(l.x, l.y)), l.z)
        };
        let (mut a, mut b) = (a, b);
        let (mut over_a, mut over_b) = (column(a).0, column(b).0);
        for halving in 0..BISECTIONS {
            // Each interpolated in-face coordinate is monotone along the path, and so is the
            // column (or row) it falls in; the points the surface covers form one stretch of
            // it. Once both ends lie over one covered cell, so does every point between them,
            // and only the height is left to compare.
            if let (Some(ca), Some(cb)) = (over_a, over_b)
                && ca == cb
            {
                let (solid, top) = (!self.is_hole(ca), self.thickness[ca as usize]);
                for _ in halving..BISECTIONS {
                    let m = 0.5 * (a + b);
                    let held = solid & ((l0.z + d.z * m) <= top);
                    (a, b) = if held { (a, m) } else { (m, b) };
                }
                break;
            }
            let m = 0.5 * (a + b);
            let (cell, h) = column(m);
            if cell.is_some_and(|c| self.holds(c, h)) {
                (b, over_b) = (m, cell);
            } else {
                (a, over_a) = (m, cell);
            }
        }
        (!inside(a) && inside(b)).then_some((a, b))
    }

    /// The contact at `point` (fraction `s` of the path), entering cell `entered` and settling
    /// in `cell`: its normal is the layer's, from the thickness gradient.
    fn contact(&self, chart: &impl Chart, point: DVec3, s: f64, entered: u32, cell: u32) -> LayerContact {
        let (gu, gv) = self.gradient(entered);
        let (u, v, _) = chart.local(point);
        let (n, right, up) = chart.frame(u, v);
        let normal = (n - right * gu - up * gv).normalize();
        LayerContact { s, point, normal, cell }
    }
}

/// Halvings that narrow a path's entry into the layer.
const BISECTIONS: usize = 32;

/// Narrows `[a, b]`, with `a` outside and `b` inside, to the entry by [`BISECTIONS`] halvings;
/// returns the last outside and inside fractions.
fn bisect(mut a: f64, mut b: f64, inside: impl Fn(f64) -> bool) -> (f64, f64) {
    for _ in 0..BISECTIONS {
        let m = 0.5 * (a + b);
        if inside(m) {
            b = m;
        } else {
            a = m;
        }
    }
    (a, b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::Face;
    use crate::deposit::testing::uniform;

    /// Whether the point at fraction `s` of the path `p0 → p1` lies in `f`'s layer on `face`,
    /// each point mapped into the chart as the march maps it.
    fn inside_of(f: &HeightField, face: Face, p0: DVec3, p1: DVec3) -> impl Fn(f64) -> bool + '_ {
        move |s: f64| {
            let (u, v, h) = Chart::local(&face, p0.lerp(p1, s));
            let cell = f.cell_at(u, v);
            Chart::covers(&face, u, v) && f.holds(cell, h)
        }
    }
    /// The pyramid lets the march skip runs of samples; skipping must find the very contact
    /// the full march finds, on a rough layer, for steep and grazing paths alike.
    #[test]
    fn skipping_over_the_pyramid_finds_the_same_contact_as_the_full_march() {
        let face = Face::new(DVec3::ZERO, DVec3::Z, DVec3::Y, [1.0, 1.0]);
        let mut f = HeightField::new(1.0, 1.0, 300, 200, 0.004);
        let mut next = uniform(7);
        // Sparse tall spikes over a thin film: most of the path lies just above the film.
        for _ in 0..3000 {
            let cell = (next() * 60_000.0) as u32;
            f.deposit(cell, 2e-9 * next());
        }
        for _ in 0..40 {
            let cell = (next() * 60_000.0) as u32;
            f.deposit(cell, 2e-7 * next());
        }
        let (mut met, top) = (0, f.max_thickness());
        for _ in 0..4000 {
            let p0 = DVec3::new(next() - 0.5, next() - 0.5, top * (0.5 + 2.0 * next()));
            let p1 = DVec3::new(next() - 0.5, next() - 0.5, top * (1.5 * next() - 0.3));
            let (h0, h1) = (p0.z, p1.z);
            if h0 <= 0.0 {
                continue;
            }
            let fast = f.layer_contact_near(&face, (p0, p1), (h0, h1), true);
            assert_eq!(fast, f.layer_contact_near(&face, (p0, p1), (h0, h1), false), "{p0} → {p1}");
            met += usize::from(fast.is_some());
        }
        assert!(met > 100, "only {met} contacts");
    }

    /// On a flat face the entry into the layer is narrowed over interpolated coordinates: on a
    /// rough layer with holes, it must be accepted by the path's own test (outside before,
    /// inside after) nearly always, and then agree with the plain bisection nearly always
    /// (where a half cell holds several entries the two may settle on different ones).
    #[test]
    fn the_entry_on_a_flat_face_is_the_bisection_of_the_path_itself() {
        let face = Face::new(DVec3::ZERO, DVec3::Z, DVec3::Y, [1.0, 1.0]);
        let mut f = HeightField::new(1.0, 1.0, 200, 100, 0.0);
        f.set_holes((0..20_000).map(|c| c % 13 == 5).collect());
        let mut next = uniform(11);
        for c in 0..20_000 {
            f.add(c, 1e-3 * (0.2 + next()));
        }
        let (mut tried, mut accepted, mut same) = (0, 0, 0);
        while tried < 3000 {
            let p0 = DVec3::new(next() - 0.5, next() - 0.5, 2e-3 + 1e-2 * next());
            let p1 = DVec3::new(next() - 0.5, next() - 0.5, 1e-4);
            let inside = inside_of(&f, face, p0, p1);
            if inside(0.0) || !inside(1.0) {
                continue;
            }
            tried += 1;
            let Some((a, b)) = f.entry_flat(&face, (p0, p1), (0.0, 1.0), &inside) else { continue };
            accepted += 1;
            assert!(!inside(a) && inside(b) && b - a < 1e-9, "{p0} → {p1}: {a} {b}");
            same += usize::from((a, b) == bisect(0.0, 1.0, &inside));
        }
        assert!(accepted > 2950, "only {accepted} of {tried} interpolated entries accepted");
        assert!(same > 2900, "only {same} of {tried} entries as the plain bisection finds them");
    }

    /// Once both ends of the bracket lie over one cell, the flat narrowing compares heights
    /// only: it must return, to the bit, what halving with every midpoint mapped to its cell
    /// returns, over long and short brackets, across holes, edges and cell borders.
    #[test]
    fn narrowing_within_one_cell_finds_the_bracket_of_the_full_bisection() {
        let face = Face::new(DVec3::ZERO, DVec3::Z, DVec3::Y, [1.0, 1.0]);
        let mut f = HeightField::new(1.0, 1.0, 50, 40, 0.0);
        f.set_holes((0..2000).map(|c| c % 7 == 3).collect());
        let mut next = uniform(5);
        for c in 0..2000 {
            f.add(c, 1e-2 * (0.2 + next()));
        }
        let (mut compared, mut found) = (0, 0);
        for k in 0..20_000 {
            // Paths over the face and past its edges, steep and grazing.
            let p0 = DVec3::new(1.2 * (next() - 0.5), 1.2 * (next() - 0.5), 2e-2 * next());
            let p1 = p0 + DVec3::new(0.1 * (next() - 0.5), 0.1 * (next() - 0.5), -2e-2 * next());
            let inside = inside_of(&f, face, p0, p1);
            let (l0, l1) = (DVec3::from(Chart::local(&face, p0)), DVec3::from(Chart::local(&face, p1)));
            let mapped = |m: f64| {
                let l = l0 + (l1 - l0) * m;
                Chart::covers(&face, l.x, l.y) && f.holds(f.cell_at(l.x, l.y), l.z)
            };
            // Whole paths, and brackets of a fiftieth of one (a cell or so).
            let (a, b) = if k % 2 == 0 {
                (0.0, 1.0)
            } else {
                let a = 0.98 * next();
                (a, a + 0.02)
            };
            let (ea, eb) = bisect(a, b, mapped);
            // The bracket itself, before the path's own test accepts it (which hides any
            // difference over a hole: neither end is inside there).
            if ea != eb {
                let raw = f.entry_flat(&face, (p0, p1), (a, b), |s| s == eb);
                assert_eq!(raw, Some((ea, eb)), "{p0} → {p1} over [{a}, {b}]");
            }
            let plain = (!inside(ea) && inside(eb)).then_some((ea, eb));
            assert_eq!(f.entry_flat(&face, (p0, p1), (a, b), inside), plain, "{p0} → {p1} over [{a}, {b}]");
            compared += 1;
            found += usize::from(plain.is_some());
        }
        assert!(found > compared / 20, "only {found} entries in {compared} brackets");
    }
}
