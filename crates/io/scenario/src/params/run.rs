//! `[simulation]`, `[domain]` and `[output]`: time stepping, the box particles live in, and
//! what a run writes.

use crate::params::Preset;
use crate::params::render::{RenderParams, read_render};
use crate::reader::{Check, Read, Section, bad, choices};
use serde::Serialize;
use spraysim_engine::motion::{GRAVITY, Integrator};

choices!(Integrator {
    "euler" => Integrator::Euler,
    "semi_implicit_euler" => Integrator::SemiImplicitEuler,
    "exact" => Integrator::Exact,
});

/// What flies the particles (`[simulation] backend`, `spraysim run --backend`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Backend {
    /// The engine's own flight on the CPU's cores.
    #[default]
    Cpu,
    /// The GPU's kernels (a build with the `gpu` feature and a Vulkan adapter); a scenario
    /// outside their scope is refused.
    Gpu,
    /// The GPU where the build, an adapter and the scenario allow it, else the CPU, saying why
    /// in one line.
    Auto,
}

choices!(Backend {
    "cpu" => Backend::Cpu,
    "gpu" => Backend::Gpu,
    "auto" => Backend::Auto,
});

impl Backend {
    /// The backend named `name` (`"cpu"`, `"gpu"` or `"auto"`), or an error listing them.
    pub fn parse(name: &str) -> Result<Backend, String> {
        use crate::reader::Choice;
        Backend::NAMES.iter().find(|(n, _)| *n == name).map(|&(_, b)| b).ok_or_else(|| {
            let names: Vec<String> = Backend::NAMES.iter().map(|(n, _)| format!("\"{n}\"")).collect();
            format!("unknown backend {name:?}; expected one of {}", names.join(", "))
        })
    }

    /// Its name in files: `"cpu"`, `"gpu"` or `"auto"`.
    pub fn name(self) -> &'static str {
        crate::reader::Choice::name(self)
    }
}

/// `[simulation]`: time stepping.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SimulationParams {
    /// Time step Δt, s.
    pub dt: f64,
    /// Simulated duration, s.
    pub duration: f64,
    /// Seed of every random stream.
    pub seed: u64,
    /// `"euler"`, `"semi_implicit_euler"` or `"exact"`.
    pub integrator: Integrator,
    /// Most impacts resolved for one particle within one step.
    pub max_impacts_per_step: u32,
    /// Length of a layer epoch, s (rounded to whole steps, at least one): particles see every
    /// deposit surface as it stood at the epoch's start; deposits, erosion and the layer
    /// stages take effect at its end.
    pub layer_epoch: f64,
    /// Gravitational acceleration, m/s².
    pub gravity: [f64; 3],
    /// Most memory a run may need, bytes; 0: half of the machine's memory. A scenario whose
    /// estimate exceeds it is refused before the run.
    pub max_memory: f64,
    /// What flies the particles: `"cpu"`, `"gpu"` or `"auto"`.
    pub backend: Backend,
}

/// Default length of a layer epoch, s: where a spray builds its layer fastest (the default
/// scene's static shotcrete spot, 25 mm/s) the layer grows 0.13 mm in one, and every reported
/// figure of the test scenes stays within its tolerance of an epoch of one step (see
/// docs/validation.md).
pub const DEFAULT_LAYER_EPOCH: f64 = 0.005;

/// Reads `[simulation]`; `drag` (1/m) decides whether the exact integrator applies.
pub(crate) fn read_simulation(s: &Section<'_>, drag: f64) -> Read<SimulationParams> {
    let dt = s.number("dt", Some(1e-3), Check::Positive(0.1), "s")?;
    if dt < 1e-7 {
        return bad(&s.key("dt"), format!("must be at least 1e-7 s, got {}", crate::reader::Num(dt)));
    }
    let duration = s.number("duration", Some(2.0), Check::Positive(1e6), "s")?;
    if duration / dt > 1e9 {
        return bad(&s.key("duration"), "needs more than 10⁹ steps at this dt");
    }
    let seed = s.integer("seed", Some(1), 0, i64::MAX)? as u64;
    let integrator = s.choice("integrator", Some(Integrator::Euler))?;
    if integrator == Integrator::Exact && drag != 0.0 {
        return bad(
            &s.key("integrator"),
            "\"exact\" has no closed form with drag; set process.drag = 0 or use \"euler\" or \"semi_implicit_euler\"",
        );
    }
    let p = SimulationParams {
        dt,
        duration,
        seed,
        integrator,
        max_impacts_per_step: s.integer("max_impacts_per_step", Some(8), 1, 1000)? as u32,
        layer_epoch: s.number("layer_epoch", Some(DEFAULT_LAYER_EPOCH), Check::Positive(1.0), "s")?,
        gravity: s.numbers("gravity", Some(GRAVITY.to_array()), Check::Within(-100.0, 100.0), "m/s²")?,
        max_memory: s.number("max_memory", Some(0.0), Check::Within(0.0, 1e15), "bytes")?,
        backend: s.choice("backend", Some(Backend::Cpu))?,
    };
    s.finish("[simulation]")?;
    Ok(p)
}

