//! Process presets: the defaults of the paper's Table 1, plus material density and flow rate.
//!
//! Where Table 1 gives a range, the default sits inside it; the comment beside each number says
//! where it comes from. Every value can be overridden in a scenario.

use crate::params::{
    ApertureKind, CohesionParams, DirectionKind, EmitterDefaults, ErosionDefaults, ErosionKind,
    ImpactDefaults, Preset, ProcessDefaults, ReboundKind, WindowParams,
};

/// Default p_r(θ) coefficients in x = θ/90°: p_r = 0.10 + 2.4 x³. Passes through the public
/// reference points: 10 % at normal incidence (ASA: 5–15 %, about 10 % on average), 12.6 % at
/// 20° (vendors: 5–12 % with the nozzle square to the surface), 40 % at 45° (vendors: 30–50 %
/// once the nozzle is more than 20° off square), and saturates at 1 beyond about 62°.
pub const SHOTCRETE_REBOUND_POLYNOMIAL: [f64; 4] = [0.10, 0.0, 0.0, 2.4];

/// Failure switched off; strengths kept at the shotcrete values so that switching it on by
/// `interval` alone gives sensible numbers.
const COHESION_OFF: CohesionParams =
    CohesionParams { interval: 0.0, tensile_strength: 1500.0, shear_strength: 5000.0, cohesion: 2000.0 };

/// Erosion constants: Oka's exponents for sand on steel (physics-notes.md); Finnie's k and Oka's
/// E90 from blasting productivity, about 10⁻⁵ m³ of coating removed per kg of grit at the best
/// angle (10–20 m²/h of a 0.2 mm coat at 5–10 kg/min): to be calibrated for the coating at hand.
const EROSION: ErosionDefaults = ErosionDefaults {
    model: ErosionKind::None,
    finnie_k: 1.5e-9,
    oka_e90: 1e-5,
    oka_n1: 0.71,
    oka_n2: 2.4,
    oka_hv: 1.6,
    oka_k2: 2.35,
    oka_k3: 0.19,
    oka_v_ref: 104.0,
    oka_d_ref: 326e-6,
    grain_diameter: 0.5e-3,
};

