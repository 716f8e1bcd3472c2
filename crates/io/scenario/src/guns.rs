//! Paint gun presets (`[process] gun`): what each atomiser sets over the painting preset — the
//! spray's shape and speeds, its droplet sizes, its air jet, its flow rate and its working
//! window — with the sources of each number.
//!
//! The numbers sit inside published ranges; where a source gives no single value (the
//! effective outlet of a gun's air, an airless fan's entrained air), the estimate and how it
//! was made are stated beside it. docs/painting.md tabulates them and shows the transfer
//! efficiency each gives on a flat panel against its published range.

use crate::params::{
    AirDefaults, AirKind, ApertureKind, DirectionKind, DragLawName, DropletsKind, EmitterDefaults, JetParams,
    ProcessDefaults,
};
use crate::reader::choices;
use serde::Serialize;

/// Growth of a round jet's half-width per unit distance (Hussein, Capp & George 1994; Pope
/// 2000, Table 5.1).
const ROUND_JET_SPREAD: f64 = 0.094;

/// A paint spray gun.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Gun {
    /// Conventional air spray: fine droplets atomised by much fast air.
    Air,
    /// High volume, low pressure: at most 0.7 bar at the air cap, slower air and droplets.
    Hvlp,
    /// Airless: paint forced through a tip at 100–300 bar; coarse droplets, no gun air (the
    /// fan drags its own air along).
    Airless,
    /// Air-assisted airless: an airless tip at 30–100 bar with a little air to finish the fan.
    AirAssistedAirless,
    /// High-speed rotary bell (without electrostatics): a spinning cup, shaped by an annular
    /// curtain of air.
    RotaryBell,
}

choices!(Gun {
    "air" => Gun::Air,
    "hvlp" => Gun::Hvlp,
    "airless" => Gun::Airless,
    "air_assisted_airless" => Gun::AirAssistedAirless,
    "rotary_bell" => Gun::RotaryBell,
});

/// What a gun sets.
struct GunTable {
    /// Paint flow while spraying, m³/s.
    flow_rate: f64,
    /// Recommended standoff `[min, max]`, m; the standard standoff is its middle.
    standoff: [f64; 2],
    /// Travel speed `[min, max]`, m/s.
    speed: [f64; 2],
    /// The spray: full fan angles `[wide, narrow]` in degrees, or a cone's full angle as
    /// `[angle, angle]` with `cone = true`.
    angles: [f64; 2],
    cone: bool,
    /// Droplet speed at the nozzle `[min, max]`, m/s.
    droplet_speed: [f64; 2],
    /// Droplet sizes: the law, D₃₂ (m) and its spread (σ_g, or Rosin–Rammler n).
    droplets: (DropletsKind, f64, f64),
    /// The air jet: U₀ (m/s) and d₀ (m). Its spread follows the spray: the air shapes the
    /// fan, whose edge lies about two half-widths out, so S = tan(θ/2)/2 along each axis of
    /// the fan (θ its full angle there), and at least a round jet's 0.094.
    air: (f64, f64),
}

impl Gun {
    /// All guns, in documentation order.
    pub const ALL: [Gun; 5] = [Gun::Air, Gun::Hvlp, Gun::Airless, Gun::AirAssistedAirless, Gun::RotaryBell];

