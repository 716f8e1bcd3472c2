//! Process presets: the defaults of the paper's Table 1, plus material density and flow rate.
//!
//! Where Table 1 gives a range, the default sits inside it; the comment beside each number says
//! where it comes from. Every value can be overridden in a scenario. A preset chooses a rebound
//! law; the law's own keys, with their defaults and sources, are declared with it, in
//! `params/rebound/`.

use crate::params::{
    ApertureKind, CohesionParams, DirectionKind, DropletsKind, EmitterDefaults, ErosionDefaults, ErosionKind,
    ImpactDefaults, LayerDefaults, Preset, ProcessDefaults, ReboundKind, SlumpParams, WindowParams,
};
use crate::reader::Choice;

/// Failure switched off; strengths kept at the shotcrete values so that switching it on by
/// `interval` alone gives sensible numbers.
const COHESION_OFF: CohesionParams =
    CohesionParams { interval: 0.0, tensile_strength: 1500.0, shear_strength: 5000.0, cohesion: 2000.0 };

/// Slump switched off; the shotcrete yield stress kept so that switching it on by `interval`
/// alone gives sensible numbers.
const SLUMP_OFF: SlumpParams = SlumpParams { interval: 0.0, yield_stress: 2500.0, max_sweeps: 200 };

/// Erosion constants (physics-notes.md; Oka et al., Wear 259, 2005): a paint or epoxy coat on
/// mild steel. Steel: Hv ≈ 1.4 GPa (S235/S275, 120–170 HV), E90 = 65 Hv^−0.12 mm³/kg = 6.2e-8
/// m³/kg for silica at 104 m/s and 326 µm, Finnie's k ≈ 3e-11 m³/J. A coat wears about 70 times
/// faster: blasting productivity (9–21 m²/h of a 150–250 µm coat with 220–520 kg/h of grit)
/// removes about 1e-5 m³ of coat per kg of grit at the best angle, so E90 ≈ 5e-6 m³/kg (the
/// angle function of Hv = 0.2 GPa peaks at 2.1) and k ≈ 2e-9 m³/J at 125 m/s; Oka's hardness
/// fit, made on metals, is used for the coat's angle function only.
const EROSION: ErosionDefaults = ErosionDefaults {
    model: ErosionKind::None,
    grain_diameter: 0.5e-3,
    oka_v_ref: 104.0,
    oka_d_ref: 326e-6,
    oka_k3: 0.19,
    coating: LayerDefaults { hardness: 0.2, oka_e90: 5e-6, finnie_k: 2e-9 },
    substrate: LayerDefaults { hardness: 1.4, oka_e90: 6.2e-8, finnie_k: 3e-11 },
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
                    alpha: 1.0, // Table 1: the angle-based law governs rebound
                    // Aggregate rebounds off a hard surface, is caught by a plastic cushion.
                    rebound_model: ReboundKind::Cushion,
                    rebound: None,
                    restitution: 0.04,    // Table 1: 0.03–0.05
                    scatter_angle: 5.0,   // Table 1: "small angular noise"
                    rest_speed: 0.5,      // m/s; slower rebounds stay put
                    rest_max_slope: 90.0, // wet mix holds on any face that is not an overhang
                    // 1.5–2 largest grains, m: a cushion is a layer, not one particle's splat.
                    cushion_radius: 0.02,
                },
                // Wet-mix is placed at 40–80 mm slump (ACI 506R); the slump–yield relation of Hu
                // and de Larrard, τ₀ = ρ (300 − s)/270 (Ferraris & de Larrard 1998; Roussel
                // 2006), gives 1.9–2.3 kPa, and spraying stiffens it further; wet-mix build-ups
                // of 68–218 mm (Yun et al. 2016) mean ρ g t = 1.5–4.9 kPa. 2500 Pa holds
                // τ_y/(ρ g) = 111 mm on a wall.
                slump: SlumpParams { interval: 0.1, ..SLUMP_OFF },
                // Fresh wet-mix shotcrete builds about 50–100 mm overhead in one pass: ρ g t
                // there sets the pull-off strength; the bond in shear outlasts the yield stress,
                // so on a wall the layer slumps before it slides off.
                cohesion: CohesionParams {
                    interval: 0.1,            // as often as slump: a lump falls once it outgrows its hold
                    tensile_strength: 1500.0, // Pa: fails overhead beyond ρ g t ≈ 66 mm
                    shear_strength: 5000.0,   // Pa: would slide off a wall beyond ≈ 222 mm
                    cohesion: 2000.0,         // Pa: of the order of the fresh mix's yield stress
                },
                erosion: ErosionDefaults { model: ErosionKind::None, ..EROSION },
                // ASA: 1–2 m, square on; rebound rises beyond 20°. Travel speed: v = Q (1 − R) /
                // (t s), a 25–66 mm pass over bands s = 0.1–0.3 m at 5.4 m³/h (ACI 506R: small
                // circles advancing along the pass; the circling tip speed is not the travel).
                window: WindowParams { standoff: [1.0, 2.0], max_angle: 20.0, speed: [0.05, 0.5] },
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
                    rebound: None,
                    restitution: 0.0,   // Table 1: N/A
                    scatter_angle: 0.0, // Table 1: negligible
                    rest_speed: 0.0,
                    rest_max_slope: 45.0,
                    cushion_radius: 0.0,
                },
                // Table 1: no cohesive failure; a film's slump is the sag and drip model (its
                // 120 µm sag limit is a yield stress of ρ g t ≈ 1.4 Pa).
                slump: SlumpParams { yield_stress: 1.4, ..SLUMP_OFF },
                cohesion: CohesionParams { interval: 0.0, ..COHESION_OFF },
                erosion: ErosionDefaults { model: ErosionKind::None, ..EROSION },
                // Air spray guns: 15–30 cm, near square; about 0.3 m/s conventional, 0.45 m/s HVLP
                // (Duffy, Auto Collision Repair and Refinishing, ch. 28; NAVAIR 01-1A-509-2).
                window: WindowParams { standoff: [0.15, 0.3], max_angle: 15.0, speed: [0.2, 0.6] },
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
                    rebound: None,
                    restitution: 0.75,   // Table 1: 0.6–0.9
                    scatter_angle: 20.0, // Table 1: moderate–large
                    rest_speed: 0.5,     // grains come to rest on the floor
                    rest_max_slope: 45.0,
                    cushion_radius: 0.0,
                },
                // Table 1: no cohesive failure; dry grit does not slump.
                slump: SLUMP_OFF,
                cohesion: CohesionParams { interval: 0.0, ..COHESION_OFF },
                erosion: ErosionDefaults { model: ErosionKind::Finnie, ..EROSION },
                // 30–90 cm, 45–90° to the surface; one full-dose pass at v = P / w, 9–21 m²/h over
                // a 50–150 mm cleaning width (MIL-HDBK-1110; abrasive suppliers' charts).
                window: WindowParams { standoff: [0.3, 0.9], max_angle: 45.0, speed: [0.02, 0.15] },
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
            // Sizes are not modelled unless asked for (or a paint gun sets them).
            droplets: DropletsKind::None,
            droplet_diameter: 0.5e-3,
            sauter_mean: 30e-6,
            gsd: 1.9,
            rr_spread: 2.3,
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

