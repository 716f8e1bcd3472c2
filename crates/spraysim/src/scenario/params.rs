//! The resolved scenario: every parameter with its unit and default.
//!
//! Field docs here are the reference for the TOML keys (see also `docs/scenario.md`).

use crate::emitter::{ApertureShape, DirectionKind};
use crate::integrator::Integrator;
use serde::{Deserialize, Serialize};

/// Declares a resolved parameter struct and, beside it, its "override" twin whose fields are
/// all optional: what a scenario file may give, to be laid over a preset's values.
macro_rules! overridable {
    (
        $(#[$meta:meta])*
        pub struct $name:ident / $over:ident {
            $( $(#[$fmeta:meta])* pub $field:ident : $ty:ty, )*
        }
    ) => {
        $(#[$meta])*
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct $name {
            $( $(#[$fmeta])* pub $field: $ty, )*
        }

        #[doc = concat!("[`", stringify!($name), "`] with every field optional: the keys a file sets.")]
        #[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct $over {
            $(
                #[doc = concat!("Overrides [`", stringify!($name), "::", stringify!($field), "`].")]
                #[serde(default, skip_serializing_if = "Option::is_none")]
                pub $field: Option<$ty>,
            )*
        }

        impl $name {
            /// Replaces each field that `over` sets.
            pub fn apply(&mut self, over: &$over) {
                $( if let Some(v) = &over.$field { self.$field = v.clone(); } )*
            }
        }
    };
}

/// The three process presets of the paper's Table 1.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
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

/// Which rebound curve `p_r(θ)` applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ReboundModel {
    /// Polynomial in θ/90° with coefficients `rebound_polynomial`.
    Polynomial,
    /// `p_r ≡ 1` (forced rebound).
    Always,
    /// `p_r ≡ 0`.
    Never,
}

/// Role of a target.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    /// The surface being sprayed; counts towards transfer efficiency and rebound ratio.
    #[default]
    Substrate,
    /// A surface that catches what rebounds or falls (a floor).
    Collector,
}

/// Colour map of the heatmap images.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
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

/// Kind of an obstacle's geometry.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ObstacleShape {
    /// Infinite plane: `center` (a point on it), `normal`.
    Plane,
    /// Rectangle: `center`, `normal`, `up`, `size = [width, height]`.
    Face,
    /// Disk: `center`, `normal`, `radius`.
    Disk,
    /// Sphere: `center`, `radius`.
    Sphere,
    /// Box: `center`, `size = [x, y, z]`, optional `x_axis`, `y_axis` (local axes).
    Box,
    /// Capped cylinder (rebar): `start`, `end`, `radius`.
    Cylinder,
    /// Triangle mesh from an STL or OBJ `file`, optionally `scale`d and moved by `center`.
    Mesh,
}

/// `[simulation]`: time stepping.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SimulationParams {
    /// Time step Δt, s. Default 0.001 (the paper recommends 1e-3 within 1e-4..1e-2).
    pub dt: f64,
    /// Simulated duration, s. Default 2.
    pub duration: f64,
    /// Seed of every random stream; same seed, same output. Default 1.
    pub seed: u64,
    /// `"euler"` (forward Euler, the paper's) or `"semi_implicit_euler"`. Default `"euler"`.
    pub integrator: Integrator,
    /// Most impacts resolved for one particle within one step; past it the particle waits for
    /// the next step at its last impact point. Default 8.
    pub max_impacts_per_step: u32,
    /// Gravitational acceleration, m/s². Default `[0, 0, -9.81]` (z up); zero it for
    /// verification against gravity-free closed forms.
    pub gravity: [f64; 3],
}

impl Default for SimulationParams {
    fn default() -> Self {
        SimulationParams {
            dt: 1e-3,
            duration: 2.0,
            seed: 1,
            integrator: Integrator::Euler,
            max_impacts_per_step: 8,
            gravity: crate::integrator::GRAVITY.to_array(),
        }
    }
}

overridable! {
    /// `[process.impact]`, `[target.impact]`, `[obstacle.impact]`: what happens on impact.
    pub struct ImpactParams / ImpactOverride {
        /// Anti-adhesion factor α in P(rebound) = α · p_r(θ), dimensionless, 0..1.
        pub alpha: f64,
        /// `"polynomial"`, `"always"` (p_r ≡ 1) or `"never"` (p_r ≡ 0).
        pub rebound_model: ReboundModel,
        /// Coefficients c₀, c₁, … of p_r(θ) = Σ cᵢ (θ/90°)ⁱ, θ from the surface normal; the result
        /// is clamped to 0..1.
        pub rebound_polynomial: Vec<f64>,
        /// Coefficient of restitution: rebound speed / impact speed, 0..1.
        pub restitution: f64,
        /// Half-angle of the cone of random scatter about the specular direction, degrees, 0..90.
        pub scatter_angle: f64,
        /// A rebound slower than this comes to rest and sticks, m/s.
        pub rest_speed: f64,
        /// Steepest surface (angle of its normal from +z) on which a slow rebound can rest,
        /// degrees, 0..180. On steeper surfaces it slides off and falls.
        pub rest_max_slope: f64,
        /// Cushion effect: rebound probability multiplier on bare substrate, decaying linearly
        /// to 1 as the local layer grows to `cushion_thickness`. 1 switches it off.
        pub cushion_factor: f64,
        /// Layer thickness at which the cushion multiplier reaches 1, m. 0 switches it off.
        pub cushion_thickness: f64,
    }
}

overridable! {
    /// `[process.cohesion]`: cohesive failure of the deposited layer (see [`crate::cohesion`]).
    pub struct CohesionParams / CohesionOverride {
        /// Time between analyses, s; 0 switches failure off.
        pub interval: f64,
        /// Adhesive tensile (pull-off) strength of the fresh layer on the substrate, Pa.
        pub tensile_strength: f64,
        /// Adhesive shear strength of the fresh layer on the substrate, Pa.
        pub shear_strength: f64,
        /// Cohesion of the layer holding an over-loaded region along its boundary, Pa.
        pub cohesion: f64,
    }
}

/// Erosion model of `[process.erosion]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ErosionModel {
    /// No erosion.
    None,
    /// Finnie (ductile targets): removed volume = k · m v² · f(γ).
    Finnie,
    /// Oka: removed volume = g(γ) · E90 · m.
    Oka,
}