impl Preset {
    /// The `[process]` defaults of this preset.
    #[allow(clippy::too_many_lines, reason = "a data table: one entry per preset")]
    pub(crate) fn defaults(self) -> ProcessDefaults {
        match self {
            Preset::Shotcrete => ProcessDefaults {
                density: 2300.0,          // fresh wet-mix concrete, kg/m³
                flow_rate: 1.5e-3,        // 5.4 m³/h, a typical wet-mix nozzle output (4–10 m³/h)
                drag: 0.0,                // the paper's ballistic configuration
                max_lifetime: 5.0,        // s; long enough to fall to the floor from a few metres
                coverage_threshold: 1e-3, // 1 mm of shotcrete counts as covered
                impact: ImpactDefaults {
                    alpha: 1.0, // Table 1: the angle curve governs rebound
                    rebound_model: ReboundKind::Polynomial,
                    rebound_polynomial: SHOTCRETE_REBOUND_POLYNOMIAL.to_vec(),
                    restitution: 0.04,    // Table 1: 0.03–0.05
                    scatter_angle: 5.0,   // Table 1: "small angular noise"
                    rest_speed: 0.5,      // m/s; slower rebounds stay put
                    rest_max_slope: 90.0, // wet mix holds on any face that is not an overhang
                    cushion_factor: 1.0,  // the cushion effect (ACI 506) is off by default
                    cushion_thickness: 0.0,
                },
                // Fresh wet-mix shotcrete builds about 50–100 mm overhead and 200–300 mm on a
                // wall in one pass: ρ g t at those thicknesses sets the adhesive strengths.
                cohesion: CohesionParams {
                    interval: 0.5,
                    tensile_strength: 1500.0, // Pa: fails overhead beyond ρ g t ≈ 66 mm
                    shear_strength: 5000.0,   // Pa: slides off a wall beyond ≈ 222 mm
                    cohesion: 2000.0,         // Pa: yield stress of a fresh wet mix
                },
                erosion: ErosionDefaults { model: ErosionKind::None, ..EROSION },
                window: WindowParams { standoff: [1.0, 2.0], max_angle: 20.0, speed: [0.0, 1.0] }, // ASA: 1–2 m, square on; rebound rises beyond 20°
                sag_threshold: 0.0,
                drip_interval: 0.0,
            },
            Preset::Painting => ProcessDefaults {
                density: 1200.0, // waterborne paint, kg/m³
                flow_rate: 5e-6, // 300 mL/min, an air spray gun
                drag: 0.0,
                max_lifetime: 2.0,
                coverage_threshold: 20e-6, // a 20 µm wet film counts as covered
                impact: ImpactDefaults {
                    alpha: 0.0, // Table 1: rebound suppressed, every impact adheres
                    rebound_model: ReboundKind::Polynomial,
                    rebound_polynomial: SHOTCRETE_REBOUND_POLYNOMIAL.to_vec(),
                    restitution: 0.0,   // Table 1: N/A
                    scatter_angle: 0.0, // Table 1: negligible
                    rest_speed: 0.0,
                    rest_max_slope: 45.0,
                    cushion_factor: 1.0, // the cushion effect (ACI 506) is off by default
                    cushion_thickness: 0.0,
                },
                // Table 1: no cohesive failure (sagging is a separate model).
                cohesion: CohesionParams { interval: 0.0, ..COHESION_OFF },
                erosion: ErosionDefaults { model: ErosionKind::None, ..EROSION },
                window: WindowParams { standoff: [0.15, 0.3], max_angle: 15.0, speed: [0.2, 1.0] }, // air spray guns: 15–30 cm, near square
                sag_threshold: 120e-6, // a wet film of about 120 µm starts to sag on a vertical panel,
                drip_interval: 0.0,
            },
            Preset::Blasting => ProcessDefaults {
                density: 3950.0,   // fused alumina grit, kg/m³
                flow_rate: 2.5e-5, // about 6 kg/min of grit
                drag: 0.0,
                max_lifetime: 3.0,
                coverage_threshold: 0.0, // nothing deposits; coverage is read from hits
                impact: ImpactDefaults {
                    alpha: 1.0,
                    rebound_model: ReboundKind::Always, // Table 1: forced rebound, p_r ≡ 1
                    rebound_polynomial: SHOTCRETE_REBOUND_POLYNOMIAL.to_vec(),
                    restitution: 0.75,   // Table 1: 0.6–0.9
                    scatter_angle: 20.0, // Table 1: moderate–large
                    rest_speed: 0.5,     // grains come to rest on the floor
                    rest_max_slope: 45.0,
                    cushion_factor: 1.0, // the cushion effect (ACI 506) is off by default
                    cushion_thickness: 0.0,
                },
                // Table 1: no cohesive failure.
                cohesion: CohesionParams { interval: 0.0, ..COHESION_OFF },
                erosion: ErosionDefaults { model: ErosionKind::Finnie, ..EROSION },
                window: WindowParams { standoff: [0.3, 0.9], max_angle: 45.0, speed: [0.0, 1.0] }, // 30–90 cm, 45–90° to the surface
                sag_threshold: 0.0,
                drip_interval: 0.0,
            },
        }
    }

