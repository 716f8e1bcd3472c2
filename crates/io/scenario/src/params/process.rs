//! `[process]`: the material and what happens on impact, with `[process.impact]`,
//! `[process.slump]`, `[process.cohesion]`, `[process.erosion]` and `[process.window]`.

use super::rebound::{ReboundKind, ReboundParams};
use crate::reader::{Check, Read, Section, choices};
use serde::Serialize;

/// The three process presets of the paper's Table 1.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Preset {
    /// Wet-mix sprayed concrete.
    #[default]
    Shotcrete,
    /// Air spray painting.
    Painting,
    /// Abrasive (sand) blasting.
    Blasting,
}

choices!(Preset { "shotcrete" => Preset::Shotcrete, "painting" => Preset::Painting, "blasting" => Preset::Blasting });

impl Preset {
    /// All presets, in documentation order.
    pub const ALL: [Preset; 3] = [Preset::Shotcrete, Preset::Painting, Preset::Blasting];

    /// The name used in scenario files.
    pub fn name(self) -> &'static str {
        match self {
            Preset::Shotcrete => "shotcrete",
            Preset::Painting => "painting",
            Preset::Blasting => "blasting",
        }
    }
}

/// `[process]`: the material, what happens on impact and what happens to the layers, from a
/// preset's defaults.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ProcessParams {
    /// The preset that supplied the defaults.
    pub preset: Preset,
    /// The paint gun whose spray, droplets, air and window override the painting preset's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gun: Option<crate::guns::Gun>,
    /// Share of the paint's volume that stays in the dry film (its solids by volume, from the
    /// data sheet), 0–1: the dry film is the wet one times it. `None`: only the wet film.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub volume_solids: Option<f64>,
    /// Material density, kg/m³.
    pub density: f64,
    /// Volume flow rate of material through the nozzle while spraying, m³/s.
    pub flow_rate: f64,
    /// Quadratic drag coefficient k in a = −k |v| v, 1/m. 0 = ballistic.
    pub drag: f64,
    /// A particle still in flight after this long is retired as expired, s.
    pub max_lifetime: f64,
    /// A cell counts as covered when its thickness reaches this, m.
    pub coverage_threshold: f64,
    /// Wet-film thickness above which a film sags on a vertical surface, m; 0 switches sag
    /// flagging off.
    pub sag_threshold: f64,
    /// Time between drip passes, s; 0 switches dripping off.
    pub drip_interval: f64,
    /// Impact parameters of every surface that does not override them.
    pub impact: ImpactParams,
    /// Slump of the fresh layer under its own weight.
    pub slump: SlumpParams,
    /// Cohesive failure of deposited layers.
    pub cohesion: CohesionParams,
    /// Erosion of targets by impacts.
    pub erosion: ErosionParams,
    /// Recommended working window of the nozzle, for the path-quality metrics.
    pub window: WindowParams,
}

/// `[process.impact]`, `[target.impact]`, `[obstacle.impact]`: what happens on impact.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ImpactParams {
    /// Anti-adhesion factor α in P(rebound) = α · p_r(θ), dimensionless, 0..1.
    pub alpha: f64,
    /// The rebound curve.
    #[serde(flatten)]
    pub rebound: ReboundParams,
    /// Rebound speed ÷ impact speed, 0..1.
    pub restitution: f64,
    /// Half-angle of the scatter cone about the specular direction, degrees, 0..90.
    pub scatter_angle: f64,
    /// A rebound slower than this comes to rest and sticks, m/s.
    pub rest_speed: f64,
    /// Steepest surface (angle of its normal from +z) on which a slow rebound can rest, degrees.
    pub rest_max_slope: f64,
    /// Radius over which the layer under an impact is averaged, m.
    pub cushion_radius: f64,
}

/// `[process.slump]`: a fresh yield-stress layer flowing where its weight shears it past its
/// yield stress (Nye's heap on a floor, τ_y/(ρ g) on a wall), and running off the edges.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SlumpParams {
    /// Time between relaxations, s; 0 switches slump off.
    pub interval: f64,
    /// Yield stress of the fresh layer, Pa.
    pub yield_stress: f64,
    /// Most relaxation sweeps per interval; what is left flows on at the next interval.
    pub max_sweeps: u32,
}