overridable! {
    /// `[process.erosion]`: material removed from targets by impacts (abrasive blasting), see
    /// [`crate::erosion`]. γ is the impact angle from the surface.
    pub struct ErosionParams / ErosionOverride {
        /// `"none"`, `"finnie"` or `"oka"`.
        pub model: ErosionModel,
        /// Finnie's k: volume removed per joule of m v² f(γ), m³/J.
        pub finnie_k: f64,
        /// Oka's E90 at the reference speed and grain size: volume removed per kg at normal
        /// incidence, m³/kg.
        pub oka_e90: f64,
        /// Oka's exponent n₁ of sin γ.
        pub oka_n1: f64,
        /// Oka's exponent n₂ of (1 + Hv (1 − sin γ)).
        pub oka_n2: f64,
        /// Vickers hardness of the target, GPa.
        pub oka_hv: f64,
        /// Oka's speed exponent k₂.
        pub oka_k2: f64,
        /// Oka's grain-size exponent k₃.
        pub oka_k3: f64,
        /// Oka's reference speed, m/s.
        pub oka_v_ref: f64,
        /// Oka's reference grain diameter, m.
        pub oka_d_ref: f64,
        /// Diameter of the abrasive grains, m.
        pub grain_diameter: f64,
    }
}

overridable! {
    /// `[process.window]`: the recommended working window of the nozzle; the metrics report the
    /// share of spraying time outside it.
    pub struct WindowParams / WindowOverride {
        /// Standoff `[min, max]`: distance along the spray axis to the first surface, m.
        pub standoff: [f64; 2],
        /// Largest angle between the spray axis and the surface normal (0: square on), degrees.
        pub max_angle: f64,
        /// Travel speed `[min, max]` of the nozzle, m/s.
        pub speed: [f64; 2],
    }
}

/// `[process]`: the material and its flight.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProcessParams {
    /// Preset that supplies every default of `[process]` and `[emitter]`.
    pub preset: Preset,
    /// Density of the sprayed material, kg/m³ (used for masses in metrics and, later, loads).
    pub density: f64,
    /// Volume flow rate of material through the nozzle while spraying, m³/s.
    pub flow_rate: f64,
    /// Quadratic drag coefficient k in a = −k |v| v, 1/m. 0 = ballistic.
    pub drag: f64,
    /// A particle still in flight after this long is retired as expired, s.
    pub max_lifetime: f64,
    /// A cell counts as covered when its thickness reaches this, m.
    pub coverage_threshold: f64,
    /// Impact parameters of every surface that does not override them.
    pub impact: ImpactParams,
    /// Cohesive failure of deposited layers.
    pub cohesion: CohesionParams,
    /// Erosion of targets by impacts.
    pub erosion: ErosionParams,
    /// Recommended working window of the nozzle, for the path-quality metrics.
    pub window: WindowParams,
    /// Wet-film thickness above which a film sags on a vertical face, m (on a face tilted by
    /// β from horizontal, when t · sin β exceeds it); 0 switches sag flagging off.
    pub sag_threshold: f64,
    /// Time between drip passes, s: film beyond the sag limit runs off and falls. 0 (the
    /// default) switches dripping off.
    pub drip_interval: f64,
}

