//! What the particles of a layer epoch leave on a target before it takes effect.
//!
//! During an epoch every particle sees the layers as they stood at its start, so what lands
//! cannot change them yet: each cell gathers, in atomic counters that any number of threads add
//! to in any order, the volume deposited on it (in quanta of the run's volume quantum), the
//! impacts it took and, under an erosion law, the volumes of coating and substrate the impacts
//! would wear away (in [`WEAR_QUANTUM`]s). Integer sums do not depend on the order of their
//! terms, so the epoch's effect, applied at its end ([`Pending::settle`]), is the same to the
//! bit for any number of threads. A cell is listed once, by the first contribution that marks
//! it, so the work at the end is proportional to the cells touched, not to the surface.

use crate::checkpoint::{Dec, Enc, StateError};
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, Ordering};

/// The unit of worn volume gathered during an epoch, m³ (2⁻⁹⁰, about 8·10⁻²⁸ m³): a single
/// impact's wear is a tiny volume (a coat of 0.1 mm wears off a 2 mm cell over thousands of
/// impacts), rounded to this it keeps 7 significant figures down to 10⁻²⁰ m³, and a cell can
/// gather 10⁻⁸ m³ of wear in one epoch before its counter fills.
pub const WEAR_QUANTUM: f64 = 1.0 / (1u128 << 90) as f64;

/// The counters of one target for the epoch under way.
#[derive(Debug, Default)]
pub struct Pending {
    /// Volume deposited per cell, quanta of the run's volume quantum.
    quanta: Vec<AtomicU64>,
    /// Impacts per cell.
    hits: Vec<AtomicU32>,
    /// Coating and substrate wear per cell, [`WEAR_QUANTUM`]s (empty without an erosion law).
    wear: Vec<[AtomicU64; 2]>,
    /// Whether the cell has been listed as touched in this epoch.
    marked: Vec<AtomicBool>,
}

/// What one cell gathered during an epoch.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Gathered {
    /// Volume deposited, quanta of the run's volume quantum.
    pub quanta: u64,
    /// Impacts centred on the cell in the epoch under way.
    pub hits: u32,
    /// Coating and substrate wear, [`WEAR_QUANTUM`]s.
    pub wear: [u64; 2],
}

impl Clone for Pending {
    fn clone(&self) -> Pending {
        let copy64 = |v: &[AtomicU64]| v.iter().map(|a| AtomicU64::new(a.load(Ordering::Relaxed))).collect();
        Pending {
            quanta: copy64(&self.quanta),
            hits: self.hits.iter().map(|a| AtomicU32::new(a.load(Ordering::Relaxed))).collect(),
            wear: self
                .wear
                .iter()
                .map(|[a, b]| {
                    [AtomicU64::new(a.load(Ordering::Relaxed)), AtomicU64::new(b.load(Ordering::Relaxed))]
                })
                .collect(),
            marked: self.marked.iter().map(|a| AtomicBool::new(a.load(Ordering::Relaxed))).collect(),
        }
    }
}

impl Pending {
    /// Counters for `cells` cells, with wear counters when `wears`.
    pub fn new(cells: usize, wears: bool) -> Pending {
        Pending {
            quanta: (0..cells).map(|_| AtomicU64::new(0)).collect(),
            hits: (0..cells).map(|_| AtomicU32::new(0)).collect(),
            wear: if wears {
                (0..cells).map(|_| [AtomicU64::new(0), AtomicU64::new(0)]).collect()
            } else {
                Vec::new()
            },
            marked: (0..cells).map(|_| AtomicBool::new(false)).collect(),
        }
    }

    /// Lists `cell` in `touched` the first time anything lands on it in this epoch.
    #[inline]
    fn mark(&self, cell: u32, touched: &mut Vec<u32>) {
        if !self.marked[cell as usize].swap(true, Ordering::Relaxed) {
            touched.push(cell);
        }
    }

    /// Adds `quanta` of deposit to `cell`.
    #[inline]
    pub fn deposit(&self, cell: u32, quanta: u64, touched: &mut Vec<u32>) {
        if quanta > 0 {
            self.quanta[cell as usize].fetch_add(quanta, Ordering::Relaxed);
            self.mark(cell, touched);
        }
    }

    /// Counts one impact on `cell`, with the volumes of coating and substrate it would wear
    /// away (m³; ignored without wear counters).
    #[inline]
    pub fn impact(&self, cell: u32, wear: (f64, f64), touched: &mut Vec<u32>) {
        self.hits[cell as usize].fetch_add(1, Ordering::Relaxed);
        if let Some([coat, sub]) = self.wear.get(cell as usize) {
            coat.fetch_add(wear_quanta(wear.0), Ordering::Relaxed);
            sub.fetch_add(wear_quanta(wear.1), Ordering::Relaxed);
        }
        self.mark(cell, touched);
    }

    /// Counts `n` impacts on `cell` without wear (as a flight stage that gathered them books
    /// them).
    #[inline]
    pub fn impacts(&self, cell: u32, n: u32, touched: &mut Vec<u32>) {
        if n > 0 {
            self.hits[cell as usize].fetch_add(n, Ordering::Relaxed);
            self.mark(cell, touched);
        }
    }

    /// Adds wear of coating and substrate, [`WEAR_QUANTUM`]s, to `cell` (as a flight stage that
    /// gathered it books it; ignored without wear counters).
    #[inline]
    pub fn wear(&self, cell: u32, wear: [u64; 2], touched: &mut Vec<u32>) {
        if let Some(counters) = self.wear.get(cell as usize)
            && wear != [0, 0]
        {
            for (c, w) in counters.iter().zip(wear) {
                c.fetch_add(w, Ordering::Relaxed);
            }
            self.mark(cell, touched);
        }
    }

