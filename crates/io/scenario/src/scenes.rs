//! Building blocks for scenes written in code and in tests, so that no program or test
//! pastes its own copy of the same TOML: the default scene's wall and the floor in front of it
//! as `[[target]]` tables (changed where a scene needs: its size, cells, name, role), the
//! nozzle square in front of the wall, the smallest runnable wall scene, a bar obstacle, a
//! one-triangle STL mesh, and helpers that read a fixed scene or its refusal.
//!
//! The frame is the default scene's: z up, the wall in the plane x = 0 facing −x, the floor at
//! z = 0 in front of it. Every builder writes TOML text, which [`Scenario::from_toml`] reads
//! as it reads a file, so a scene built here is checked and resolved like any other.
//!
//! ```
//! use spraysim_scenario::scenes::{NOZZLE_AT_WALL, floor, scenario, wall};
//!
//! let text = format!("{NOZZLE_AT_WALL}{}{}", wall().resolution(64, 64), floor().resolution(40, 30));
//! let sc = scenario(&text, "wall and floor");
//! assert_eq!(sc.targets().len(), 2);
//! ```

use crate::reader::Choice;
use crate::{Scenario, ScenarioError};
use spraysim_engine::motion::Integrator;
use std::fmt;

/// A rectangle `[[target]]` table, written as TOML by `Display`: `name`, `role`, `center`,
/// `normal`, `up`, `size`, `resolution`, `splat_radius` and `coating` in that order (the
/// optional ones only when set), then any extra lines.
#[derive(Clone, Debug, PartialEq)]
pub struct Rectangle {
    name: String,
    /// `None` leaves the default role, a substrate.
    role: Option<&'static str>,
    /// Centre, m.
    center: [f64; 3],
    /// Normal, towards the side that is sprayed.
    normal: [f64; 3],
    /// The face's up direction: its rows run along it.
    up: [f64; 3],
    /// Width and height, m.
    size: [f64; 2],
    /// Cells across and up; `None` leaves the default.
    resolution: Option<[u32; 2]>,
    /// Splat radius, m; `None` leaves the default.
    splat_radius: Option<f64>,
    /// Thickness of the coat the face starts with, m; `None`: bare.
    coating: Option<f64>,
    /// TOML lines written after the keys (an `edges` key, a `[[target.opening]]` table).
    extra: String,
}

/// The default scene's wall: a 2 m × 2 m substrate named `wall` in the plane x = 0, centred
/// 1 m up, facing −x, with z up (cells and splat radius left to the scenario's defaults).
pub fn wall() -> Rectangle {
    Rectangle {
        name: "wall".into(),
        role: None,
        center: [0.0, 0.0, 1.0],
        normal: [-1.0, 0.0, 0.0],
        up: [0.0, 0.0, 1.0],
        size: [2.0, 2.0],
        resolution: None,
        splat_radius: None,
        coating: None,
        extra: String::new(),
    }
}

/// The default scene's floor: a collector named `floor` at z = 0, 4 m wide (along y) and 3 m
/// deep (along x, its up direction, towards the wall), centred 1.5 m in front of the wall.
pub fn floor() -> Rectangle {
    Rectangle {
        name: "floor".into(),
        role: Some("collector"),
        center: [-1.5, 0.0, 0.0],
        normal: [0.0, 0.0, 1.0],
        up: [1.0, 0.0, 0.0],
        size: [4.0, 3.0],
        ..wall()
    }
}

impl Rectangle {
    /// The same face named `name`.
    pub fn named(mut self, name: &str) -> Self {
        self.name = name.into();
        self
    }

    /// The same face as a collector: it records what lands on it, outside the rebound count.
    pub fn collector(mut self) -> Self {
        self.role = Some("collector");
        self
    }

    /// The same face as a substrate, the default role (no `role` line).
    pub fn substrate(mut self) -> Self {
        self.role = None;
        self
    }

    /// The same face centred at `center` (m), its orientation kept.
    pub fn at(mut self, center: [f64; 3]) -> Self {
        self.center = center;
        self
    }

    /// The same face `width` m across and `height` m along its up direction.
    pub fn size(mut self, width: f64, height: f64) -> Self {
        self.size = [width, height];
        self
    }

    /// The same face with `cols` cells across and `rows` up.
    pub fn resolution(mut self, cols: u32, rows: u32) -> Self {
        self.resolution = Some([cols, rows]);
        self
    }