    /// The `[emitter]` defaults of this preset.
    pub(crate) fn emitter_defaults(self) -> EmitterDefaults {
        let base = EmitterDefaults {
            shape: ApertureKind::Circle,
            diameter: 0.05,
            width: 0.02,
            height: 0.002,
            inner_diameter: 0.03,
            outer_diameter: 0.05,
            spawn_rate: 1e4,
            speed: [20.0, 30.0],
            cone_angle: 14.0,
            direction: DirectionKind::TruncatedNormal,
            mu: 0.255,
            sigma: 0.102,
            fan_wide_angle: 60.0,
            fan_narrow_angle: 10.0,
        };
        match self {
            // Table 1: circular, 10⁴ /s, 20–30 m/s (wet-mix), 32–76 mm, 9–18°; μ and σ are the
            // paper's fit to Ginouse & Jolin's wet-mix profiles.
            Preset::Shotcrete => base,
            // Table 1: point emitter, 10⁴–10⁵ /s, 20–60 m/s, 0.5–2 mm, 15–120°. A centred
            // truncated normal gives the Gaussian-like footprint of path-planning models.
            Preset::Painting => EmitterDefaults {
                shape: ApertureKind::Point,
                diameter: 0.001,
                spawn_rate: 5e4,
                speed: [20.0, 40.0],
                cone_angle: 40.0,
                mu: 0.0,
                sigma: 0.5,
                ..base
            },
            // Table 1: circular, 10³–10⁵ /s, 100–200 m/s, 3.2–19.1 mm (9.5 mm = a No. 6
            // nozzle), 15°.
            Preset::Blasting => EmitterDefaults {
                diameter: 0.0095,
                spawn_rate: 1e4,
                speed: [100.0, 200.0],
                cone_angle: 15.0,
                direction: DirectionKind::UniformPolar,
                ..base
            },
        }
    }
}

/// Unit (or meaning) of each preset key, printed beside it by [`presets_toml`].
const UNITS: &[(&str, &str)] = &[
    ("density", "kg/m³"),
    ("flow_rate", "m³/s while spraying"),
    ("drag", "1/m, a = −k |v| v"),
    ("max_lifetime", "s"),
    ("coverage_threshold", "m"),
    ("alpha", "P(rebound) = α · p_r(θ), 0–1"),
    ("rebound_model", "polynomial | always | never"),
    ("rebound_polynomial", "p_r = Σ cᵢ (θ/90°)ⁱ, θ from the normal"),
    ("restitution", "rebound speed / impact speed"),
    ("scatter_angle", "degrees, half-angle about the specular direction"),
    ("rest_speed", "m/s"),
    ("rest_max_slope", "degrees from +z"),
    ("cushion_factor", "rebound multiplier on bare substrate, 1 = off"),
    ("cushion_thickness", "m, layer at which the multiplier reaches 1"),
    ("interval", "s between failure analyses, 0 = off"),
    ("sag_threshold", "m of wet film that sags on a vertical face, 0 = off"),
    ("drip_interval", "s between drip passes, 0 = off"),
    ("standoff", "m, [min, max] recommended"),
    ("max_angle", "degrees off square, recommended"),
    ("model", "erosion: none | finnie | oka"),
    ("finnie_k", "m³/J"),
    ("oka_e90", "m³/kg"),
    ("oka_hv", "GPa"),
    ("oka_v_ref", "m/s"),
    ("oka_d_ref", "m"),
    ("grain_diameter", "m"),
    ("tensile_strength", "Pa, adhesive pull-off strength"),
    ("shear_strength", "Pa, adhesive shear strength"),
    ("cohesion", "Pa, holds a region along its boundary"),
    ("shape", "point | circle | rectangle | annulus"),
    ("diameter", "m, circle"),
    ("width", "m, rectangle"),
    ("height", "m, rectangle"),
    ("inner_diameter", "m, annulus"),
    ("outer_diameter", "m, annulus"),
    ("spawn_rate", "particles/s"),
    ("speed", "m/s, [min, max]"),
    ("cone_angle", "degrees, full angle"),
    ("direction", "uniform_polar | truncated_normal | uniform_solid_angle | fan"),
    ("mu", "of θ/θ_half, truncated_normal"),
    ("sigma", "of θ/θ_half, truncated_normal"),
    ("fan_wide_angle", "degrees, fan"),
    ("fan_narrow_angle", "degrees, fan"),
];