    /// Takes what `cell` gathered, leaving its counters at zero.
    pub fn take(&self, cell: u32) -> Gathered {
        let c = cell as usize;
        self.marked[c].store(false, Ordering::Relaxed);
        Gathered {
            quanta: self.quanta[c].swap(0, Ordering::Relaxed),
            hits: self.hits[c].swap(0, Ordering::Relaxed),
            wear: self
                .wear
                .get(c)
                .map_or([0, 0], |[a, b]| [a.swap(0, Ordering::Relaxed), b.swap(0, Ordering::Relaxed)]),
        }
    }

    /// What `cell` has gathered so far, leaving it as it is.
    pub fn peek(&self, cell: u32) -> Gathered {
        let c = cell as usize;
        Gathered {
            quanta: self.quanta[c].load(Ordering::Relaxed),
            hits: self.hits[c].load(Ordering::Relaxed),
            wear: self
                .wear
                .get(c)
                .map_or([0, 0], |[a, b]| [a.load(Ordering::Relaxed), b.load(Ordering::Relaxed)]),
        }
    }

    /// Writes the cells listed in this epoch with what they gathered, for a checkpoint.
    pub(crate) fn save_state(&self, e: &mut Enc) {
        let listed: Vec<u32> = (0..self.marked.len() as u32)
            .filter(|&c| self.marked[c as usize].load(Ordering::Relaxed))
            .collect();
        e.list(&listed, |e, &c| {
            let g = self.peek(c);
            e.u32(c);
            e.u64(g.quanta);
            e.u32(g.hits);
            e.u64(g.wear[0]);
            e.u64(g.wear[1]);
        });
    }

    /// Reads what [`Pending::save_state`] wrote, over counters at zero.
    pub(crate) fn load_state(&mut self, d: &mut Dec<'_>) -> Result<(), StateError> {
        let cells = self.marked.len();
        *self = Pending::new(cells, !self.wear.is_empty());
        let n = d.len(28)?;
        for _ in 0..n {
            let c = d.u32()? as usize;
            let g = Gathered { quanta: d.u64()?, hits: d.u32()?, wear: [d.u64()?, d.u64()?] };
            if c >= cells {
                return Err(StateError::Mismatch(format!("a deposit under way in cell {c} of {cells}")));
            }
            self.quanta[c] = AtomicU64::new(g.quanta);
            self.hits[c] = AtomicU32::new(g.hits);
            if let Some(w) = self.wear.get_mut(c) {
                *w = [AtomicU64::new(g.wear[0]), AtomicU64::new(g.wear[1])];
            }
            self.marked[c] = AtomicBool::new(true);
        }
        Ok(())
    }
}

/// `volume` (m³) of wear in [`WEAR_QUANTUM`]s, rounded to the nearest; negative, non-finite or
/// vanishing volumes count as none.
#[inline]
pub fn wear_quanta(volume: f64) -> u64 {
    let q = volume / WEAR_QUANTUM;
    if q.is_finite() && q > 0.0 { q.round() as u64 } else { 0 }
}

/// Share `k` (from 0) of `quanta` split over `n` cells (at least one) as evenly as whole quanta
/// allow: each takes `quanta / n`, and the first (the cell a deposit centres on) also the
/// remainder, so the shares add up to `quanta` exactly and where the remainder goes does not
/// depend on how a surface orders the cells around its centre.
#[inline]
pub fn share(quanta: u64, n: u64, k: u64) -> u64 {
    let n = n.max(1);
    quanta / n + if k == 0 { quanta % n } else { 0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_add_up_exactly_and_only_the_centre_takes_the_remainder() {
        for (q, n) in [(0, 3), (7, 3), (1 << 24, 29), (u64::MAX, 7), (5, 9)] {
            let parts: Vec<u64> = (0..n).map(|k| share(q, n, k)).collect();
            assert_eq!(parts.iter().map(|&p| u128::from(p)).sum::<u128>(), u128::from(q));
            // Every cell but the centre takes the same share; the centre takes less than one
            // quantum more per cell.
            assert!(parts[1..].iter().all(|&p| p == q / n), "{q} over {n}: {parts:?}");
            assert!(parts[0] - q / n < n, "{q} over {n}: {parts:?}");
        }
    }

    #[test]
    fn contributions_in_any_order_from_any_thread_gather_the_same_sums() {
        let order = |reversed: bool, threads: usize| {
            let p = Pending::new(16, true);
            let mut touched = Vec::new();
            std::thread::scope(|s| {
                let handles: Vec<_> = (0..threads)
                    .map(|t| {
                        let p = &p;
                        s.spawn(move || {
                            let mut mine = Vec::new();
                            let mut work: Vec<u32> =
                                (0..200u32).filter(|k| k % threads as u32 == t as u32).collect();
                            if reversed {
                                work.reverse();
                            }
                            for k in work {
                                p.deposit(k % 16, u64::from(k) * 1000 + 7, &mut mine);
                                p.impact(k % 16, (1e-20 * f64::from(k), 3e-21), &mut mine);
                            }
                            mine
                        })
                    })
                    .collect();
                for h in handles {
                    touched.extend(h.join().unwrap_or_default());
                }
            });
            touched.sort_unstable();
            assert_eq!(touched, (0..16).collect::<Vec<u32>>(), "each cell listed once");
            (0..16).map(|c| p.take(c)).collect::<Vec<_>>()
        };
        let reference = order(false, 1);
        assert_eq!(order(true, 3), reference);
        assert_eq!(order(false, 4), reference);
        assert!(reference.iter().all(|g| g.hits > 0 && g.quanta > 0 && g.wear[0] > 0));
    }
}
