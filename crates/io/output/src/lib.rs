//! # spraysim-output
//!
//! Writing a run's results: `metrics.json`, per-target arrays (`.npy`), heatmaps (`.png`) and
//! 3D files of the deposits (PLY, glTF, VTK), the impact log and the resolved scenario, and
//! checkpoints to resume a run. An output directory holds one run's complete set, is written
//! by one writer at a time, and spraysim never touches a file there that it did not write (see
//! [`directory`]).

pub mod checkpoint;
pub mod directory;
pub mod export;
pub mod heatmap;
mod maps;
pub mod text;

pub use directory::{CommitHooks, CommitPoint, FILE_LIST, NoHooks, OutputDir, STAGING_PREFIX};

use ndarray::{ArrayViewD, IxDyn};
use spraysim_engine::Simulation;
use spraysim_engine::collision::SurfaceKind;
use spraysim_engine::deposit::{DepositSurface, Layout};
use spraysim_scenario::{ExportFormat, Scenario};
use std::path::{Path, PathBuf};

/// Why outputs could not be written.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// A file or folder could not be created, written or moved.
    #[error("{path}: {source}")]
    Io {
        /// What was being written.
        path: PathBuf,
        /// What the operating system reported.
        #[source]
        source: std::io::Error,
    },
    /// Another writer holds the output directory's lock.
    #[error(
        "{path} is in use by another spraysim writer ({holder}): wait for it to finish, or write into \
         another directory"
    )]
    Busy {
        /// The output directory whose lock is held.
        path: PathBuf,
        /// Who holds it: process id, for how long, command line.
        holder: String,
    },
    /// An array could not be encoded.
    #[error("{path}: cannot write the array: {message}")]
    Npy {
        /// The `.npy` file being written, by its name in the output directory.
        path: PathBuf,
        /// What the array encoder reported.
        message: String,
    },
    /// An image could not be encoded.
    #[error("{path}: cannot write the image: {message}")]
    Image {
        /// The image file being written, as its caller named it.
        path: PathBuf,
        /// What the PNG encoder reported.
        message: String,
    },
}

pub(crate) fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> OutputError + '_ {
    move |source| OutputError::Io { path: path.to_path_buf(), source }
}

/// Writes `files` (name, contents) into `dir` as one set (see [`OutputDir::write_set`]),
/// holding the directory's lock for the write; returns the paths written.
pub fn write_all(dir: &Path, files: &[(String, Vec<u8>)]) -> Result<Vec<PathBuf>, OutputError> {
    OutputDir::lock(dir)?.write_set(files)
}

/// Writes every output of `sim`, a run of `scenario`, into `dir` (created if needed), holding
/// the directory's lock for the write; returns the files written.
pub fn write_outputs(sim: &Simulation, scenario: &Scenario, dir: &Path) -> Result<Vec<PathBuf>, OutputError> {
    write_outputs_with(sim, scenario, &OutputDir::lock(dir)?, Vec::new(), &NoHooks)
}

/// [`write_outputs`] into a directory the caller has locked, with `extra` files (name,
/// contents) of the same run, such as its 3D views: written in the same set and listed in the
/// same manifest, with the caller's `hooks` (see [`OutputDir::write_set_with`]). The directory
/// then records this run (see [`OutputDir::record_run`]).
pub fn write_outputs_with(
    sim: &Simulation,
    scenario: &Scenario,
    dir: &OutputDir,
    extra: Vec<(String, Vec<u8>)>,
    hooks: &dyn CommitHooks,
) -> Result<Vec<PathBuf>, OutputError> {
    let written = dir.write_set_with(&outputs_with(sim, scenario, extra)?, hooks)?;
    dir.record_run(&scenario.to_toml())?;
    Ok(written)
}

/// What `metrics.json` holds: the engine's metrics, the sanity warnings about the run (see
/// [`spraysim_scenario::sanity`]), whether the run reached its duration (`time` says how far it
/// got), and the manifest of the run's other files.
#[derive(serde::Serialize)]
struct MetricsFile<'a> {
    #[serde(flatten)]
    metrics: &'a spraysim_engine::Metrics,
    #[serde(skip_serializing_if = "Option::is_none")]
    warnings: Option<Vec<spraysim_scenario::sanity::Warning>>,
    completed: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    files: Option<Vec<FileEntry<'a>>>,
}

