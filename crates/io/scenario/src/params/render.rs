//! `[output] render`: 3D views of the run, drawn at given times and as an animation. The
//! scenario only describes them; the renderer (the `spraysim` command's `render` feature) draws
//! them, so this crate stays free of any GPU code.

use crate::params::Preset;
use crate::reader::{Check, Num, NumberOrWord, Read, Section, bad, choices};
use serde::Serialize;
use serde::ser::{SerializeMap, Serializer};

/// When a still is taken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RenderTime {
    /// At this simulated time, s (the nearest step).
    At(f64),
    /// After the last step.
    End,
}

impl Serialize for RenderTime {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            RenderTime::At(t) => s.serialize_f64(*t),
            RenderTime::End => s.serialize_str("end"),
        }
    }
}

/// A camera placed from the scene's own geometry.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ViewPreset {
    /// Square onto the first target, from the side the spray comes from.
    Front,
    /// Along the first target's face, from its right.
    Side,
    /// From above, the first target at the top of the image.
    Top,
    /// Three-quarter view from the front, the right and above.
    #[default]
    Iso,
    /// Behind the nozzle, looking along the spray.
    Follow,
}

choices!(ViewPreset {
    "front" => ViewPreset::Front,
    "side" => ViewPreset::Side,
    "top" => ViewPreset::Top,
    "iso" => ViewPreset::Iso,
    "follow" => ViewPreset::Follow,
});

impl ViewPreset {
    /// Every preset, in documentation order.
    pub const ALL: [ViewPreset; 5] =
        [ViewPreset::Front, ViewPreset::Side, ViewPreset::Top, ViewPreset::Iso, ViewPreset::Follow];

    /// The name used in scenario files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            ViewPreset::Front => "front",
            ViewPreset::Side => "side",
            ViewPreset::Top => "top",
            ViewPreset::Iso => "iso",
            ViewPreset::Follow => "follow",
        }
    }
}

/// Where the camera stands.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RenderCamera {
    /// Placed by a preset so that the whole scene is in view.
    Preset(ViewPreset),
    /// Placed by hand.
    Custom {
        /// Eye position, m.
        eye: [f64; 3],
        /// Point looked at, m.
        target: [f64; 3],
    },
}

/// What colours the particles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ParticleColoring {
    /// In flight from the nozzle, rebounded, or released by a failure.
    #[default]
    State,
    /// Speed, from 0 to the emitter's highest speed.
    Speed,
}

choices!(ParticleColoring { "state" => ParticleColoring::State, "speed" => ParticleColoring::Speed });

/// `[output] render`: 3D views drawn during a run and written with its outputs.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderParams {
    /// Times of the stills.
    pub at: Vec<RenderTime>,
    /// Frames of an animation spread evenly over the run (0: none).
    pub frames: u32,
    /// Where the camera stands.
    pub camera: RenderCamera,
    /// Vertical field of view, degrees.
    pub fov: f64,
    /// Image width and height, px.
    pub size: [u32; 2],
    /// What colours the particles.
    pub color_by: ParticleColoring,
    /// Particle size, px.
    pub point_size: f64,
    /// Factor on the deposit's thickness where it is drawn raised off its surface (1: true
    /// scale; 0: flat).
    pub exaggeration: f64,
    /// Most particles drawn; a larger swarm is drawn as an even sample of this many.
    pub max_particles: u64,
}

/// Default particle size in pixels for each process: coarse wet-mix lumps are drawn larger
/// than paint droplets, grit in between (`point_size` sets any other).
pub fn point_size(preset: Preset) -> f64 {
    match preset {
        Preset::Shotcrete => 3.0,
        Preset::Painting => 1.0,
        Preset::Blasting => 2.0,
    }
}

/// Limits of the render settings, shared by the scenario reader and the command line.
const MAX_SIDE: f64 = 8192.0;

impl RenderParams {
    /// The default views of a run of `preset`: one still at the end, three-quarter view,
    /// 1280 × 720 px, particles coloured by state.
    pub fn defaults(preset: Preset) -> RenderParams {
        RenderParams {
            at: vec![RenderTime::End],
            frames: 0,
            camera: RenderCamera::Preset(ViewPreset::Iso),
            fov: 40.0,
            size: [1280, 720],
            color_by: ParticleColoring::State,
            point_size: point_size(preset),
            exaggeration: 1.0,
            max_particles: 2_000_000,
        }
    }