/// `[process.cohesion]`: cohesive failure of deposited layers.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CohesionParams {
    /// Time between failure analyses, s; 0 switches failure off.
    pub interval: f64,
    /// Adhesive tensile (pull-off) strength of the fresh layer on the substrate, Pa.
    pub tensile_strength: f64,
    /// Adhesive shear strength of the fresh layer on the substrate, Pa.
    pub shear_strength: f64,
    /// Cohesion holding an over-loaded region along its boundary, Pa.
    pub cohesion: f64,
}

/// Which erosion model applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ErosionKind {
    None,
    Finnie,
    Oka,
}

choices!(ErosionKind { "none" => ErosionKind::None, "finnie" => ErosionKind::Finnie, "oka" => ErosionKind::Oka });

/// `[process.erosion]`: material removed from targets by abrasive impacts. A target's coating
/// (`[[target]] coating`) and the substrate under it each have their own resistance
/// (`[process.erosion.coating]`, `[process.erosion.substrate]`).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "model", rename_all = "snake_case")]
pub enum ErosionParams {
    /// No erosion.
    None,
    /// Finnie (ductile targets): V = k m v² f(γ).
    Finnie {
        /// The coating's constant.
        coating: FinnieLayer,
        /// The substrate's constant.
        substrate: FinnieLayer,
    },
    /// Oka: V = g(γ) E90 m, with the angle function's exponents from the layer's hardness.
    Oka {
        /// Diameter of the abrasive grains, m.
        grain_diameter: f64,
        /// Oka's reference speed, m/s.
        oka_v_ref: f64,
        /// Oka's reference grain diameter, m.
        oka_d_ref: f64,
        /// Oka's grain-size exponent k₃.
        oka_k3: f64,
        /// The coating's hardness and E90.
        coating: OkaLayer,
        /// The substrate's hardness and E90.
        substrate: OkaLayer,
    },
}

/// Finnie's constant of one layer.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FinnieLayer {
    /// Finnie's constant k, m³/J.
    pub finnie_k: f64,
}

/// Oka's parameters of one layer.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct OkaLayer {
    /// Vickers hardness Hv, GPa: sets the angle function's exponents.
    pub hardness: f64,
    /// Volume removed per kg of grit at normal incidence, the reference speed and grain size,
    /// m³/kg.
    pub oka_e90: f64,
}

/// `[process.window]`: the recommended working window of the nozzle.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WindowParams {
    /// `[min, max]` standoff along the spray axis, m.
    pub standoff: [f64; 2],
    /// Largest angle between the spray axis and the surface's normal, degrees.
    pub max_angle: f64,
    /// `[min, max]` travel speed, m/s.
    pub speed: [f64; 2],
}

/// Every `[process]` key of a preset, whatever the models chosen, to fill what a file leaves out.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ProcessDefaults {
    pub density: f64,
    pub flow_rate: f64,
    pub drag: f64,
    pub max_lifetime: f64,
    pub coverage_threshold: f64,
    pub impact: ImpactDefaults,
    pub slump: SlumpParams,
    pub cohesion: CohesionParams,
    pub erosion: ErosionDefaults,
    pub window: WindowParams,
    pub sag_threshold: f64,
    pub drip_interval: f64,
}

/// The defaults of an impact table.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ImpactDefaults {
    pub alpha: f64,
    pub rebound_model: ReboundKind,
    /// A rebound law whose keys stand in for that law's own defaults: the process's law, for a
    /// surface's table; `None` (a preset's): every law's own.
    pub rebound: Option<ReboundParams>,
    pub restitution: f64,
    pub scatter_angle: f64,
    pub rest_speed: f64,
    pub rest_max_slope: f64,
    pub cushion_radius: f64,
}

impl ImpactDefaults {
    /// The resolved `impact` as defaults for a surface's override (a rebound law other than
    /// `impact`'s takes its own defaults).
    pub fn over(impact: &ImpactParams) -> ImpactDefaults {
        ImpactDefaults {
            alpha: impact.alpha,
            rebound_model: impact.rebound.kind(),
            rebound: Some(impact.rebound.clone()),
            restitution: impact.restitution,
            scatter_angle: impact.scatter_angle,
            rest_speed: impact.rest_speed,
            rest_max_slope: impact.rest_max_slope,
            cushion_radius: impact.cushion_radius,
        }
    }
}