/// `[domain]`: particles that leave this axis-aligned box are retired.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DomainParams {
    /// Lower corner, m.
    pub min: [f64; 3],
    /// Upper corner, m.
    pub max: [f64; 3],
}

/// Reads `[domain]`; `default` is used when the file gives none.
pub(crate) fn read_domain(
    s: Option<&Section<'_>>,
    default: impl FnOnce() -> DomainParams,
) -> Read<DomainParams> {
    let Some(s) = s else { return Ok(default()) };
    let d = DomainParams { min: s.point("min", None)?, max: s.point("max", None)? };
    if (0..3).any(|i| d.min[i] >= d.max[i]) {
        return bad(&s.key("max"), "must be greater than domain.min along every axis");
    }
    s.finish("[domain]")?;
    Ok(d)
}

/// Colour map of the heatmap images.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Colormap {
    /// Perceptually uniform, colour-blind safe.
    #[default]
    Viridis,
    /// High contrast rainbow.
    Turbo,
    /// Black to yellow through red.
    Inferno,
    /// White to blue.
    Blues,
}

choices!(Colormap {
    "viridis" => Colormap::Viridis,
    "turbo" => Colormap::Turbo,
    "inferno" => Colormap::Inferno,
    "blues" => Colormap::Blues,
});

/// `[output]`: what a run writes.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OutputParams {
    /// Output directory, relative to the working directory.
    pub directory: String,
    /// Colour map of heatmaps.
    pub colormap: Colormap,
    /// Write PNG heatmaps.
    pub images: bool,
    /// Write `.npy` arrays.
    pub arrays: bool,
    /// Share of impacts written to `impacts.csv`, 0..1.
    pub impact_log: f64,
    /// 3D files of every target's deposit to write.
    pub export: Vec<ExportFormat>,
    /// Most cells of an exported mesh: a finer grid is averaged down by a whole factor.
    pub export_max_cells: u32,
    /// Also write the particles in flight at the end as a point cloud (`particles.ply`).
    pub export_particles: bool,
    /// 3D views drawn during the run and written with its outputs (`[output] render`), if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub render: Option<RenderParams>,
}

/// A 3D file format for deposits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ExportFormat {
    /// Stanford PLY, binary: per-vertex thickness and colour, per-face thickness and hits.
    Ply,
    /// glTF 2.0 binary: vertex colours, per-vertex thickness as `_THICKNESS`.
    Glb,
    /// Legacy VTK polydata, binary: thickness, hits and erosion as cell data.
    Vtk,
}

choices!(ExportFormat { "ply" => ExportFormat::Ply, "glb" => ExportFormat::Glb, "vtk" => ExportFormat::Vtk });

impl ExportFormat {
    /// The file extension.
    pub fn extension(self) -> &'static str {
        match self {
            ExportFormat::Ply => "ply",
            ExportFormat::Glb => "glb",
            ExportFormat::Vtk => "vtk",
        }
    }
}

/// Reads `[output]`; `preset` and `duration` (s) are the run's, for the render settings.
pub(crate) fn read_output(s: &Section<'_>, preset: Preset, duration: f64) -> Read<OutputParams> {
    let p = OutputParams {
        directory: s.string("directory", Some("out"))?,
        colormap: s.choice("colormap", Some(Colormap::Viridis))?,
        images: s.boolean("images", true)?,
        arrays: s.boolean("arrays", true)?,
        impact_log: s.number("impact_log", Some(0.0), Check::Within(0.0, 1.0), "")?,
        export: s.choice_list("export")?,
        export_max_cells: s.integer("export_max_cells", Some(1 << 20), 1, 1 << 24)? as u32,
        export_particles: s.boolean("export_particles", false)?,
        render: read_render(s, preset, duration)?,
    };
    if p.directory.trim().is_empty() {
        return bad(&s.key("directory"), "must not be empty");
    }
    s.finish("[output]")?;
    Ok(p)
}