    /// The same face spreading each particle over a disc of `radius` m.
    pub fn splat_radius(mut self, radius: f64) -> Self {
        self.splat_radius = Some(radius);
        self
    }

    /// The same face under a coat `thickness` m thick before the run.
    pub fn coating(mut self, thickness: f64) -> Self {
        self.coating = Some(thickness);
        self
    }

    /// The same face with `lines` (TOML) written after its keys: more keys of the target, or
    /// its sub-tables such as `[[target.opening]]`.
    pub fn with(mut self, lines: &str) -> Self {
        self.extra.push_str(lines);
        if !self.extra.ends_with('\n') {
            self.extra.push('\n');
        }
        self
    }
}

impl fmt::Display for Rectangle {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "[[target]]\nname = \"{}\"", self.name)?;
        if let Some(role) = self.role {
            writeln!(f, "role = \"{role}\"")?;
        }
        writeln!(f, "center = {:?}\nnormal = {:?}\nup = {:?}", self.center, self.normal, self.up)?;
        writeln!(f, "size = {:?}", self.size)?;
        if let Some(resolution) = self.resolution {
            writeln!(f, "resolution = {resolution:?}")?;
        }
        if let Some(radius) = self.splat_radius {
            writeln!(f, "splat_radius = {radius:?}")?;
        }
        if let Some(coating) = self.coating {
            writeln!(f, "coating = {coating:?}")?;
        }
        f.write_str(&self.extra)
    }
}

/// The default scene's nozzle as a `[nozzle]` table: 1 m in front of the wall's centre,
/// spraying square onto it (+x).
pub const NOZZLE_AT_WALL: &str = "[nozzle]\nposition = [-1.0, 0.0, 1.0]\naxis = [1.0, 0.0, 0.0]\n";

/// The smallest runnable wall scene: `duration` s of the default process and nozzle onto the
/// [`wall`] at `cells` × `cells`, as TOML that more tables may follow.
pub fn wall_scene(duration: f64, cells: u32) -> String {
    format!("[simulation]\nduration = {duration:?}\n{}", wall().resolution(cells, cells))
}

/// The flat-panel test of a paint gun's transfer efficiency: a 1 m × 1 m `panel` (the
/// [`wall`] resized, 100 × 100 cells) sprayed square by `gun` at its standard standoff and
/// travel speed, in horizontal passes from the bottom edge to the top that overlap by half the
/// pattern's width, with the fan turned across the passes (roll 90°) and the gun triggered
/// 5 cm beyond each edge; `spawn_rate` particles/s, `seed`, and `extra` TOML lines in
/// `[process]` (say, the paint's volume solids). The run ends 1 s after the last pass, when
/// every droplet has landed or drifted off.
pub fn painted_panel(gun: crate::Gun, spawn_rate: f64, seed: u64, extra: &str) -> Scenario {
    let standoff = gun.standoff();
    let step = 0.5 * gun.pattern_width(standoff);
    let text = |duration: f64| {
        format!(
            "[simulation]\nduration = {duration:?}\nseed = {seed}\n\
             [process]\npreset = \"painting\"\ngun = \"{}\"\n{extra}\n\
             [emitter]\nspawn_rate = {spawn_rate:?}\n\
             [nozzle]\nroll = 90.0\n\
             [nozzle.raster]\ntarget = \"panel\"\nstandoff = {standoff:?}\nspeed = {:?}\nstep_over = {step:?}\nlead = 0.05\n\
             {}[domain]\nmin = [-1.0, -1.5, -0.5]\nmax = [0.5, 1.5, 2.5]\n",
            gun.name(),
            gun.travel_speed(),
            wall().named("panel").size(1.0, 1.0).resolution(100, 100),
        )
    };
    let long = scenario(&text(1e3), "painted panel");
    let end = long.config().nozzle.spray_end();
    scenario(&text((end + 1.0).ceil()), "painted panel")
}

/// The word that selects `integrator` as `[simulation] integrator`, from the table the
/// scenario reads it by.
pub fn integrator_word(integrator: Integrator) -> &'static str {
    integrator.name()
}

/// `text` read as a scenario named `origin`; panics naming the scene and the error, for the
/// fixed scenes of tests and checks, where a refusal is a bug of the scene.
pub fn scenario(text: &str, origin: &str) -> Scenario {
    Scenario::from_toml(text, origin).unwrap_or_else(|e| panic!("the scene `{origin}` is refused: {e}"))
}