/// Every erosion key, whatever the model.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ErosionDefaults {
    pub model: ErosionKind,
    pub grain_diameter: f64,
    pub oka_v_ref: f64,
    pub oka_d_ref: f64,
    pub oka_k3: f64,
    pub coating: LayerDefaults,
    pub substrate: LayerDefaults,
}

/// Every erosion key of one layer, whatever the model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct LayerDefaults {
    pub hardness: f64,
    pub oka_e90: f64,
    pub finnie_k: f64,
}

/// Reads `[process]` over the defaults (`defaults` of its preset) of the preset it names.
pub(crate) fn read(s: &Section<'_>, defaults: impl Fn(Preset) -> ProcessDefaults) -> Read<ProcessParams> {
    let preset = s.choice("preset", Some(Preset::Shotcrete))?;
    let gun = if s.has("gun") { Some(s.choice::<crate::guns::Gun>("gun", None)?) } else { None };
    if gun.is_some() && preset != Preset::Painting {
        return crate::reader::bad(&s.key("gun"), "is a paint gun: it needs process.preset = \"painting\"");
    }
    let d = &match gun {
        Some(gun) => gun.process(defaults(preset)),
        None => defaults(preset),
    };
    let volume_solids = if s.has("volume_solids") {
        let v = s.number("volume_solids", None, Check::Positive(1.0), "")?;
        Some(v)
    } else {
        None
    };
    let p = ProcessParams {
        preset,
        gun,
        volume_solids,
        density: s.number("density", Some(d.density), Check::Positive(25_000.0), "kg/m³")?,
        flow_rate: s.number("flow_rate", Some(d.flow_rate), Check::Positive(10.0), "m³/s")?,
        drag: s.number("drag", Some(d.drag), Check::Within(0.0, 1e3), "1/m")?,
        max_lifetime: s.number("max_lifetime", Some(d.max_lifetime), Check::Positive(1e6), "s")?,
        coverage_threshold: s.number(
            "coverage_threshold",
            Some(d.coverage_threshold),
            Check::Within(0.0, 10.0),
            "m",
        )?,
        sag_threshold: s.number("sag_threshold", Some(d.sag_threshold), Check::Within(0.0, 1.0), "m")?,
        drip_interval: s.number("drip_interval", Some(d.drip_interval), Check::Within(0.0, 1e6), "s")?,
        impact: read_impact(&s.table_or_empty("impact")?, &d.impact)?,
        slump: read_slump(&s.table_or_empty("slump")?, &d.slump)?,
        cohesion: read_cohesion(&s.table_or_empty("cohesion")?, &d.cohesion)?,
        erosion: read_erosion(&s.table_or_empty("erosion")?, d)?,
        window: read_window(&s.table_or_empty("window")?, &d.window)?,
    };
    s.finish("[process]")?;
    Ok(p)
}

/// Reads an impact table over `d`: the process's own, or a surface's override of the process's.
pub(crate) fn read_impact(s: &Section<'_>, d: &ImpactDefaults) -> Read<ImpactParams> {
    let kind = s.choice("rebound_model", Some(d.rebound_model))?;
    let rebound = ReboundParams::read(kind, s, d.rebound.as_ref())?;
    let p = ImpactParams {
        alpha: s.number("alpha", Some(d.alpha), Check::Within(0.0, 1.0), "")?,
        rebound,
        restitution: s.number("restitution", Some(d.restitution), Check::Within(0.0, 1.0), "")?,
        scatter_angle: s.number(
            "scatter_angle",
            Some(d.scatter_angle),
            Check::Within(0.0, 90.0),
            "degrees",
        )?,
        rest_speed: s.number("rest_speed", Some(d.rest_speed), Check::Within(0.0, 1e3), "m/s")?,
        rest_max_slope: s.number(
            "rest_max_slope",
            Some(d.rest_max_slope),
            Check::Within(0.0, 180.0),
            "degrees",
        )?,
        cushion_radius: s.number("cushion_radius", Some(d.cushion_radius), Check::Within(0.0, 1.0), "m")?,
    };
    s.finish(&format!("an impact table with rebound_model = \"{}\"", crate::reader::Choice::name(kind)))?;
    Ok(p)
}

