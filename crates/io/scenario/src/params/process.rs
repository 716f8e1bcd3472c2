//! `[process]`: the material and what happens on impact, with `[process.impact]`,
//! `[process.cohesion]`, `[process.erosion]` and `[process.window]`.

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

/// `[process]`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ProcessParams {
    /// The preset that supplied the defaults.
    pub preset: Preset,
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
    /// Cohesive failure of deposited layers.
    pub cohesion: CohesionParams,
    /// Erosion of targets by impacts.
    pub erosion: ErosionParams,
    /// Recommended working window of the nozzle, for the path-quality metrics.
    pub window: WindowParams,
}

/// Which rebound curve p_r(θ) applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ReboundKind {
    Polynomial,
    Always,
    Never,
}

choices!(ReboundKind {
    "polynomial" => ReboundKind::Polynomial,
    "always" => ReboundKind::Always,
    "never" => ReboundKind::Never,
});

/// The rebound curve p_r(θ), θ from the surface normal.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "rebound_model", rename_all = "snake_case")]
pub enum ReboundParams {
    /// p_r = Σ cᵢ xⁱ with x = θ/90°, clamped to [0, 1].
    Polynomial {
        /// Coefficients c₀, c₁, …, dimensionless.
        rebound_polynomial: Vec<f64>,
    },
    /// p_r ≡ 1 (forced rebound).
    Always,
    /// p_r ≡ 0.
    Never,
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
    /// Rebound probability multiplier on bare substrate (1: no cushion effect).
    pub cushion_factor: f64,
    /// Layer thickness at which the cushion multiplier has decayed to 1, m (0: off).
    pub cushion_thickness: f64,
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

/// `[process.erosion]`: material removed from targets by impacts.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "model", rename_all = "snake_case")]
pub enum ErosionParams {
    /// No erosion.
    None,
    /// Finnie (ductile targets): V = k m v² f(γ).
    Finnie {
        /// Finnie's constant k, m³/J.
        finnie_k: f64,
    },
    /// Oka: V = g(γ) E90 m.
    Oka {
        /// E90 at the reference speed and grain size, m³/kg.
        oka_e90: f64,
        /// Angle exponent n₁.
        oka_n1: f64,
        /// Angle exponent n₂.
        oka_n2: f64,
        /// Vickers hardness of the target, GPa.
        oka_hv: f64,
        /// Speed exponent k₂.
        oka_k2: f64,
        /// Grain-size exponent k₃.
        oka_k3: f64,
        /// Reference speed, m/s.
        oka_v_ref: f64,
        /// Reference grain diameter, m.
        oka_d_ref: f64,
        /// Diameter of the abrasive grains, m.
        grain_diameter: f64,
    },
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
    pub cohesion: CohesionParams,
    pub erosion: ErosionDefaults,
    pub window: WindowParams,
    pub sag_threshold: f64,
    pub drip_interval: f64,
}

/// Every impact key, whatever the rebound model.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ImpactDefaults {
    pub alpha: f64,
    pub rebound_model: ReboundKind,
    pub rebound_polynomial: Vec<f64>,
    pub restitution: f64,
    pub scatter_angle: f64,
    pub rest_speed: f64,
    pub rest_max_slope: f64,
    pub cushion_factor: f64,
    pub cushion_thickness: f64,
}

impl ImpactDefaults {
    /// The resolved `impact` as defaults for a surface's override; `polynomial` fills the
    /// coefficients when the override switches to the polynomial model.
    pub fn over(impact: &ImpactParams, polynomial: &[f64]) -> ImpactDefaults {
        let (rebound_model, rebound_polynomial) = match &impact.rebound {
            ReboundParams::Polynomial { rebound_polynomial } => {
                (ReboundKind::Polynomial, rebound_polynomial.clone())
            }
            ReboundParams::Always => (ReboundKind::Always, polynomial.to_vec()),
            ReboundParams::Never => (ReboundKind::Never, polynomial.to_vec()),
        };
        ImpactDefaults {
            alpha: impact.alpha,
            rebound_model,
            rebound_polynomial,
            restitution: impact.restitution,
            scatter_angle: impact.scatter_angle,
            rest_speed: impact.rest_speed,
            rest_max_slope: impact.rest_max_slope,
            cushion_factor: impact.cushion_factor,
            cushion_thickness: impact.cushion_thickness,
        }
    }
}

/// Every erosion key, whatever the model.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ErosionDefaults {
    pub model: ErosionKind,
    pub finnie_k: f64,
    pub oka_e90: f64,
    pub oka_n1: f64,
    pub oka_n2: f64,
    pub oka_hv: f64,
    pub oka_k2: f64,
    pub oka_k3: f64,
    pub oka_v_ref: f64,
    pub oka_d_ref: f64,
    pub grain_diameter: f64,
}

/// Reads `[process]` over the defaults (`defaults` of its preset) of the preset it names.
pub(crate) fn read(s: &Section<'_>, defaults: impl Fn(Preset) -> ProcessDefaults) -> Read<ProcessParams> {
    let preset = s.choice("preset", Some(Preset::Shotcrete))?;
    let d = &defaults(preset);
    let p = ProcessParams {
        preset,
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
    let rebound = match kind {
        ReboundKind::Polynomial => ReboundParams::Polynomial {
            rebound_polynomial: s.list(
                "rebound_polynomial",
                Some(d.rebound_polynomial.clone()),
                16,
                Check::Within(-1e6, 1e6),
            )?,
        },
        ReboundKind::Always => ReboundParams::Always,
        ReboundKind::Never => ReboundParams::Never,
    };
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
        cushion_factor: s.number("cushion_factor", Some(d.cushion_factor), Check::Within(0.0, 100.0), "")?,
        cushion_thickness: s.number(
            "cushion_thickness",
            Some(d.cushion_thickness),
            Check::Within(0.0, 10.0),
            "m",
        )?,
    };
    s.finish(&format!("an impact table with rebound_model = \"{}\"", crate::reader::Choice::name(kind)))?;
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
    let unit = |k: &str, v: f64, hi: f64| s.number(k, Some(v), Check::Within(0.0, hi), "");
    let p = match kind {
        ErosionKind::None => ErosionParams::None,
        ErosionKind::Finnie => ErosionParams::Finnie {
            finnie_k: s.number("finnie_k", Some(e.finnie_k), Check::Within(0.0, 1.0), "m³/J")?,
        },
        ErosionKind::Oka => ErosionParams::Oka {
            oka_e90: s.number("oka_e90", Some(e.oka_e90), Check::Within(0.0, 1.0), "m³/kg")?,
            oka_n1: unit("oka_n1", e.oka_n1, 10.0)?,
            oka_n2: unit("oka_n2", e.oka_n2, 10.0)?,
            oka_hv: s.number("oka_hv", Some(e.oka_hv), Check::Within(0.0, 100.0), "GPa")?,
            oka_k2: unit("oka_k2", e.oka_k2, 10.0)?,
            oka_k3: unit("oka_k3", e.oka_k3, 10.0)?,
            oka_v_ref: s.number("oka_v_ref", Some(e.oka_v_ref), Check::Positive(1e4), "m/s")?,
            oka_d_ref: s.number("oka_d_ref", Some(e.oka_d_ref), Check::Positive(1.0), "m")?,
            grain_diameter: s.number("grain_diameter", Some(e.grain_diameter), Check::Positive(1.0), "m")?,
        },
    };
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