/// One file of a run's set: its name, size in bytes and SHA-256 (hex).
#[derive(serde::Serialize)]
struct FileEntry<'a> {
    name: &'a str,
    bytes: usize,
    sha256: String,
}

/// The metrics of `sim` as `metrics.json` holds them, without the manifest: the engine's
/// [`spraysim_engine::Metrics`] and whether the run reached its duration (`completed`; `time`
/// says how far it got). Without the scenario, it has no `warnings` (see
/// [`spraysim_scenario::sanity::after_run`]).
pub fn metrics_json(sim: &Simulation) -> Result<String, OutputError> {
    metrics_file(sim, None, None)
}

/// [`metrics_json`] of `sim`, a run of `sc`, with the sanity `warnings` about it: what a
/// written set's `metrics.json` holds, less its manifest.
pub fn run_metrics_json(sim: &Simulation, sc: &Scenario) -> Result<String, OutputError> {
    metrics_file(sim, Some(sc), None)
}

/// `metrics.json` of `sim`, with the warnings about it as a run of `sc` when given, and the
/// manifest of `files` when given.
fn metrics_file(
    sim: &Simulation,
    sc: Option<&Scenario>,
    files: Option<&[(String, Vec<u8>)]>,
) -> Result<String, OutputError> {
    let metrics = sim.metrics();
    let warnings = sc.map(|sc| spraysim_scenario::sanity::after_run(sc, &metrics));
    let files = files.map(|files| {
        let mut entries = Vec::with_capacity(files.len());
        for (name, bytes) in files {
            let sha256 = directory::hash_bytes(bytes);
            entries.push(FileEntry { name, bytes: bytes.len(), sha256 });
        }
        entries
    });
    let file = MetricsFile { metrics: &metrics, warnings, completed: sim.is_finished(), files };
    serde_json::to_string_pretty(&file)
        .map_err(|e| OutputError::Io { path: "metrics.json".into(), source: e.into() })
}

/// Every output of `sim`, a run of `sc`, as (file name, contents).
pub fn outputs(sim: &Simulation, sc: &Scenario) -> Result<Vec<(String, Vec<u8>)>, OutputError> {
    outputs_with(sim, sc, Vec::new())
}

/// [`outputs`] with `extra` files of the same run, before the manifest is made.
fn outputs_with(
    sim: &Simulation,
    sc: &Scenario,
    extra: Vec<(String, Vec<u8>)>,
) -> Result<Vec<(String, Vec<u8>)>, OutputError> {
    let mut files = Vec::new();
    let header = "# Resolved scenario written by spraysim: every default filled in.\n\
                  # Run it again with `spraysim run scenario.resolved.toml` for the same result.\n\n";
    files.push(("scenario.resolved.toml".into(), format!("{header}{}", sc.to_toml()).into_bytes()));
    if sc.output().impact_log > 0.0 {
        files.push(("impacts.csv".into(), impact_csv(sim).into_bytes()));
    }
    for t in sim.targets() {
        files.extend(target_files(t, sim.targets(), sc)?);
    }
    if sc.output().export_particles {
        let points: Vec<_> = sim.in_flight().map(|(x, v, _)| (x, v)).collect();
        files.push(("particles.ply".into(), export::ply_points(&points)));
    }
    files.extend(extra);
    // The index of the set comes first: it is moved into place last.
    let metrics = metrics_file(sim, Some(sc), Some(&files))?.into_bytes();
    files.insert(0, ("metrics.json".to_string(), metrics));
    Ok(files)
}