fn read_slump(s: &Section<'_>, d: &SlumpParams) -> Read<SlumpParams> {
    let p = SlumpParams {
        interval: s.number("interval", Some(d.interval), Check::Within(0.0, 1e6), "s")?,
        yield_stress: s.number("yield_stress", Some(d.yield_stress), Check::Positive(1e9), "Pa")?,
        max_sweeps: s.integer("max_sweeps", Some(i64::from(d.max_sweeps)), 1, 1_000_000)? as u32,
    };
    s.finish("[process.slump]")?;
    Ok(p)
}

fn read_cohesion(s: &Section<'_>, d: &CohesionParams) -> Read<CohesionParams> {
    let c = CohesionParams {
        interval: s.number("interval", Some(d.interval), Check::Within(0.0, 1e6), "s")?,
        tensile_strength: s.number(
            "tensile_strength",
            Some(d.tensile_strength),
            Check::Positive(1e9),
            "Pa",
        )?,
        shear_strength: s.number("shear_strength", Some(d.shear_strength), Check::Positive(1e9), "Pa")?,
        cohesion: s.number("cohesion", Some(d.cohesion), Check::Within(0.0, 1e9), "Pa")?,
    };
    s.finish("[process.cohesion]")?;
    Ok(c)
}

fn read_erosion(s: &Section<'_>, d: &ProcessDefaults) -> Read<ErosionParams> {
    let e = &d.erosion;
    let kind = s.choice("model", Some(e.model))?;
    let (coat, sub) = (s.table_or_empty("coating")?, s.table_or_empty("substrate")?);
    let finnie = |l: &Section<'_>, d: &LayerDefaults| -> Read<FinnieLayer> {
        let k = l.number("finnie_k", Some(d.finnie_k), Check::Within(0.0, 1.0), "m³/J")?;
        l.finish("a Finnie layer")?;
        Ok(FinnieLayer { finnie_k: k })
    };
    let oka = |l: &Section<'_>, d: &LayerDefaults| -> Read<OkaLayer> {
        let layer = OkaLayer {
            hardness: l.number("hardness", Some(d.hardness), Check::Positive(100.0), "GPa")?,
            oka_e90: l.number("oka_e90", Some(d.oka_e90), Check::Within(0.0, 1.0), "m³/kg")?,
        };
        l.finish("an Oka layer")?;
        Ok(layer)
    };
    let p = match kind {
        ErosionKind::None => ErosionParams::None,
        ErosionKind::Finnie => ErosionParams::Finnie {
            coating: finnie(&coat, &e.coating)?,
            substrate: finnie(&sub, &e.substrate)?,
        },
        ErosionKind::Oka => ErosionParams::Oka {
            grain_diameter: s.number("grain_diameter", Some(e.grain_diameter), Check::Positive(1.0), "m")?,
            oka_v_ref: s.number("oka_v_ref", Some(e.oka_v_ref), Check::Positive(1e4), "m/s")?,
            oka_d_ref: s.number("oka_d_ref", Some(e.oka_d_ref), Check::Positive(1.0), "m")?,
            oka_k3: s.number("oka_k3", Some(e.oka_k3), Check::Within(0.0, 10.0), "")?,
            coating: oka(&coat, &e.coating)?,
            substrate: oka(&sub, &e.substrate)?,
        },
    };
    if kind == ErosionKind::None {
        // Layers of an erosion that is off: refused like any key that does nothing.
        coat.finish("[process.erosion] with model = \"none\"")?;
        sub.finish("[process.erosion] with model = \"none\"")?;
    }
    s.finish(&format!("[process.erosion] with model = \"{}\"", crate::reader::Choice::name(kind)))?;
    Ok(p)
}

fn read_window(s: &Section<'_>, d: &WindowParams) -> Read<WindowParams> {
    let pair = |k: &str, v: [f64; 2]| -> Read<[f64; 2]> {
        let p = s.numbers(k, Some(v), Check::Within(0.0, 1e3), "")?;
        if p[0] > p[1] {
            return crate::reader::bad(&s.key(k), format!("must be [min, max] with min ≤ max, got {p:?}"));
        }
        Ok(p)
    };
    let w = WindowParams {
        standoff: pair("standoff", d.standoff)?,
        max_angle: s.number("max_angle", Some(d.max_angle), Check::Within(0.0, 90.0), "degrees")?,
        speed: pair("speed", d.speed)?,
    };
    s.finish("[process.window]")?;
    Ok(w)
}
