//! Dripping: on tilted surfaces, wet film beyond the sag limit runs off and falls.

use super::{LayerContext, LayerStage, Release};
use crate::deposit::DepositSurface;

/// Every interval, film beyond the sag limit (`threshold / sin β`, β the surface's tilt from
/// horizontal) runs off and falls as released particles, one per cell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DripStage {
    /// Wet-film thickness that sags on a vertical surface, m.
    pub threshold: f64,
}

impl LayerStage for DripStage {
    fn name(&self) -> &'static str {
        "drip"
    }

    fn run(&self, ctx: &mut LayerContext<'_>) {
        for t in ctx.targets.iter_mut() {
            for cell in 0..t.surface.thickness().len() as u32 {
                let Some(limit) = t.sag_limit(cell, self.threshold) else { continue };
                let excess = t.surface.thickness()[cell as usize] - limit;
                if excess > 0.0 {
                    let area = t.surface.cell_area(cell);
                    ctx.release.release(t, cell, excess * area, Release::Drip);
                }
            }
        }
    }
}