/// Unit (or meaning) of each preset key, printed beside it by [`presets_toml`]; the rebound
/// law's keys are the law's own (see `ReboundModel::notes`), and `rebound_model` lists the laws.
const UNITS: &[(&str, &str)] = &[
    ("density", "kg/m³"),
    ("flow_rate", "m³/s while spraying"),
    ("drag", "1/m, a = −k |v| v"),
    ("max_lifetime", "s"),
    ("coverage_threshold", "m"),
    ("alpha", "P(rebound) = α · p_r(θ), 0–1"),
    ("cushion_radius", "m, the layer under an impact is averaged over it"),
    ("restitution", "rebound speed / impact speed"),
    ("scatter_angle", "degrees, half-angle about the specular direction"),
    ("rest_speed", "m/s"),
    ("rest_max_slope", "degrees from +z"),
    ("process.slump.interval", "s between relaxations, 0 = off"),
    ("yield_stress", "Pa"),
    ("max_sweeps", "relaxation sweeps per interval at most"),
    ("interval", "s between failure analyses, 0 = off"),
    ("sag_threshold", "m of wet film that sags on a vertical face, 0 = off"),
    ("drip_interval", "s between drip passes, 0 = off"),
    ("standoff", "m, [min, max] recommended"),
    ("process.window.speed", "m/s, [min, max] travel along the path (without a superposed circle)"),
    ("hardness", "GPa, Vickers (Oka's angle function)"),
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
        (Shotcrete, "process.window.speed") => "a 25–66 mm pass over 0.1–0.3 m bands at 5.4 m³/h",
        (Painting, "process.window.speed") => "0.3 conventional, 0.45 HVLP (Duffy; NAVAIR 01-1A-509-2)",
        (Blasting, "process.window.speed") => "one full-dose pass, 9–21 m²/h over 50–150 mm (MIL-HDBK-1110)",
        (_, "process.erosion.coating.hardness") => "paint or epoxy, for the angle function only",
        (_, "process.erosion.coating.oka_e90") => {
            "about 1e-5 m³ of coat per kg of grit at best (productivity)"
        }
        (_, "process.erosion.coating.finnie_k") => "the same productivity at 125 m/s",
        (_, "process.erosion.substrate.hardness") => "mild steel, 120–170 HV",
        (_, "process.erosion.substrate.oka_e90") => "65 Hv^-0.12 mm³/kg (Oka et al. 2005)",
        (_, "process.erosion.substrate.finnie_k") => "steel, Oka et al. 2005 at 104 m/s",
        (Shotcrete, "density") => "fresh wet-mix concrete",
        (Shotcrete, "flow_rate") => "5.4 m³/h, a typical wet-mix nozzle (4–10 m³/h)",
        (Shotcrete, "alpha") => "Table 1: angle-based",
        (Shotcrete, "rebound_polynomial") => "the aggregate's share of 40 % at 45° (ASA, vendors)",
        (Shotcrete, "aggregate_fraction") => "sand 40–60 %, coarse 10–20 % (Morgan & Jolin 2022)",
        (Shotcrete, "grading") => "ACI 506R gradation No. 2, mid-band",
        (Shotcrete, "capture_ratio") => "Poncelet penetration: 0.5–2.2; calibrated to ACI's wall rebound",
        (Shotcrete, "yield_stress") => "40–80 mm slump (Hu & de Larrard); build-ups of Yun et al. 2016",
        (Painting, "yield_stress") => "ρ g × the 120 µm sag limit; the drip model acts instead",
        (Shotcrete, "restitution") => "Table 1: 0.03–0.05",
        (Shotcrete, "scatter_angle") => "Table 1: small",
        (Shotcrete, "spawn_rate") => "Table 1: 10⁴",
        (Shotcrete, "emitter.speed") => "Table 1: 20–30 (wet-mix)",
        (Shotcrete, "diameter") => "Table 1: 32–76 mm",
        (Shotcrete, "cone_angle") => "Table 1: 9–18",
        (Shotcrete, "mu" | "sigma") => "paper: fit to Ginouse & Jolin's wet-mix profiles",
        (Painting, "density") => "waterborne paint",
        (Painting, "flow_rate") => "300 mL/min, an air spray gun",
        (Painting, "alpha") => "Table 1: rebound suppressed",
        (Painting, "spawn_rate") => "Table 1: 10⁴–10⁵",
        (Painting, "emitter.speed") => "Table 1: 20–60",
        (Painting, "diameter") => "Table 1: 0.5–2 mm",
        (Painting, "cone_angle") => "Table 1: 15–120",
        (Painting, "shape") => "Table 1: point / rectangular / annulus",
        (Blasting, "density") => "fused alumina grit",
        (Blasting, "flow_rate") => "about 6 kg/min of grit",
        (Blasting, "rebound_model") => "Table 1: forced rebound, p_r ≡ 1",
        (Blasting, "restitution") => "Table 1: 0.6–0.9",
        (Blasting, "scatter_angle") => "Table 1: moderate–large",
        (Blasting, "spawn_rate") => "Table 1: 10³–10⁵",
        (Blasting, "emitter.speed") => "Table 1: 100–200",
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
    let laws = ReboundKind::NAMES.iter().map(|(name, _)| *name).collect::<Vec<_>>().join(" | ");
    for preset in Preset::ALL {
        let sections = Sections { process: preset.resolved_process(), emitter: preset.resolved_emitter() };
        let law_notes = sections.process.impact.rebound.as_dyn().notes();
        let text = toml::to_string(&sections).unwrap_or_else(|e| panic!("presets always serialise: {e}"));
        out.push_str(&format!("\n# ---- {} ----\n", preset.name()));
        let mut section = "";
        for line in text.lines() {
            if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
                section = name;
            }
            let key = line.split(" = ").next().unwrap_or_default();
            // A key's own entry in its section first (`process.window.speed`), else by name.
            let full = format!("{section}.{key}");
            let lookup = |table: &[(&str, &'static str)]| {
                table
                    .iter()
                    .find(|(k, _)| *k == full)
                    .or_else(|| table.iter().find(|(k, _)| *k == key))
                    .map(|(_, u)| *u)
            };
            let unit = match key {
                "rebound_model" => Some(laws.as_str()),
                _ => lookup(UNITS).or_else(|| lookup(law_notes)),
            };
            match (unit, source(preset, &full).or_else(|| source(preset, key))) {
                (Some(u), Some(s)) => out.push_str(&format!("{line:<46} # {u}; {s}\n")),
                (Some(u), None) => out.push_str(&format!("{line:<46} # {u}\n")),
                _ => out.push_str(&format!("{line}\n")),
            }
        }
    }
    out.push_str(&guns_toml());
    out
}

