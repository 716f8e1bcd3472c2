//! Cushion capture: wet-mix shotcrete rebounds as coarse aggregate that reaches a hard surface,
//! so rebound is highest on bare substrate and falls as a plastic cushion builds up (ACI 506R;
//! Armelin & Banthia 1998, "Mechanics of aggregate rebound in shotcrete").

use super::{PolynomialRebound, ReboundLaw};
use crate::process::ImpactSite;

/// Each particle is mortar (which always sticks) or an aggregate grain whose diameter follows
/// the mix's grading; what it is is fixed by its [`ImpactSite::material`] draw, the same at
/// every impact. A grain landing on a plastic layer thinner than `capture_ratio` × its diameter
/// reaches the hard substrate through it and bounces; a grain caught by a thicker cushion
/// rebounds only by ricochet at oblique incidence, following `ricochet` (the aggregate's share
/// of the field curve's rise with the angle of incidence). A grain that has rebounded before
/// lands slowly (at the restitution's share of its speed, plus what gravity adds): it sinks into
/// a cushion at least `trap_ratio` × its diameter deep and stays, trapped in the layer (on a
/// floor, rebound falls back onto the fresh layer; ACI 506R counts it as a defect, not a loss).
///
/// Averaged over the grading, the probability that the material rebounds is
/// `f · [S(h/κ) + (1 − S(h/κ)) · min(1, r(θ)/f)]` with `f` the aggregate fraction, `S(d)` the
/// share of the aggregate coarser than `d`, `h` the layer and `κ` the capture ratio: 65 % on
/// bare substrate for the default mix, nothing at normal incidence beyond a cushion of κ times
/// the largest grain.
#[derive(Clone, Debug, PartialEq)]
pub struct CushionCapture {
    /// Volume share of aggregate grains in the mix, 0..1 (the rest is mortar).
    pub aggregate_fraction: f64,
    /// The grading: `(diameter in m, share of the aggregate volume finer than it)`, both
    /// increasing; the first share 0, the last 1.
    pub grading: Vec<(f64, f64)>,
    /// A grain bounces off a plastic layer thinner than this many times its diameter.
    pub capture_ratio: f64,
    /// A grain that has rebounded before stays in a plastic layer at least this many times its
    /// diameter deep.
    pub trap_ratio: f64,
    /// Ricochet probability of a captured grain's material share, `r(θ)` (θ from the normal).
    pub ricochet: PolynomialRebound,
}

impl CushionCapture {
    /// The grain diameter (m) at share `q` (0..1) of the aggregate volume, interpolated
    /// log-linearly between the grading's sieves.
    pub fn diameter(&self, q: f64) -> f64 {
        let g = &self.grading;
        let k = g.partition_point(|&(_, share)| share <= q).clamp(1, g.len().saturating_sub(1).max(1));
        let ((d0, s0), (d1, s1)) = (g[k - 1], g[k.min(g.len() - 1)]);
        if s1 <= s0 {
            return d1;
        }
        let f = ((q - s0) / (s1 - s0)).clamp(0.0, 1.0);
        (d0.ln() + f * (d1.ln() - d0.ln())).exp()
    }

    /// What the particle with material draw `m` (0..1) is: `None` for mortar, else the grain's
    /// diameter, m.
    pub fn grain(&self, m: f64) -> Option<f64> {
        let f = self.aggregate_fraction;
        let q = (m - (1.0 - f)) / f;
        (f > 0.0 && q >= 0.0).then(|| self.diameter(q.min(1.0)))
    }
}

impl ReboundLaw for CushionCapture {
    fn probability(&self, impact: &ImpactSite) -> f64 {
        let Some(d) = self.grain(impact.material) else { return 0.0 };
        let layer = impact.layer.unwrap_or(0.0);
        if impact.bounced && layer >= self.trap_ratio * d && impact.layer.is_some() {
            return 0.0;
        }
        if layer < self.capture_ratio * d {
            return 1.0;
        }
        (self.ricochet.at(impact.theta) / self.aggregate_fraction).clamp(0.0, 1.0)
    }