    /// The name used in scenario files.
    pub fn name(self) -> &'static str {
        crate::reader::Choice::name(self)
    }

    /// The gun's standard standoff: the middle of its recommended window, m.
    pub fn standoff(self) -> f64 {
        let [lo, hi] = self.table().standoff;
        0.5 * (lo + hi)
    }

    /// Width of the spray's pattern at `standoff` (m), m: the fan's (or cone's) full angle
    /// seen from the nozzle.
    pub fn pattern_width(self, standoff: f64) -> f64 {
        2.0 * standoff * (0.5 * self.table().angles[0]).to_radians().tan()
    }

    /// The gun's standard travel speed: the middle of its recommended range, m/s.
    pub fn travel_speed(self) -> f64 {
        let [lo, hi] = self.table().speed;
        0.5 * (lo + hi)
    }

    /// The published range of transfer efficiency on large flat work, `[min, max]` as shares,
    /// and its source; `None` where no range applies to the model (a bell's published figures
    /// are with electrostatics, which spraysim does not model).
    pub fn published_transfer_efficiency(self) -> Option<([f64; 2], &'static str)> {
        const PRIMER: &str = "\"A Primer on Transfer Efficiency\", Products Finishing; physics-notes";
        match self {
            Gun::Air => Some(([0.20, 0.40], PRIMER)),
            Gun::Hvlp => Some(([0.50, 0.60], PRIMER)),
            Gun::Airless => Some(([0.40, 0.50], PRIMER)),
            Gun::AirAssistedAirless => Some(([0.60, 0.80], PRIMER)),
            Gun::RotaryBell => None,
        }
    }

    #[rustfmt::skip]
    fn table(self) -> GunTable {
        use DropletsKind::{LogNormal, RosinRammler};
        match self {
            Gun::Air => GunTable {
                flow_rate: 5.0e-6, standoff: [0.15, 0.25], speed: [0.2, 0.5],
                angles: [50.0, 15.0], cone: false, droplet_speed: [30.0, 60.0],
                droplets: (LogNormal, 16e-6, 1.9),
                air: (250.0, 0.005),
            },
            Gun::Hvlp => GunTable {
                flow_rate: 4.2e-6, standoff: [0.10, 0.20], speed: [0.3, 0.6],
                angles: [45.0, 15.0], cone: false, droplet_speed: [20.0, 35.0],
                droplets: (LogNormal, 22e-6, 1.9),
                air: (150.0, 0.008),
            },
            Gun::Airless => GunTable {
                flow_rate: 1.67e-5, standoff: [0.25, 0.35], speed: [0.3, 1.0],
                angles: [50.0, 8.0], cone: false, droplet_speed: [70.0, 110.0],
                droplets: (RosinRammler, 50e-6, 2.0),
                air: (10.0, 0.010),
            },
            Gun::AirAssistedAirless => GunTable {
                flow_rate: 8.3e-6, standoff: [0.20, 0.30], speed: [0.3, 0.8],
                angles: [45.0, 10.0], cone: false, droplet_speed: [40.0, 70.0],
                droplets: (RosinRammler, 55e-6, 2.3),
                air: (80.0, 0.006),
            },
            Gun::RotaryBell => GunTable {
                flow_rate: 4.2e-6, standoff: [0.20, 0.30], speed: [0.3, 0.8],
                angles: [40.0, 40.0], cone: true, droplet_speed: [20.0, 40.0],
                droplets: (LogNormal, 25e-6, 1.5),
                air: (60.0, 0.016),
            },
        }
    }

    /// Where each of the gun's numbers comes from.
    pub fn sources(self) -> &'static str {
        match self {
            Gun::Air => {
                "D₃₂ 15–40 µm, D_v50 39–52 µm (Bonner, Products Finishing); air choked at the cap, \
                 250–330 m/s, d₀ from about 350 NL/min; 20–25 cm standoff (Goodheart-Willcox, \
                 Auto Collision Repair & Refinishing; NAVAIR 01-1A-509-2); 150–500 mL/min"
            }
            Gun::Hvlp => {
                "≤ 0.7 bar at the cap (SCAQMD Rule 1151; 40 CFR 63.801), 150–250 m/s, d₀ from about \
                 500 NL/min; D₃₂ 20–45 µm; 10–20 cm standoff (Goodheart-Willcox)"
            }
            Gun::Airless => {
                "D₃₂ 50–120 µm, air spray 20–50 vs airless 70–150 µm (Kansai Altan glossary); \
                 tip speed C_d √(2Δp/ρ) ≈ 110 m/s at 150 bar; fan width at 30 cm (Graco tip guide); \
                 no gun air: the fan's entrained air, estimated"
            }
            Gun::AirAssistedAirless => {
                "30–100 bar tip plus low-pressure air; D₃₂ 30–60 µm; 20–30 cm standoff"
            }
            Gun::RotaryBell => {
                "cup 50–70 mm, shaping air 50–150 m/s, D₃₂ 15–40 µm, narrow (σ_g ≈ 1.5) \
                 (Andersson et al. 2013; Ray & Henshaw 2018; Wilson et al. 2018)"
            }
        }
    }

    /// The gun's `[process]` defaults over the painting preset's `d`.
    pub(crate) fn process(self, mut d: ProcessDefaults) -> ProcessDefaults {
        let t = self.table();
        d.flow_rate = t.flow_rate;
        d.window.standoff = t.standoff;
        d.window.speed = t.speed;
        d
    }

    /// The gun's own air speed at the outlet, U₀, m/s.
    pub fn air_speed(self) -> f64 {
        self.table().air.0
    }

    /// True for a gun whose air atomises the paint (air, HVLP): its droplet size follows the
    /// air's speed.
    pub fn air_atomised(self) -> bool {
        matches!(self, Gun::Air | Gun::Hvlp)
    }

    /// The gun's `[emitter]` defaults over the painting preset's `d`, for its air jet at
    /// `air_speed` (m/s). An air-atomised gun's Sauter mean diameter scales as 1/U₀ from its
    /// own (D₃₂, U₀): the leading term of plain-jet airblast atomisation (Lorenzetto & Lefebvre
    /// 1977; Lefebvre & McDonell, Atomization and Sprays, 2017), so faster air makes finer
    /// droplets.
    pub(crate) fn emitter(self, mut d: EmitterDefaults, air_speed: f64) -> EmitterDefaults {
        let t = self.table();
        d.speed = t.droplet_speed;
        if t.cone {
            // A bell's droplets leave its rim and the shaping air turns them forward: a cone
            // from the jet's virtual origin, densest on its axis.
            d.shape = ApertureKind::Point;
            d.direction = DirectionKind::TruncatedNormal;
            d.mu = 0.0;
            d.sigma = 0.5;
            d.cone_angle = t.angles[0];
        } else {
            d.shape = ApertureKind::Point;
            d.direction = DirectionKind::Fan;
            [d.fan_wide_angle, d.fan_narrow_angle] = t.angles;
        }
        let (law, d32, spread) = t.droplets;
        d.droplets = law;
        d.sauter_mean = if self.air_atomised() && air_speed > 0.0 { d32 * t.air.0 / air_speed } else { d32 };
        match law {
            DropletsKind::LogNormal => d.gsd = spread,
            _ => d.rr_spread = spread,
        }
        d
    }

    /// The gun's `[air]` defaults.
    pub(crate) fn air(self) -> AirDefaults {
        let t = self.table();
        let (speed, outlet_diameter) = t.air;
        let spread = t.angles.map(|a| ((a / 2.0).to_radians().tan() / 2.0).max(ROUND_JET_SPREAD));
        AirDefaults {
            model: AirKind::Jet,
            jet: JetParams {
                speed,
                outlet_diameter,
                spread,
                drag: DragLawName::SchillerNaumann,
                ..JetParams::AIR_20C
            },
        }
    }
}
