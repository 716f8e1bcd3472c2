//! `[air]`: the gun's air that carries droplets (a free jet turned along the surface it strikes;
//! see the engine's `motion::air` for the model).

use crate::reader::{Check, Read, Section, bad, choices};
use serde::Serialize;

/// How drag depends on a droplet's Reynolds number.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DragLawName {
    /// Stokes drag at every Reynolds number.
    Stokes,
    /// Stokes drag times 1 + 0.15 Re^0.687 (Schiller & Naumann 1933).
    SchillerNaumann,
}

choices!(DragLawName { "schiller_naumann" => DragLawName::SchillerNaumann, "stokes" => DragLawName::Stokes });

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum AirKind {
    None,
    Jet,
}

choices!(AirKind { "none" => AirKind::None, "jet" => AirKind::Jet });

/// `[air]`: the gun's air, or none (still air: the paper's droplets, drag only from
/// `process.drag`).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "model", rename_all = "snake_case")]
pub enum AirParams {
    /// Still air.
    None,
    /// A free jet from the nozzle and a stagnation flow over the surface it strikes.
    Jet(JetParams),
}

/// The jet's parameters and the air's properties.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct JetParams {
    /// Air speed at the outlet U₀, m/s.
    pub speed: f64,
    /// Effective outlet diameter d₀ (the diameter of a round outlet with the gun's air flow at
    /// U₀), m.
    pub outlet_diameter: f64,
    /// Growth of the jet's half-width per metre from the nozzle, `[along the width axis, along
    /// the height axis]`, dimensionless (0.094 for a round jet).
    pub spread: [f64; 2],
    /// Thickness of the stagnation layer over a struck surface, as a share of the distance
    /// from the nozzle to it, dimensionless (0.14: Beltaos & Rajaratnam 1974).
    pub stagnation_layer: f64,
    /// Dynamic viscosity of the air, Pa·s.
    pub viscosity: f64,
    /// Density of the air, kg/m³.
    pub density: f64,
    /// Drag law: `schiller_naumann` or `stokes`.
    pub drag: DragLawName,
    /// A droplet slower than this where the air is too has left the jet, and the booth's
    /// ventilation carries it off as overspray, m/s (0: never).
    pub booth_speed: f64,
}

/// Every `[air]` key, to fill what a file leaves out.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct AirDefaults {
    pub model: AirKind,
    pub jet: JetParams,
}

impl AirDefaults {
    /// Still air, with the jet keys of a generic air gun should a file switch the jet on.
    pub fn still() -> AirDefaults {
        AirDefaults { model: AirKind::None, jet: JetParams::AIR_20C }
    }
}

impl JetParams {
    /// A conventional air gun's jet in air at 20 °C and 1 atm (μ = 1.81 × 10⁻⁵ Pa·s, ρ = 1.20
    /// kg/m³); the guns' own values are in the scenario crate's `guns` module.
    pub(crate) const AIR_20C: JetParams = JetParams {
        speed: 100.0,
        outlet_diameter: 0.005,
        spread: [0.094, 0.094],
        stagnation_layer: 0.14,
        viscosity: 1.81e-5,
        density: 1.20,
        drag: DragLawName::SchillerNaumann,
        booth_speed: 0.3,
    };
}

/// Reads `[air]` over `d`.
pub(crate) fn read(s: &Section<'_>, d: &AirDefaults) -> Read<AirParams> {
    let model = s.choice("model", Some(d.model))?;
    let p = match model {
        AirKind::None => AirParams::None,
        AirKind::Jet => {
            let j = &d.jet;
            let spread = s.numbers("spread", Some(j.spread), Check::Within(0.0, 2.0), "")?;
            if spread.iter().any(|&x| x <= 0.0) {
                return bad(&s.key("spread"), format!("must be positive on both axes, got {spread:?}"));
            }
            AirParams::Jet(JetParams {
                speed: s.number("speed", Some(j.speed), Check::Within(0.0, 1000.0), "m/s")?,
                outlet_diameter: s.number(
                    "outlet_diameter",
                    Some(j.outlet_diameter),
                    Check::Positive(1.0),
                    "m",
                )?,
                spread,
                stagnation_layer: s.number(
                    "stagnation_layer",
                    Some(j.stagnation_layer),
                    Check::Within(0.0, 1.0),
                    "",
                )?,
                viscosity: s.number("viscosity", Some(j.viscosity), Check::Positive(1.0), "Pa·s")?,
                density: s.number("density", Some(j.density), Check::Positive(100.0), "kg/m³")?,
                drag: s.choice("drag", Some(j.drag))?,
                booth_speed: s.number("booth_speed", Some(j.booth_speed), Check::Within(0.0, 2.0), "m/s")?,
            })
        }
    };
    s.finish(&format!("[air] with model = \"{}\"", crate::reader::Choice::name(model)))?;
    Ok(p)
}