    fn form(&self) -> super::ReboundForm<'_> {
        super::ReboundForm::Cushion(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::process::ImpactModel;
    use glam::DVec3;

    /// The shotcrete preset's mix: ACI 506R gradation No. 2, mid-band.
    fn mix() -> CushionCapture {
        let grading = [
            (0.075e-3, 0.0),
            (0.15e-3, 0.06),
            (0.3e-3, 0.14),
            (0.6e-3, 0.275),
            (1.18e-3, 0.45),
            (2.36e-3, 0.60),
            (4.75e-3, 0.775),
            (9.5e-3, 0.95),
            (12.5e-3, 1.0),
        ];
        CushionCapture {
            aggregate_fraction: 0.65,
            grading: grading.to_vec(),
            capture_ratio: 4.0,
            trap_ratio: 0.5,
            ricochet: PolynomialRebound { coefficients: vec![0.0, 0.0, 0.0, 2.4] },
        }
    }

    /// The share of the mix that rebounds at `theta_deg` over `layer` m: the law averaged over
    /// the material draw by the midpoint rule.
    fn share(law: &CushionCapture, theta_deg: f64, layer: f64, bounced: bool) -> f64 {
        let n = 200_000;
        let v = DVec3::new(0.0, 0.0, -20.0);
        let normal = DVec3::new(theta_deg.to_radians().sin(), 0.0, theta_deg.to_radians().cos());
        (0..n)
            .map(|k| {
                let m = (k as f64 + 0.5) / n as f64;
                law.probability(&ImpactModel::site(v, normal, Some(layer), m, bounced))
            })
            .sum::<f64>()
            / n as f64
    }

    #[test]
    fn the_grading_is_interpolated_log_linearly_between_sieves() {
        let g = mix();
        assert!((g.diameter(0.0) - 0.075e-3).abs() < 1e-15);
        assert!((g.diameter(1.0) - 12.5e-3).abs() < 1e-15);
        assert!((g.diameter(0.45) - 1.18e-3).abs() < 1e-15);
        // Half way from 45 % to 60 % finer: the geometric mean of 1.18 and 2.36 mm.
        assert!((g.diameter(0.525) - (1.18e-3_f64 * 2.36e-3).sqrt()).abs() < 1e-15);
        // The first 35 % of draws are mortar; the rest map onto the grading in order.
        assert_eq!(g.grain(0.349), None);
        assert!((g.grain(0.35 + 0.65 * 0.45).expect("a grain") - 1.18e-3).abs() < 1e-12);
    }

    #[test]
    fn the_mix_bounces_off_bare_substrate_and_a_cushion_catches_it_grain_size_by_size() {
        let g = mix();
        // Bare: every grain bounces, mortar sticks.
        assert!((share(&g, 0.0, 0.0, false) - 0.65).abs() < 1e-4);
        // Over κ × 1.18 mm the grains finer than 1.18 mm (45 % of the aggregate) are caught.
        assert!((share(&g, 0.0, 4.0 * 1.18e-3 + 1e-12, false) - 0.65 * 0.55).abs() < 1e-4);
        // Past κ times the largest grain nothing bounces at normal incidence.
        assert_eq!(share(&g, 0.0, 4.0 * 12.5e-3, false), 0.0);
        // On a full cushion at 45°, the mix rebounds with the ricochet curve: 2.4 × 0.5³.
        assert!((share(&g, 45.0, 0.1, false) - 0.3).abs() < 1e-4);
        // Off deposits (no layer at all) it behaves as on bare substrate.
        let v = DVec3::new(0.0, 0.0, -20.0);
        let grain = ImpactModel::site(v, DVec3::Z, None, 0.99, false);
        assert_eq!(g.probability(&grain), 1.0);
    }

    #[test]
    fn a_rebound_landing_on_a_deep_enough_cushion_is_trapped() {
        let g = mix();
        // The largest grain (draw near 1): trapped in 6.25 mm or more, bounces off less.
        let v = DVec3::new(0.0, 0.0, -1.0);
        let at = |layer: f64| g.probability(&ImpactModel::site(v, DVec3::Z, Some(layer), 0.999_999, true));
        assert_eq!(at(0.5 * 12.5e-3), 0.0);
        assert_eq!(at(0.9 * 0.5 * 12.5e-3), 1.0);
        // Rebounds landing on bare substrate or obstacles are never trapped.
        assert_eq!(g.probability(&ImpactModel::site(v, DVec3::Z, None, 0.999_999, true)), 1.0);
        assert!((share(&g, 0.0, 0.0, true) - 0.65).abs() < 1e-4);
    }
}