/// The default scene for `duration` s with `seed`, its layer weak and barely cohesive (shear
/// strength 300 Pa, cohesion 1 Pa) and analysed every 0.1 s: it fails as it grows, and from
/// about 0.6 s its failures feed each other as released material lands on the layer below.
pub fn failing_layer(duration: f64, seed: u64) -> Scenario {
    Scenario::default_scene()
        .with_all(&[
            ("simulation.duration".into(), duration.into()),
            ("simulation.seed".into(), (seed as i64).into()),
            ("process.cohesion.interval".into(), 0.1.into()),
            ("process.cohesion.shear_strength".into(), 300.0.into()),
            ("process.cohesion.cohesion".into(), 1.0.into()),
        ])
        .unwrap_or_else(|e| panic!("the failing layer is refused: {e}"))
}

/// The key and message of a scenario's refusal; panics when `result` is accepted or refused
/// without a key, naming `what` was refused.
pub fn refusal(result: Result<Scenario, ScenarioError>, what: &str) -> (String, String) {
    match result {
        Ok(_) => panic!("{what}: accepted"),
        Err(ScenarioError::Invalid { key, message, .. }) => (key, message),
        Err(other) => panic!("{what}: refused without a key: {other}"),
    }
}

/// A cylinder `[[obstacle]]` table named `name`: a bar (rebar, a pipe) of `radius` m from
/// `start` to `end` (m), as TOML that more tables may follow.
pub fn bar(name: &str, start: [f64; 3], end: [f64; 3], radius: f64) -> String {
    format!(
        "[[obstacle]]\nname = \"{name}\"\nshape = \"cylinder\"\nstart = {start:?}\nend = {end:?}\nradius = {radius:?}\n"
    )
}

/// An ASCII STL file of one triangle with these corners (m).
pub fn triangle_stl(corners: [[f64; 3]; 3]) -> String {
    let v: Vec<String> = corners.iter().map(|c| format!("vertex {} {} {}", c[0], c[1], c[2])).collect();
    format!("solid t\nfacet normal 0 0 1\nouter loop\n{}\nendloop\nendfacet\nendsolid t\n", v.join("\n"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_wall_and_floor_are_the_default_scenes_targets() {
        let text = format!(
            "[simulation]\nseed = 1\n[process]\npreset = \"shotcrete\"\n[emitter]\ncone_angle = 18.0\n\
             direction = \"uniform_solid_angle\"\n{NOZZLE_AT_WALL}{}{}[output]\ndirectory = \"out\"\n",
            wall().resolution(1024, 1024).splat_radius(0.008).with("role = \"substrate\""),
            floor().resolution(400, 300).splat_radius(0.01),
        );
        assert_eq!(scenario(&text, "built"), Scenario::default_scene());
    }

    #[test]
    fn a_face_is_written_key_by_key_in_a_fixed_order() {
        let face =
            wall().named("panel").size(1.0, 0.5).resolution(10, 5).coating(1e-4).with("edges = \"held\"");
        assert_eq!(
            face.to_string(),
            "[[target]]\nname = \"panel\"\ncenter = [0.0, 0.0, 1.0]\nnormal = [-1.0, 0.0, 0.0]\n\
             up = [0.0, 0.0, 1.0]\nsize = [1.0, 0.5]\nresolution = [10, 5]\ncoating = 0.0001\nedges = \"held\"\n"
        );
        assert!(floor().substrate().to_string().lines().all(|l| !l.starts_with("role")));
    }

    #[test]
    fn a_bar_is_a_cylinder_obstacle_that_a_scene_reads() {
        let table = bar("rebar", [-0.05, -1.0, 1.0], [-0.05, 1.0, 1.0], 0.01);
        assert_eq!(
            table,
            "[[obstacle]]\nname = \"rebar\"\nshape = \"cylinder\"\nstart = [-0.05, -1.0, 1.0]\n\
             end = [-0.05, 1.0, 1.0]\nradius = 0.01\n"
        );
        let sc = scenario(&format!("{}{table}", wall_scene(0.01, 8)), "a bar");
        assert_eq!(sc.obstacles().len(), 1);
    }

    #[test]
    fn each_integrator_is_selected_by_its_word() {
        for integrator in [Integrator::Euler, Integrator::SemiImplicitEuler, Integrator::Exact] {
            let text = format!("[simulation]\nintegrator = \"{}\"\n", integrator_word(integrator));
            assert_eq!(scenario(&text, "integrator").simulation().integrator, integrator);
        }
    }
}
