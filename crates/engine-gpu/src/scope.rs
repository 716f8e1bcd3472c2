//! What the GPU backend runs: a configuration outside its scope is refused before the run, with
//! an error naming the feature, so that no run silently loses a part of the physics.

use spraysim_engine::SimulationConfig;
use spraysim_engine::collision::Shape;
use spraysim_engine::deposit::Surface;
use spraysim_engine::process::{ErosionForm, ImpactModel, ReboundForm};

/// Most coefficients of a polynomial rebound law (and of the cushion law's ricochet curve).
pub const MAX_COEFFICIENTS: usize = 8;
/// Most sieves of the cushion law's grading curve.
pub const MAX_SIEVES: usize = 16;
/// Most cells of a deposit footprint: the kernel shares a deposit over them in 16-bit steps.
pub const MAX_FOOTPRINT: usize = (1 << 16) - 1;
/// Most impacts a particle may resolve within one step.
pub const MAX_IMPACTS_PER_STEP: u32 = 64;

/// A feature of the configuration the GPU backend does not run.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("the GPU backend does not run {feature} (`{key}`); use the CPU backend")]
pub struct Unsupported {
    /// The feature, in words.
    pub feature: String,
    /// The scenario key or the part of the configuration that asks for it.
    pub key: String,
}

fn refuse(feature: impl Into<String>, key: impl Into<String>) -> Result<(), Unsupported> {
    Err(Unsupported { feature: feature.into(), key: key.into() })
}

/// Checks that the GPU backend runs everything `config` asks for: rectangle and cylinder-shell
/// targets (with openings, under Finnie's or Oka's erosion law); plane, face, disk, sphere,
/// cylinder and box obstacles; the built-in rebound laws; any integrator; no gun's air and no
/// impact log.
pub fn check(config: &SimulationConfig) -> Result<(), Unsupported> {
    if config.motion.air.is_some() {
        return refuse("the gun's air (droplets in a jet)", "air.model");
    }
    if config.impact_log > 0.0 {
        return refuse("an impact log", "output.impact_log");
    }
    if config.max_impacts_per_step > MAX_IMPACTS_PER_STEP {
        return refuse(
            format!("more than {MAX_IMPACTS_PER_STEP} impacts per particle and step"),
            "simulation.max_impacts_per_step",
        );
    }
    for (i, t) in config.targets.iter().enumerate() {
        let key = format!("target[{i}] `{}`", t.name);
        let field = match &t.surface {
            Surface::Rectangle(r) => &r.field,
            Surface::Cylinder(c) => &c.field,
            Surface::Mesh(_) => return refuse("mesh targets", format!("{key}.mesh")),
        };
        if field.splat_offsets().len() > MAX_FOOTPRINT {
            return refuse(
                format!("a deposit footprint of more than {MAX_FOOTPRINT} cells"),
                format!("{key}.splat_radius"),
            );
        }
        if let Some(e) = &t.erosion {
            for (law, part) in [(&e.coating_law, "coating"), (&e.substrate_law, "substrate")] {
                if matches!(law.form(), ErosionForm::Opaque) {
                    return refuse(
                        format!("erosion laws defined outside the engine (the {part}'s)"),
                        format!("{key}.erosion"),
                    );
                }
            }
        }
        model(&t.impact, &key)?;
    }
    for (i, o) in config.obstacles.iter().enumerate() {
        let key = format!("obstacle[{i}] `{}`", o.name);
        for s in &o.shapes {
            match s {
                Shape::Plane(_)
                | Shape::Face(_)
                | Shape::Disk(_)
                | Shape::Sphere(_)
                | Shape::Cylinder(_)
                | Shape::Box(_) => {}
                Shape::Triangle(_) => return refuse("mesh obstacles", format!("{key}.mesh")),
                Shape::Shell(_) => return refuse("cylinder-shell obstacles", format!("{key}.shape")),
                Shape::Custom(_) => return refuse("shapes defined outside the engine", key),
            }
        }
        model(&o.impact, &key)?;
    }
    Ok(())
}

/// Checks an impact model's rebound law.
fn model(m: &ImpactModel, key: &str) -> Result<(), Unsupported> {
    match m.rebound.form() {
        ReboundForm::Always | ReboundForm::Never => Ok(()),
        ReboundForm::Polynomial(p) if p.coefficients.len() <= MAX_COEFFICIENTS => Ok(()),
        ReboundForm::Cushion(c)
            if c.ricochet.coefficients.len() <= MAX_COEFFICIENTS && c.grading.len() <= MAX_SIEVES =>
        {
            Ok(())
        }
        ReboundForm::Polynomial(_) | ReboundForm::Cushion(_) => refuse(
            format!(
                "rebound curves of more than {MAX_COEFFICIENTS} coefficients or gradings of more than {MAX_SIEVES} sieves"
            ),
            format!("{key}.rebound"),
        ),
        ReboundForm::Opaque => refuse("rebound laws defined outside the engine", format!("{key}.rebound")),
    }
}