/// The arrays, heatmaps and 3D files of one target (`all`: every target of the run, `t` among
/// them, which its maps may point to).
fn target_files(
    t: &spraysim_engine::world::Target,
    all: &[spraysim_engine::world::Target],
    sc: &Scenario,
) -> Result<Vec<(String, Vec<u8>)>, OutputError> {
    let mut files = Vec::new();
    let layout = t.surface.layout();
    let shape = match &layout {
        Layout::Grid { rows, cols, .. } => vec![*rows, *cols],
        Layout::Cells { count } => vec![*count],
    };
    let name = |what: &str, ext: &str| format!("{}_{what}.{ext}", t.name);
    // Cells cut away (openings) carry no surface: NaN in the maps.
    let cells = t.surface.thickness().len() as u32;
    let solid: Vec<bool> = (0..cells).map(|c| t.surface.cell_area(c) > 0.0).collect();
    let map = |values: &dyn Fn(usize) -> f64| -> Vec<f64> {
        (0..cells as usize).map(|c| if solid[c] { values(c) } else { f64::NAN }).collect()
    };
    let thickness = map(&|c| t.surface.thickness()[c]);
    if sc.output().arrays {
        let f32s = |v: &[f64]| v.iter().map(|&x| x as f32).collect::<Vec<f32>>();
        let n = name("thickness", "npy");
        files.push((n.clone(), npy_bytes(&shape, &f32s(&thickness), Path::new(&n))?));
        if let Some(solids) = sc.process().volume_solids {
            let dry: Vec<f64> = thickness.iter().map(|x| x * solids).collect();
            let n = name("dry_thickness", "npy");
            files.push((n.clone(), npy_bytes(&shape, &f32s(&dry), Path::new(&n))?));
        }
        let n = name("hits", "npy");
        files.push((n.clone(), npy_bytes(&shape, t.surface.hits(), Path::new(&n))?));
        if let Some(e) = &t.erosion {
            let n = name("erosion", "npy");
            files.push((n.clone(), npy_bytes(&shape, &f32s(&map(&|c| e.substrate[c])), Path::new(&n))?));
            if e.initial_coating > 0.0 {
                let n = name("coating", "npy");
                files.push((n.clone(), npy_bytes(&shape, &f32s(&map(&|c| e.coating[c])), Path::new(&n))?));
            }
        }
    }
    if sc.output().images {
        for (what, img) in maps::target_maps(t, all, sc, &thickness) {
            let n = name(what, "png");
            files.push((n.clone(), png_bytes(&img, Path::new(&n))?));
        }
    }
    if !sc.output().export.is_empty() {
        let deposit = export::Deposit::of(t, sc.output().export_max_cells as usize, sc.output().colormap);
        for &format in &sc.output().export {
            let n = format!("{}.{}", t.name, format.extension());
            let bytes = match format {
                ExportFormat::Ply => export::ply(&deposit, &t.name),
                ExportFormat::Vtk => export::vtk(&deposit, &t.name),
                ExportFormat::Glb => export::glb(&deposit, &t.name)
                    .map_err(|message| OutputError::Npy { path: n.clone().into(), message })?,
            };
            files.push((n, bytes));
        }
    }
    Ok(files)
}

/// The impact log as CSV: one sampled impact a row.
fn impact_csv(sim: &Simulation) -> String {
    let name = |s| match sim.scene().surface(s).kind {
        SurfaceKind::Target(i) => sim.targets()[i].name.as_str(),
        SurfaceKind::Obstacle(i) => sim.obstacles()[i].name.as_str(),
    };
    let mut out =
        String::from("time_s,x_m,y_m,z_m,nx,ny,nz,vx_m_s,vy_m_s,vz_m_s,surface,outcome,eroded_m3\n");
    for i in sim.impact_log() {
        let (p, n, v) = (i.position, i.normal, i.velocity);
        let outcome = if i.stuck { "stuck" } else { "rebounded" };
        out.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{outcome},{}\n",
            i.time,
            p.x,
            p.y,
            p.z,
            n.x,
            n.y,
            n.z,
            v.x,
            v.y,
            v.z,
            name(i.surface),
            i.eroded
        ));
    }
    out
}

fn npy_bytes<T: ndarray_npy::WritableElement>(
    shape: &[usize],
    data: &[T],
    at: &Path,
) -> Result<Vec<u8>, OutputError> {
    use ndarray_npy::WriteNpyExt;
    let err = |message: String| OutputError::Npy { path: at.to_path_buf(), message };
    let array = ArrayViewD::from_shape(IxDyn(shape), data).map_err(|e| err(e.to_string()))?;
    let mut bytes = Vec::new();
    array.write_npy(&mut bytes).map_err(|e| err(e.to_string()))?;
    Ok(bytes)
}

/// `img` encoded as PNG; `at` names the file in errors.
pub fn png_bytes(img: &image::RgbImage, at: &Path) -> Result<Vec<u8>, OutputError> {
    let mut bytes = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png)
        .map_err(|e| OutputError::Image { path: at.to_path_buf(), message: e.to_string() })?;
    Ok(bytes)
}
