//! # spraysim-render
//!
//! 3D views of spraysim runs, drawn with wgpu: the targets with their deposit as a displaced
//! surface coloured by thickness (the heatmaps' colour scale, with a legend), erosion or coating
//! maps for blasting, failed and at-risk regions, the obstacles (rebar as cylinders, boxes,
//! spheres, meshes), the nozzle with its spray axis and cone, its path (past and planned), and
//! the particles in flight coloured by state or by speed.
//!
//! Three layers, each usable alone:
//!
//! - [`Scene`]: what a view shows, built on the CPU from a running [`spraysim::Simulation`]
//!   ([`Scene::build`]), as plain vertex lists;
//! - [`Camera`] and [`camera::Orbit`]: where the view is taken from, with presets that frame the
//!   whole scene ([`Camera::preset`]);
//! - [`gpu`]: the [`gpu::Renderer`] that draws a scene into any wgpu render pass (a window's or
//!   an offscreen texture's), and [`Offscreen`], which renders to an image without a display.
//!
//! [`record`] draws the stills and animations a scenario's `[output] render` asks for during a
//! run (`spraysim render`, and `spraysim run` with its `render` feature).
//!
//! Without a GPU, Mesa's software drivers (lavapipe for Vulkan, llvmpipe for GL) render the same
//! pictures; [`Offscreen::new`] returns [`RenderError::NoAdapter`] when no adapter at all is found.
//!
//! ```no_run
//! use spraysim_render::{Camera, Offscreen, Scene, SceneOptions, ViewPreset};
//!
//! let scenario = spraysim::Scenario::default_scene().with("simulation.duration", 0.2)?;
//! let mut sim = scenario.build()?;
//! sim.run(|_| {});
//! let scene = Scene::build(&sim, &SceneOptions::for_scenario(&scenario));
//! let camera = Camera::preset(ViewPreset::Iso, &scene.framing, 40f64.to_radians(), 16.0 / 9.0);
//! let mut view = Offscreen::new(&Default::default(), 1280, 720)?;
//! let image = view.render(&scene, &camera)?;
//! image.save("wall.png")?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod camera;
pub mod gpu;
pub mod overlay;
pub mod record;
pub mod scene;
mod shapes;

pub use camera::Camera;
pub use gpu::{GpuOptions, Offscreen};
pub use scene::{Field, Scene, SceneOptions, Show};
pub use spraysim::scenario::{ParticleColoring, RenderCamera, RenderParams, RenderTime, ViewPreset};

/// Why a view could not be rendered.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No graphics adapter: no GPU driver, and no software one either.
    #[error(
        "no graphics adapter found ({0}); on Debian or Ubuntu, Mesa's software drivers render without a GPU: \
         apt-get install mesa-vulkan-drivers libvulkan1 libegl1 libgl1-mesa-dri"
    )]
    NoAdapter(String),
    /// The adapter refused to open a device.
    #[error("cannot open the graphics device: {0}")]
    Device(String),
    /// The rendered image could not be read back.
    #[error("cannot read the rendered image back: {0}")]
    Readback(String),
    /// A setting is out of range.
    #[error("{0}")]
    Settings(String),
    /// An image or animation could not be encoded.
    #[error("cannot encode {what}: {message}")]
    Encode {
        /// What was being encoded.
        what: String,
        /// Why the encoder refused it, as the encoder says.
        message: String,
    },
}