/// Every paint gun's settings over the painting preset as TOML blocks: its `[process]` and
/// `[process.window]` keys, its `[emitter]` and its `[air]`, under a line naming its sources.
fn guns_toml() -> String {
    #[derive(serde::Serialize)]
    struct Sections<'a> {
        emitter: &'a crate::params::EmitterParams,
        air: &'a crate::params::AirParams,
    }
    let mut out = String::new();
    for gun in crate::Gun::ALL {
        let text = format!("[process]\npreset = \"painting\"\ngun = \"{}\"\n", gun.name());
        let sc = crate::Scenario::from_toml(&text, "a paint gun")
            .unwrap_or_else(|e| panic!("the {} gun is invalid: {e}", gun.name()));
        let (p, w) = (sc.process(), &sc.process().window);
        out.push_str(&format!(
            "\n# ---- painting with gun = \"{}\" (over the painting preset) ----\n# sources: {}\n\
             [process]\npreset = \"painting\"\ngun = \"{}\"\nflow_rate = {:?}{:>24}\n\n[process.window]\n\
             standoff = {:?}{:>24}\nspeed = {:?}{:>24}\n\n",
            gun.name(),
            gun.sources(),
            gun.name(),
            p.flow_rate,
            "# m³/s while spraying",
            w.standoff,
            "# m, [min, max]",
            w.speed,
            "# m/s, [min, max]",
        ));
        let sections = Sections { emitter: sc.emitter(), air: sc.air() };
        out.push_str(&toml::to_string(&sections).unwrap_or_else(|e| panic!("guns always serialise: {e}")));
    }
    out
}

impl Preset {
    /// This preset's `[process]` as a scenario with no `[process]` keys but the preset's name
    /// resolves it.
    pub fn resolved_process(self) -> crate::params::ProcessParams {
        let table = crate::reader::table_of("preset", self.name());
        crate::params::read::process(&crate::reader::Section::root(&table), Preset::defaults)
            .unwrap_or_else(|e| panic!("the {} preset is invalid: {e}", self.name()))
    }

    /// This preset's `[emitter]`, resolved the same way.
    pub fn resolved_emitter(self) -> crate::params::EmitterParams {
        crate::params::read::emitter(&crate::reader::Section::empty("emitter"), &self.emitter_defaults(), 1.0)
            .unwrap_or_else(|e| panic!("the {} preset is invalid: {e}", self.name()))
    }
}
