//! Deposition and impact statistics against closed forms (physics-notes, "Analytic checks").
//! The experiments live in `spraysim_validate::checks`; `spraysim validate` runs them ten
//! times larger.

use spraysim_validate::checks::{cone_law, restitution};
use spraysim_validate::chi2_limit;

#[test]
fn a_cone_onto_a_plane_follows_the_cos3_law_in_shape_and_volume() {
    let c = cone_law("uniform_solid_angle", 3e5, 0);
    // Everything lands: the absolute volume is the emitted volume.
    assert_eq!(c.stuck, c.emitted);
    assert!((c.volumes.1 - c.volumes.0).abs() <= 1e-12 * c.volumes.0, "{:?}", c.volumes);
    let dof = c.radii.len();
    assert!(dof >= 10, "only {dof} annuli");
    // χ² with `dof` degrees of freedom: mean dof, sd √(2 dof); 5 sd is a false alarm about
    // once in 10⁵ runs.
    let limit = chi2_limit(dof);
    eprintln!("cone χ² = {:.1} over {dof} annuli", c.chi2);
    assert!(c.chi2 < limit, "χ² = {} over {dof} annuli (limit {limit})", c.chi2);
    // Uniform in polar angle concentrates at the axis: the same test rejects it.
    let wrong = cone_law("uniform_polar", 3e5, 0);
    assert!(wrong.chi2 > 10.0 * limit, "uniform_polar passed the cos³ law: χ² = {}", wrong.chi2);
}

#[test]
fn scatter_angles_are_uniform_over_the_scatter_cone() {
    let half = 30f64.to_radians();
    let r = restitution(0.5, half, 100_000);
    assert!(r.scatter_chi2 < chi2_limit(19), "χ² = {} (19 degrees of freedom)", r.scatter_chi2);
    assert!((r.speed_ratio - 0.5).abs() < 1e-9, "mean rebound speed ratio {}", r.speed_ratio);
    assert!(r.max_scatter <= half + 1e-12 && r.max_scatter > 29f64.to_radians(), "{}", r.max_scatter);
}