/// Where a preset's value comes from, where it is worth saying.
fn source(preset: Preset, key: &str) -> Option<&'static str> {
    use Preset::*;
    Some(match (preset, key) {
        (Shotcrete, "density") => "fresh wet-mix concrete",
        (Shotcrete, "flow_rate") => "5.4 m³/h, a typical wet-mix nozzle (4–10 m³/h)",
        (Shotcrete, "alpha") => "Table 1: angle-based",
        (Shotcrete, "rebound_polynomial") => "10 % at 0°, 40 % at 45° (ASA, vendors)",
        (Shotcrete, "restitution") => "Table 1: 0.03–0.05",
        (Shotcrete, "scatter_angle") => "Table 1: small",
        (Shotcrete, "spawn_rate") => "Table 1: 10⁴",
        (Shotcrete, "speed") => "Table 1: 20–30 (wet-mix)",
        (Shotcrete, "diameter") => "Table 1: 32–76 mm",
        (Shotcrete, "cone_angle") => "Table 1: 9–18",
        (Shotcrete, "mu" | "sigma") => "paper: fit to Ginouse & Jolin's wet-mix profiles",
        (Painting, "density") => "waterborne paint",
        (Painting, "flow_rate") => "300 mL/min, an air spray gun",
        (Painting, "alpha") => "Table 1: rebound suppressed",
        (Painting, "spawn_rate") => "Table 1: 10⁴–10⁵",
        (Painting, "speed") => "Table 1: 20–60",
        (Painting, "diameter") => "Table 1: 0.5–2 mm",
        (Painting, "cone_angle") => "Table 1: 15–120",
        (Painting, "shape") => "Table 1: point / rectangular / annulus",
        (Blasting, "density") => "fused alumina grit",
        (Blasting, "flow_rate") => "about 6 kg/min of grit",
        (Blasting, "rebound_model") => "Table 1: forced rebound, p_r ≡ 1",
        (Blasting, "restitution") => "Table 1: 0.6–0.9",
        (Blasting, "scatter_angle") => "Table 1: moderate–large",
        (Blasting, "spawn_rate") => "Table 1: 10³–10⁵",
        (Blasting, "speed") => "Table 1: 100–200",
        (Blasting, "diameter") => "Table 1: 3.2–19.1 mm (No. 6 nozzle)",
        (Blasting, "cone_angle") => "Table 1: 15",
        _ => return None,
    })
}

/// Every preset's `[process]`, `[process.impact]` and `[emitter]` as TOML, each value commented
/// with its unit and, where known, its source; any one block pastes into a scenario.
pub fn presets_toml() -> String {
    #[derive(serde::Serialize)]
    struct Sections {
        process: crate::params::ProcessParams,
        emitter: crate::params::EmitterParams,
    }
    let mut out =
        String::from("# Process presets (the paper's Table 1). Paste one block into a scenario and edit.\n");
    for preset in Preset::ALL {
        let sections = Sections { process: preset.resolved_process(), emitter: preset.resolved_emitter() };
        let text = toml::to_string(&sections).unwrap_or_else(|e| panic!("presets always serialise: {e}"));
        out.push_str(&format!("\n# ---- {} ----\n", preset.name()));
        for line in text.lines() {
            let key = line.split(" = ").next().unwrap_or_default();
            let unit = UNITS.iter().find(|(k, _)| *k == key).map(|(_, u)| *u);
            match (unit, source(preset, key)) {
                (Some(u), Some(s)) => out.push_str(&format!("{line:<46} # {u}; {s}\n")),
                (Some(u), None) => out.push_str(&format!("{line:<46} # {u}\n")),
                _ => out.push_str(&format!("{line}\n")),
            }
        }
    }
    out
}

impl Preset {
    /// This preset's `[process]` as a scenario with no `[process]` keys but the preset's name
    /// resolves it.
    pub fn resolved_process(self) -> crate::params::ProcessParams {
        let table = toml::Table::from_iter([("preset".to_string(), toml::Value::String(self.name().into()))]);
        crate::params::read::process(&crate::reader::Section::root(&table), Preset::defaults)
            .unwrap_or_else(|e| panic!("the {} preset is invalid: {e}", self.name()))
    }

    /// This preset's `[emitter]`, resolved the same way.
    pub fn resolved_emitter(self) -> crate::params::EmitterParams {
        crate::params::read::emitter(&crate::reader::Section::empty("emitter"), &self.emitter_defaults(), 1.0)
            .unwrap_or_else(|e| panic!("the {} preset is invalid: {e}", self.name()))
    }
}