/// `[process]` as a file gives it: every key optional.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProcessOverride {
    /// See [`ProcessParams::preset`].
    pub preset: Option<Preset>,
    /// See [`ProcessParams::density`].
    pub density: Option<f64>,
    /// See [`ProcessParams::flow_rate`].
    pub flow_rate: Option<f64>,
    /// See [`ProcessParams::drag`].
    pub drag: Option<f64>,
    /// See [`ProcessParams::max_lifetime`].
    pub max_lifetime: Option<f64>,
    /// See [`ProcessParams::coverage_threshold`].
    pub coverage_threshold: Option<f64>,
    /// See [`ProcessParams::impact`].
    #[serde(default)]
    pub impact: ImpactOverride,
    /// See [`ProcessParams::cohesion`].
    #[serde(default)]
    pub cohesion: CohesionOverride,
    /// See [`ProcessParams::erosion`].
    #[serde(default)]
    pub erosion: ErosionOverride,
    /// See [`ProcessParams::sag_threshold`].
    pub sag_threshold: Option<f64>,
    /// See [`ProcessParams::drip_interval`].
    pub drip_interval: Option<f64>,
    /// See [`ProcessParams::window`].
    #[serde(default)]
    pub window: WindowOverride,
}

overridable! {
    /// `[emitter]`: the nozzle's aperture, spawn rate, speeds and spray cone.
    pub struct EmitterParams / EmitterOverride {
        /// `"point"`, `"circle"`, `"rectangle"` or `"annulus"`.
        pub shape: ApertureShape,
        /// Aperture diameter of a circle, m.
        pub diameter: f64,
        /// Aperture width of a rectangle (along the nozzle's width axis), m.
        pub width: f64,
        /// Aperture height of a rectangle, m.
        pub height: f64,
        /// Inner diameter of an annulus, m.
        pub inner_diameter: f64,
        /// Outer diameter of an annulus, m.
        pub outer_diameter: f64,
        /// Particles emitted per second while spraying, 1/s.
        pub spawn_rate: f64,
        /// Emission speed range `[min, max]`, sampled uniformly, m/s.
        pub speed: [f64; 2],
        /// Full angle of the spray cone, degrees, 0..180.
        pub cone_angle: f64,
        /// `"uniform_polar"`, `"truncated_normal"`, `"uniform_solid_angle"` or `"fan"`.
        pub direction: DirectionKind,
        /// Mean μ of θ/θ_half for `"truncated_normal"`, dimensionless.
        pub mu: f64,
        /// Standard deviation σ of θ/θ_half for `"truncated_normal"`, dimensionless, > 0.
        pub sigma: f64,
        /// Full fan angle along the width axis for `"fan"`, degrees.
        pub fan_wide_angle: f64,
        /// Full fan angle across the width axis for `"fan"`, degrees.
        pub fan_narrow_angle: f64,
    }
}

/// One `[[nozzle.waypoints]]` entry.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WaypointParams {
    /// Time, s; strictly increasing along the list.
    pub time: f64,
    /// Nozzle position, m.
    pub position: [f64; 3],
    /// Spray axis (any length, not zero).
    pub axis: [f64; 3],
    /// Whether the nozzle sprays from here to the next waypoint. Default true.
    #[serde(default = "yes")]
    pub spray: bool,
}

fn yes() -> bool {
    true
}

