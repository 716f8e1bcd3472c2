//! `[emitter]`: the nozzle's aperture, spawn rate, speeds, spray cone and droplet sizes.

use crate::reader::{Check, Choice, Read, Section, bad, choices};
use serde::Serialize;

/// Shape of the aperture, in the plane perpendicular to the spray axis; sizes in m.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "shape", rename_all = "snake_case")]
pub enum Aperture {
    /// All particles start at the nozzle point (air spray gun).
    Point,
    /// Uniform over a disk (shotcrete, blasting nozzles).
    Circle {
        /// Diameter, m.
        diameter: f64,
    },
    /// Uniform over a rectangle (fan nozzles).
    Rectangle {
        /// Side along the nozzle's width axis, m.
        width: f64,
        /// Side across it, m.
        height: f64,
    },
    /// Uniform over a ring (rotary bells).
    Annulus {
        /// Inner diameter, m.
        inner_diameter: f64,
        /// Outer diameter, m.
        outer_diameter: f64,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ApertureKind {
    Point,
    Circle,
    Rectangle,
    Annulus,
}

choices!(ApertureKind {
    "point" => ApertureKind::Point,
    "circle" => ApertureKind::Circle,
    "rectangle" => ApertureKind::Rectangle,
    "annulus" => ApertureKind::Annulus,
});

/// How directions spread within the spray cone; angles in degrees.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "direction", rename_all = "snake_case")]
pub enum DirectionLaw {
    /// θ = θ_half · s, s ~ U(0, 1): concentrated at the axis (paper Fig. 3a).
    UniformPolar {
        /// Full angle of the spray cone, degrees.
        cone_angle: f64,
    },
    /// θ = θ_half · s, s ~ N(μ, σ) truncated to [0, 1] (paper Fig. 3b).
    TruncatedNormal {
        /// Full angle of the spray cone, degrees.
        cone_angle: f64,
        /// Mean μ of θ/θ_half.
        mu: f64,
        /// Standard deviation σ of θ/θ_half.
        sigma: f64,
    },
    /// cos θ ~ U(cos θ_half, 1): uniform flux per steradian.
    UniformSolidAngle {
        /// Full angle of the spray cone, degrees.
        cone_angle: f64,
    },
    /// Independent uniform angles in the two planes through the axis.
    Fan {
        /// Full angle along the nozzle's width axis, degrees.
        fan_wide_angle: f64,
        /// Full angle across it, degrees.
        fan_narrow_angle: f64,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum DirectionKind {
    UniformPolar,
    TruncatedNormal,
    UniformSolidAngle,
    Fan,
}

choices!(DirectionKind {
    "uniform_polar" => DirectionKind::UniformPolar,
    "truncated_normal" => DirectionKind::TruncatedNormal,
    "uniform_solid_angle" => DirectionKind::UniformSolidAngle,
    "fan" => DirectionKind::Fan,
});

/// The sizes of the droplets (or grains) the particles stand for, by volume (see the engine's
/// `emission::DropletSizes`: every particle carries the same volume, and its diameter sets its
/// drag in the gun's air).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "droplets", rename_all = "snake_case")]
pub enum DropletsLaw {
    /// Sizes are not modelled (no air to feel them).
    None,
    /// Every droplet has one diameter.
    Fixed {
        /// Diameter, m.
        droplet_diameter: f64,
    },
    /// Log-normal in number with geometric standard deviation σ_g.
    LogNormal {
        /// Sauter mean diameter D₃₂, m.
        sauter_mean: f64,
        /// Geometric standard deviation σ_g (> 1).
        gsd: f64,
    },
    /// Rosin–Rammler in volume, with spread exponent n.
    RosinRammler {
        /// Sauter mean diameter D₃₂, m.
        sauter_mean: f64,
        /// Spread exponent n (> 1; larger is narrower).
        rr_spread: f64,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum DropletsKind {
    None,
    Fixed,
    LogNormal,
    RosinRammler,
}

choices!(DropletsKind {
    "none" => DropletsKind::None,
    "fixed" => DropletsKind::Fixed,
    "log_normal" => DropletsKind::LogNormal,
    "rosin_rammler" => DropletsKind::RosinRammler,
});

impl DropletsLaw {
    /// The engine's size distribution (`None` where sizes are not modelled).
    pub fn distribution(&self) -> Option<spraysim_engine::emission::SizeDistribution> {
        use spraysim_engine::emission::SizeDistribution as D;
        match *self {
            DropletsLaw::None => None,
            DropletsLaw::Fixed { droplet_diameter } => Some(D::Fixed { diameter: droplet_diameter }),
            DropletsLaw::LogNormal { sauter_mean, gsd } => Some(D::LogNormal { sauter_mean, gsd }),
            DropletsLaw::RosinRammler { sauter_mean, rr_spread } => {
                Some(D::RosinRammler { sauter_mean, spread: rr_spread })
            }
        }
    }
}

/// `[emitter]`: where on the nozzle particles start, how many, how fast and in which
/// directions.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EmitterParams {
    /// The nozzle's opening, where particles start: `shape` and its size keys.
    #[serde(flatten)]
    pub aperture: Aperture,
    /// Particles emitted per second while spraying, 1/s.
    pub spawn_rate: f64,
    /// Emission speed range `[min, max]`, sampled uniformly, m/s.
    pub speed: [f64; 2],
    /// How directions spread about the spray axis: `direction` and its angle keys.
    #[serde(flatten)]
    pub direction: DirectionLaw,
    /// The droplet sizes: `droplets` and its keys.
    #[serde(flatten)]
    pub droplets: DropletsLaw,
}

impl EmitterParams {
    /// Full angle of the spray cone, degrees (the wider fan angle for a fan).
    pub fn cone_angle(&self) -> f64 {
        match self.direction {
            DirectionLaw::UniformPolar { cone_angle }
            | DirectionLaw::TruncatedNormal { cone_angle, .. }
            | DirectionLaw::UniformSolidAngle { cone_angle } => cone_angle,
            DirectionLaw::Fan { fan_wide_angle, fan_narrow_angle } => fan_wide_angle.max(fan_narrow_angle),
        }
    }
}

/// Every emitter key of a preset, whatever the shape and direction law, to fill what a file
/// leaves out.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct EmitterDefaults {
    pub shape: ApertureKind,
    pub diameter: f64,
    pub width: f64,
    pub height: f64,
    pub inner_diameter: f64,
    pub outer_diameter: f64,
    pub spawn_rate: f64,
    pub speed: [f64; 2],
    pub cone_angle: f64,
    pub direction: DirectionKind,
    pub mu: f64,
    pub sigma: f64,
    pub fan_wide_angle: f64,
    pub fan_narrow_angle: f64,
    pub droplets: DropletsKind,
    pub droplet_diameter: f64,
    pub sauter_mean: f64,
    pub gsd: f64,
    pub rr_spread: f64,
}

/// Reads `[emitter]` over a preset's defaults `d`; `duration` (s) bounds the particle count.
pub(crate) fn read(s: &Section<'_>, d: &EmitterDefaults, duration: f64) -> Read<EmitterParams> {
    let size = |k: &str, v: f64| s.number(k, Some(v), Check::Positive(10.0), "m");
    let shape = s.choice("shape", Some(d.shape))?;
    let aperture = match shape {
        ApertureKind::Point => Aperture::Point,
        ApertureKind::Circle => Aperture::Circle { diameter: size("diameter", d.diameter)? },
        ApertureKind::Rectangle => Aperture::Rectangle {
            width: s.number("width", Some(d.width), Check::Within(0.0, 10.0), "m")?,
            height: s.number("height", Some(d.height), Check::Within(0.0, 10.0), "m")?,
        },
        ApertureKind::Annulus => {
            let inner = s.number("inner_diameter", Some(d.inner_diameter), Check::Within(0.0, 10.0), "m")?;
            let outer = size("outer_diameter", d.outer_diameter)?;
            if inner >= outer {
                return bad(&s.key("inner_diameter"), "must be smaller than emitter.outer_diameter");
            }
            Aperture::Annulus { inner_diameter: inner, outer_diameter: outer }
        }
    };
    let spawn_rate = s.number("spawn_rate", Some(d.spawn_rate), Check::Positive(1e9), "particles/s")?;
    if spawn_rate * duration > f64::from(u32::MAX) {
        return bad(
            &s.key("spawn_rate"),
            "times the duration exceeds 2³² particles, the most one run can emit",
        );
    }
    let speed = s.numbers("speed", Some(d.speed), Check::Within(0.0, 1e4), "m/s")?;
    if speed[0] > speed[1] {
        return bad(&s.key("speed"), format!("must be [min, max] with min ≤ max, got {speed:?}"));
    }
    if speed[1] <= 0.0 {
        return bad(&s.key("speed"), "must allow a speed above 0 m/s");
    }
    let direction = read_direction(s, d)?;
    let droplets = read_droplets(s, d)?;
    s.finish(&format!(
        "an emitter with shape = \"{}\", direction = \"{}\" and droplets = \"{}\"",
        shape.name(),
        s.choice("direction", Some(d.direction))?.name(),
        s.choice("droplets", Some(d.droplets))?.name()
    ))?;
    Ok(EmitterParams { aperture, spawn_rate, speed, direction, droplets })
}

fn read_droplets(s: &Section<'_>, d: &EmitterDefaults) -> Read<DropletsLaw> {
    let diameter = |k: &str, v: f64| s.number(k, Some(v), Check::Positive(0.1), "m");
    let law = match s.choice("droplets", Some(d.droplets))? {
        DropletsKind::None => DropletsLaw::None,
        DropletsKind::Fixed => {
            DropletsLaw::Fixed { droplet_diameter: diameter("droplet_diameter", d.droplet_diameter)? }
        }
        DropletsKind::LogNormal => {
            let sauter_mean = diameter("sauter_mean", d.sauter_mean)?;
            let gsd = s.number("gsd", Some(d.gsd), Check::Within(1.0, 3.0), "")?;
            if gsd <= 1.0 {
                return bad(&s.key("gsd"), "must exceed 1 (1 is a single size: use droplets = \"fixed\")");
            }
            DropletsLaw::LogNormal { sauter_mean, gsd }
        }
        DropletsKind::RosinRammler => {
            let sauter_mean = diameter("sauter_mean", d.sauter_mean)?;
            let rr_spread = s.number("rr_spread", Some(d.rr_spread), Check::Within(1.0, 100.0), "")?;
            if rr_spread < 1.2 {
                return bad(
                    &s.key("rr_spread"),
                    "must be at least 1.2 (at n ≤ 1 the Sauter mean diameter is 0, and near 1 the largest droplets are metres across)",
                );
            }
            DropletsLaw::RosinRammler { sauter_mean, rr_spread }
        }
    };
    Ok(law)
}

fn read_direction(s: &Section<'_>, d: &EmitterDefaults) -> Read<DirectionLaw> {
    let cone = || s.number("cone_angle", Some(d.cone_angle), Check::Within(0.0, 179.0), "degrees");
    Ok(match s.choice("direction", Some(d.direction))? {
        DirectionKind::UniformPolar => DirectionLaw::UniformPolar { cone_angle: cone()? },
        DirectionKind::UniformSolidAngle => DirectionLaw::UniformSolidAngle { cone_angle: cone()? },
        DirectionKind::TruncatedNormal => {
            let cone_angle = cone()?;
            let mu = s.number("mu", Some(d.mu), Check::Within(-10.0, 10.0), "")?;
            let sigma = s.number("sigma", Some(d.sigma), Check::Positive(100.0), "")?;
            if spraysim_engine::emission::truncated_normal_mass(mu, sigma) < 1e-3 {
                return bad(
                    &s.key("mu"),
                    "and emitter.sigma put less than 0.1 % of the normal inside [0, 1]",
                );
            }
            DirectionLaw::TruncatedNormal { cone_angle, mu, sigma }
        }
        DirectionKind::Fan => DirectionLaw::Fan {
            fan_wide_angle: s.number(
                "fan_wide_angle",
                Some(d.fan_wide_angle),
                Check::Within(0.0, 179.0),
                "degrees",
            )?,
            fan_narrow_angle: s.number(
                "fan_narrow_angle",
                Some(d.fan_narrow_angle),
                Check::Within(0.0, 179.0),
                "degrees",
            )?,
        },
    })
}
