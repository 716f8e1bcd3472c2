//! Finnie's erosion of ductile targets.

use super::ErosionLaw;

/// Finnie's model for ductile targets: `V = k m v² f(γ)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Finnie {
    /// Finnie's constant k, m³/J.
    pub k: f64,
}

/// Finnie's angle function f(γ) for ductile targets, γ the impact angle from the surface (rad):
/// sin 2γ − 3 sin²γ up to tan γ = 1/3, cos²γ / 3 beyond; its peak lies near 17°, and it is zero
/// at 90°.
pub fn finnie_f(gamma: f64) -> f64 {
    if gamma.tan() <= 1.0 / 3.0 {
        (2.0 * gamma).sin() - 3.0 * gamma.sin().powi(2)
    } else {
        gamma.cos().powi(2) / 3.0
    }
}

impl ErosionLaw for Finnie {
    fn form(&self) -> super::ErosionForm<'_> {
        super::ErosionForm::Finnie(self)
    }

    fn removed_volume(&self, mass: f64, speed: f64, gamma: f64) -> f64 {
        self.k * mass * speed * speed * finnie_f(gamma).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finnie_peaks_near_17_degrees_and_vanishes_at_normal_incidence() {
        let (mut best, mut at) = (0.0, 0.0);
        for k in 0..=9000 {
            let g = (k as f64 / 100.0).to_radians();
            if finnie_f(g) > best {
                best = finnie_f(g);
                at = k as f64 / 100.0;
            }
        }
        assert!((at - 17.0).abs() < 1.0, "peak at {at}°");
        assert!(finnie_f(90f64.to_radians()).abs() < 1e-15);
        assert_eq!(finnie_f(0.0), 0.0);
        // Continuous where the two branches meet (tan γ = 1/3).
        let joint = (1.0f64 / 3.0).atan();
        assert!((finnie_f(joint - 1e-9) - finnie_f(joint + 1e-9)).abs() < 1e-6);
    }
}