/// `[nozzle]`: where the spray comes from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NozzleParams {
    /// Static nozzle position, m. Default `[-1, 0, 1]`. Ignored when `waypoints` are given.
    pub position: [f64; 3],
    /// Static spray axis. Default `[1, 0, 0]`. Ignored when `waypoints` are given.
    pub axis: [f64; 3],
    /// Roll of the aperture about the axis, degrees. At 0 the width axis is horizontal.
    pub roll: f64,
    /// Radius of a circular motion of the static nozzle about `position`, in the plane
    /// perpendicular to `axis` (the nozzleman's circles), m. Default 0 (none).
    pub circle_radius: f64,
    /// Revolutions per second of that motion, Hz. Default 0.
    pub circle_frequency: f64,
    /// Add the nozzle's own velocity to the particles it emits. Default false.
    pub add_velocity: bool,
    /// Time-stamped poses; position is interpolated linearly, the axis spherically.
    pub waypoints: Vec<WaypointParams>,
    /// A robot tool path to read into `waypoints`: a CSV file (relative to the scenario's
    /// folder) with the header `t,x,y,z,qx,qy,qz,qw` and optionally `spray`; the spray axis is
    /// the tool's z axis. The resolved scenario holds the waypoints it read.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub path_csv: Option<String>,
    /// A raster (zig-zag) pass over a target, generated when the simulation starts.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub raster: Option<RasterParams>,
}

/// Direction of the raster's passes in the target's face.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PassDirection {
    /// Passes along the face's width (`up × normal`), stepping up from the bottom edge.
    #[default]
    Horizontal,
    /// Passes along the face's height (`up`), stepping right from the left edge.
    Vertical,
}

/// `[nozzle.raster]`: a zig-zag pass over a rectangle of a target's face at a standoff, with an
/// optional circular motion superposed (the shotcrete nozzle technique).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RasterParams {
    /// Name of the target whose face is covered (required).
    pub target: String,
    /// `[width, height]` of the covered rectangle, m. Default: the target's size.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub size: Option<[f64; 2]>,
    /// Centre of the rectangle from the face's centre, `[right, up]`, m. Default `[0, 0]`.
    pub offset: [f64; 2],
    /// Distance of the nozzle from the face along its normal, m. Default 1.
    pub standoff: f64,
    /// Travel speed along the path, m/s. Default 0.5.
    pub speed: f64,
    /// Distance between neighbouring passes, m. Default 0.1.
    pub step_over: f64,
    /// `"horizontal"` (default) or `"vertical"` passes.
    pub passes: PassDirection,
    /// Travel beyond the rectangle's edge at each end of a pass, spraying, m. Default 0.1.
    pub lead: f64,
    /// Whether the nozzle sprays while stepping over between passes. Default false.
    pub spray_on_turns: bool,
    /// Radius of a circular motion superposed on the path, m. Default 0 (none).
    pub circle_radius: f64,
    /// Revolutions per second of that circular motion, Hz. Default 0.
    pub circle_frequency: f64,
    /// Time at which the raster starts, s. Default 0.
    pub start_time: f64,
}

impl Default for RasterParams {
    fn default() -> Self {
        RasterParams {
            target: String::new(),
            size: None,
            offset: [0.0, 0.0],
            standoff: 1.0,
            speed: 0.5,
            step_over: 0.1,
            passes: PassDirection::Horizontal,
            lead: 0.1,
            spray_on_turns: false,
            circle_radius: 0.0,
            circle_frequency: 0.0,
            start_time: 0.0,
        }
    }
}

impl Default for NozzleParams {
    fn default() -> Self {
        NozzleParams {
            position: [-1.0, 0.0, 1.0],
            axis: [1.0, 0.0, 0.0],
            roll: 0.0,
            circle_radius: 0.0,
            circle_frequency: 0.0,
            add_velocity: false,
            waypoints: Vec::new(),
            path_csv: None,
            raster: None,
        }
    }
}

fn default_resolution() -> [u32; 2] {
    [1024, 1024]
}

/// One `[[target]]`: a rectangular face that records deposition in a heightfield.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TargetParams {
    /// Name, used for output files (letters, digits, `-` and `_`).
    pub name: String,
    /// `"substrate"` (default) or `"collector"`.
    #[serde(default)]
    pub role: Role,
    /// Centre of the face, m.
    pub center: [f64; 3],
    /// Normal, pointing towards the side that receives spray.
    pub normal: [f64; 3],
    /// A direction in the face (made perpendicular to `normal`); rows grow along it.
    pub up: [f64; 3],
    /// `[width, height]`, m; width along `up × normal`, height along `up`.
    pub size: [f64; 2],
    /// Heightfield cells `[cols, rows]`, each 1..4096. Default `[1024, 1024]`.
    #[serde(default = "default_resolution")]
    pub resolution: [u32; 2],
    /// Radius over which each stuck particle's volume is spread, m. Default 0 (one cell).
    #[serde(default)]
    pub splat_radius: f64,
    /// Thickness of a coating on the face at the start, which erosion removes, m. Default 0.
    #[serde(default)]
    pub coating: f64,
    /// Impact parameters that differ from the process's.
    #[serde(default, skip_serializing_if = "is_default")]
    pub impact: ImpactOverride,
}