    /// Checks every setting against a run of `duration` seconds; an error names the setting
    /// (`at`, `size`, …) and what is wrong with it.
    pub fn check(&self, duration: f64) -> Result<(), (&'static str, String)> {
        for t in &self.at {
            if let RenderTime::At(t) = *t
                && !(t.is_finite() && (0.0..=duration).contains(&t))
            {
                return Err((
                    "at",
                    format!(
                        "must be times within the run, 0 to {} s, or \"end\"; got {}",
                        Num(duration),
                        Num(t)
                    ),
                ));
            }
        }
        if self.at.is_empty() && self.frames == 0 {
            return Err(("at", "asks for no still and there is no animation (frames = 0)".into()));
        }
        if self.frames > 10_000 {
            return Err(("frames", format!("must be at most 10000, got {}", self.frames)));
        }
        if self.size.iter().any(|&s| !(16.0..=MAX_SIDE).contains(&f64::from(s))) {
            return Err(("size", format!("must be two sizes of 16 to 8192 px, got {:?}", self.size)));
        }
        if !(self.fov.is_finite() && self.fov > 1.0 && self.fov < 170.0) {
            return Err(("fov", format!("must be between 1 and 170 degrees, got {}", Num(self.fov))));
        }
        if !(self.point_size.is_finite() && (1.0..=64.0).contains(&self.point_size)) {
            return Err(("point_size", format!("must be between 1 and 64 px, got {}", Num(self.point_size))));
        }
        if !(self.exaggeration.is_finite() && (0.0..=1000.0).contains(&self.exaggeration)) {
            return Err((
                "exaggeration",
                format!("must be between 0 and 1000, got {}", Num(self.exaggeration)),
            ));
        }
        if !(1..=100_000_000).contains(&self.max_particles) {
            return Err(("max_particles", format!("must be between 1 and 10⁸, got {}", self.max_particles)));
        }
        if let RenderCamera::Custom { eye, target } = self.camera {
            let d = glam::DVec3::from_array(eye) - glam::DVec3::from_array(target);
            if !(d.is_finite() && d.length() > 1e-6) {
                return Err(("eye", "must differ from target".into()));
            }
        }
        Ok(())
    }
}

impl Serialize for RenderParams {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(None)?;
        m.serialize_entry("at", &self.at)?;
        m.serialize_entry("frames", &self.frames)?;
        match &self.camera {
            RenderCamera::Preset(p) => m.serialize_entry("camera", p)?,
            RenderCamera::Custom { eye, target } => {
                m.serialize_entry("eye", eye)?;
                m.serialize_entry("target", target)?;
            }
        }
        m.serialize_entry("fov", &self.fov)?;
        m.serialize_entry("size", &self.size)?;
        m.serialize_entry("color_by", &self.color_by)?;
        m.serialize_entry("point_size", &self.point_size)?;
        m.serialize_entry("exaggeration", &self.exaggeration)?;
        m.serialize_entry("max_particles", &self.max_particles)?;
        m.end()
    }
}

/// Reads `[output] render`: `true` (the defaults), `false` or absent (none), or a table of
/// settings; `preset` gives the default particle size, `duration` (s) bounds the times.
pub(crate) fn read_render(s: &Section<'_>, preset: Preset, duration: f64) -> Read<Option<RenderParams>> {
    if !s.has("render") {
        return Ok(None);
    }
    if !s.is_table("render") {
        let on = s.boolean("render", false)?;
        return Ok(on.then(|| RenderParams::defaults(preset)));
    }
    let Some(r) = s.table("render")? else { return Ok(None) };
    let d = RenderParams::defaults(preset);
    let at = match r.numbers_or_words("at", &["end"], 1000)? {
        None => d.at,
        Some(items) => items
            .into_iter()
            .map(|i| match i {
                NumberOrWord::Number(t) => RenderTime::At(t),
                NumberOrWord::Word(_) => RenderTime::End,
            })
            .collect(),
    };
    let camera = if r.has("eye") || r.has("target") {
        if r.has("camera") {
            return bad(
                &r.key("camera"),
                "is a preset; `eye` and `target` place the camera by hand: give one or the other",
            );
        }
        RenderCamera::Custom { eye: r.point("eye", None)?, target: r.point("target", None)? }
    } else {
        RenderCamera::Preset(r.choice("camera", Some(ViewPreset::Iso))?)
    };
    let size = r.numbers("size", Some([1280.0, 720.0]), Check::Within(16.0, MAX_SIDE), "px")?;
    if size.iter().any(|x| x.fract() != 0.0) {
        return bad(&r.key("size"), format!("must be whole numbers of pixels, got {size:?}"));
    }
    let p = RenderParams {
        at,
        frames: r.integer("frames", Some(0), 0, 10_000)? as u32,
        camera,
        fov: r.number("fov", Some(d.fov), Check::Within(1.0, 170.0), "degrees")?,
        size: [size[0] as u32, size[1] as u32],
        color_by: r.choice("color_by", Some(ParticleColoring::State))?,
        point_size: r.number("point_size", Some(d.point_size), Check::Within(1.0, 64.0), "px")?,
        exaggeration: r.number("exaggeration", Some(1.0), Check::Within(0.0, 1000.0), "")?,
        max_particles: r.integer("max_particles", Some(2_000_000), 1, 100_000_000)? as u64,
    };
    if let Err((field, message)) = p.check(duration) {
        return bad(&r.key(field), message);
    }
    r.finish("`[output] render`")?;
    Ok(Some(p))
}