/// One `[[obstacle]]`: a surface without a heightfield (rebar, formwork, a floor).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleParams {
    /// Name, used in metrics.
    pub name: String,
    /// `"plane"`, `"face"`, `"disk"`, `"sphere"`, `"box"` or `"cylinder"`.
    pub shape: ObstacleShape,
    /// Centre (plane: a point on it), m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center: Option<[f64; 3]>,
    /// Normal of a plane, face or disk.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal: Option<[f64; 3]>,
    /// In-face direction of a face.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up: Option<[f64; 3]>,
    /// Face `[width, height]` or box `[x, y, z]` full size, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<Vec<f64>>,
    /// Radius of a disk, sphere or cylinder, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// First cap centre of a cylinder, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<[f64; 3]>,
    /// Second cap centre of a cylinder, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub end: Option<[f64; 3]>,
    /// Local x axis of a box. Default `[1, 0, 0]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_axis: Option<[f64; 3]>,
    /// Local y axis of a box (made perpendicular to `x_axis`). Default `[0, 1, 0]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y_axis: Option<[f64; 3]>,
    /// Mesh file (`.stl` or `.obj`), relative to the scenario's folder; the resolved scenario
    /// holds its full path.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// Factor from the mesh file's units to metres (0.001 for millimetres). Default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f64>,
    /// Impact parameters that differ from the process's.
    #[serde(default, skip_serializing_if = "is_default")]
    pub impact: ImpactOverride,
}

impl ObstacleParams {
    /// The triangles of a mesh obstacle, placed in the scene (`None` for other shapes).
    pub fn mesh(&self) -> Option<Result<Vec<crate::collision::Triangle>, crate::io::mesh::MeshError>> {
        let file = self.file.as_ref().filter(|_| self.shape == ObstacleShape::Mesh)?;
        let offset = glam::DVec3::from_array(self.center.unwrap_or_default());
        Some(crate::io::mesh::load(std::path::Path::new(file), self.scale.unwrap_or(1.0), offset))
    }
}

fn is_default<T: Default + PartialEq>(t: &T) -> bool {
    *t == T::default()
}

/// `[domain]`: particles that leave this axis-aligned box are retired.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DomainParams {
    /// Lower corner, m. Default: the scene's bounding box (targets, bounded obstacles, nozzle
    /// path) grown by 1 m.
    pub min: [f64; 3],
    /// Upper corner, m. Default as for `min`.
    pub max: [f64; 3],
}

/// `[output]`: what a run writes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OutputParams {
    /// Output directory, relative to the working directory. Default `"out"`; the CLI's `-o`
    /// overrides it.
    pub directory: String,
    /// Colour map of heatmaps. Default `"viridis"`.
    pub colormap: Colormap,
    /// Write PNG heatmaps. Default true.
    pub images: bool,
    /// Write `.npy` arrays. Default true.
    pub arrays: bool,
    /// Share of impacts written to `impacts.csv`, 0..1 (sampled by a hash of particle and
    /// impact number). Default 0: no log.
    pub impact_log: f64,
}

impl Default for OutputParams {
    fn default() -> Self {
        OutputParams {
            directory: "out".into(),
            colormap: Colormap::Viridis,
            images: true,
            arrays: true,
            impact_log: 0.0,
        }
    }
}

/// A complete, resolved scenario: every default filled in.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Time stepping.
    pub simulation: SimulationParams,
    /// Material and impact model.
    pub process: ProcessParams,
    /// Emitter.
    pub emitter: EmitterParams,
    /// Nozzle pose or path.
    pub nozzle: NozzleParams,
    /// Obstacles, in file order.
    #[serde(rename = "obstacle", default, skip_serializing_if = "Vec::is_empty")]
    pub obstacles: Vec<ObstacleParams>,
    /// Targets, in file order.
    #[serde(rename = "target", default, skip_serializing_if = "Vec::is_empty")]
    pub targets: Vec<TargetParams>,
    /// Simulation domain.
    pub domain: DomainParams,
    /// Outputs.
    pub output: OutputParams,
}
