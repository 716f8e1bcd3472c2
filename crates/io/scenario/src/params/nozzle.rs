//! `[nozzle]`: where the spray comes from: a static pose, a circling nozzle, time-stamped
//! waypoints (or a robot tool path read into them), or a raster over a target.

use super::targets::TargetParams;
use crate::reader::{Check, Read, Section, bad, choices};
use serde::Serialize;
use spraysim_engine::emission::{PassDirection, RasterPlan};
use std::path::Path;

choices!(PassDirection { "horizontal" => PassDirection::Horizontal, "vertical" => PassDirection::Vertical });

/// `[nozzle]`: how the nozzle moves and whether its own velocity adds to the particles'.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct NozzleParams {
    /// Roll of the aperture about the axis, degrees. At 0 the width axis is horizontal.
    pub roll: f64,
    /// Add the nozzle's own velocity to the particles it emits.
    pub add_velocity: bool,
    /// How the nozzle moves.
    #[serde(flatten)]
    pub motion: NozzleMotion,
}

/// How the nozzle moves; the keys a file gives say which.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum NozzleMotion {
    /// Stays put and sprays throughout.
    Static {
        /// Position, m.
        position: [f64; 3],
        /// Spray axis (any length, not zero).
        axis: [f64; 3],
    },
    /// Circles `position` in the plane perpendicular to `axis` (the nozzleman's circles).
    Circling {
        /// Centre of the circle, m.
        position: [f64; 3],
        /// Spray axis.
        axis: [f64; 3],
        /// Radius, m.
        circle_radius: f64,
        /// Revolutions per second, Hz.
        circle_frequency: f64,
    },
    /// Through time-stamped poses (from `[[nozzle.waypoints]]` or `path_csv`).
    Waypoints {
        /// The poses, by strictly increasing time.
        waypoints: Vec<WaypointParams>,
    },
    /// A zig-zag over a target.
    Raster {
        /// The target, the rectangle of it covered and the passes (`[nozzle.raster]`).
        raster: RasterParams,
    },
}

/// One `[[nozzle.waypoints]]` entry.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WaypointParams {
    /// Time, s; strictly increasing along the list.
    pub time: f64,
    /// Nozzle position, m.
    pub position: [f64; 3],
    /// Spray axis (any length, not zero).
    pub axis: [f64; 3],
    /// Whether the nozzle sprays from here to the next waypoint.
    pub spray: bool,
}

/// `[nozzle.raster]`: a zig-zag pass over a rectangle of a target's face at a standoff, with an
/// optional circular motion superposed (the shotcrete nozzle technique).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RasterParams {
    /// Name of the target whose face is covered.
    pub target: String,
    /// The raster over that face.
    #[serde(flatten)]
    pub plan: RasterPlan,
}

/// The static position and axis when a file gives none, m.
pub(crate) const DEFAULT_POSITION: [f64; 3] = [-1.0, 0.0, 1.0];
const DEFAULT_AXIS: [f64; 3] = [1.0, 0.0, 0.0];

/// Reads `[nozzle]`; `base` is the folder a tool path is read from, `targets` those a raster
/// may cover, `duration` (s) bounds the path's size.
pub(crate) fn read(
    s: &Section<'_>,
    base: &Path,
    targets: &[TargetParams],
    duration: f64,
) -> Read<NozzleParams> {
    let roll = s.number("roll", Some(0.0), Check::Within(-360.0, 360.0), "degrees")?;
    let add_velocity = s.boolean("add_velocity", false)?;
    one_motion(s)?;
    let listed = s.has("waypoints") || s.has("path_csv");
    let motion = if let Some(r) = s.table("raster")? {
        NozzleMotion::Raster { raster: read_raster(&r, targets)? }
    } else if listed {
        NozzleMotion::Waypoints { waypoints: read_waypoints(s, base)? }
    } else {
        read_pose(s, duration)?
    };
    let what = match motion {
        NozzleMotion::Static { .. } => "a static nozzle",
        NozzleMotion::Circling { .. } => "a circling nozzle",
        NozzleMotion::Waypoints { .. } => "a nozzle on waypoints",
        NozzleMotion::Raster { .. } => "a nozzle on a raster (the raster has its own circle_radius)",
    };
    s.finish(what)?;
    Ok(NozzleParams { roll, add_velocity, motion })
}

/// The motions of a nozzle, each named as messages name it, with the keys that choose it (the
/// others, `roll` and `add_velocity`, go with every motion).
const MOTIONS: [(&str, &[&str]); 3] = [
    ("a raster nozzle", &["raster"]),
    ("a nozzle on waypoints", &["waypoints", "path_csv"]),
    ("a static or circling nozzle", &["position", "axis", "circle_radius", "circle_frequency"]),
];

/// Refuses a `[nozzle]` that gives the keys of two motions (a raster and a static `axis`): a
/// nozzle moves one way. The key blamed is one an override set, if any (so that the refusal
/// names the override), else the one that chooses the motion read first (`raster`, then the
/// waypoints). When an override set it, the message says how to change the motion instead:
/// by replacing the whole table, without the other motion's keys.
fn one_motion(s: &Section<'_>) -> Read<()> {
    let given: Vec<(usize, &str)> = (MOTIONS.iter().enumerate())
        .flat_map(|(m, (_, keys))| keys.iter().filter(|k| s.has(k)).map(move |k| (m, *k)))
        .collect();
    let Some(&(first, _)) = given.first() else { return Ok(()) };
    if given.iter().all(|(m, _)| *m == first) {
        return Ok(());
    }
    let (motion, blamed) = given.iter().copied().find(|(_, k)| s.set_by_override(k)).unwrap_or(given[0]);
    let others: Vec<&str> = given.iter().filter(|(m, _)| *m != motion).map(|(_, k)| *k).collect();
    let other_motions: Vec<usize> = given.iter().filter(|(m, _)| *m != motion).map(|(m, _)| *m).collect();
    let named = others.iter().map(|k| format!("`{}`", s.key(k))).collect::<Vec<_>>();
    let named = match named.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => named.join(""),
    };
    let keys = if others.len() == 1 { "a key" } else { "keys" };
    let whose = if other_motions.iter().all(|m| *m == other_motions[0]) {
        format!("{keys} of {}", MOTIONS[other_motions[0]].0)
    } else {
        format!("{keys} of other motions")
    };
    let raster = given.iter().any(|(_, k)| *k == "raster");
    let circles = if raster && given.iter().any(|(_, k)| k.starts_with("circle_")) {
        " (a raster circles with its own circle_radius and circle_frequency, in [nozzle.raster])"
    } else {
        ""
    };
    let remedy = if s.set_by_override(blamed) {
        format!(
            "to change how it moves, set the whole table, which replaces the scenario's: {}={}",
            s.path(),
            s.inline_without(&others)
        )
    } else {
        "give the keys of one motion only".to_string()
    };
    bad(
        &s.key(blamed),
        format!(
            "belongs to {}, but [{}] also has {named}, {whose}{circles}: a nozzle moves one way only; {remedy}",
            MOTIONS[motion].0,
            s.path(),
        ),
    )
}

/// A static or circling nozzle.
fn read_pose(s: &Section<'_>, duration: f64) -> Read<NozzleMotion> {
    let position = s.point("position", Some(DEFAULT_POSITION))?;
    let axis = s.direction("axis", Some(DEFAULT_AXIS))?;
    let radius = s.number("circle_radius", Some(0.0), Check::Within(0.0, 10.0), "m")?;
    let frequency = s.number("circle_frequency", Some(0.0), Check::Within(0.0, 100.0), "Hz")?;
    if radius == 0.0 {
        return Ok(NozzleMotion::Static { position, axis });
    }
    if frequency == 0.0 {
        return bad(&s.key("circle_radius"), "needs circle_frequency > 0 and a static nozzle");
    }
    if frequency * duration * 36.0 > 1e7 {
        return bad(&s.key("circle_frequency"), "makes a path of more than 10⁷ waypoints");
    }
    Ok(NozzleMotion::Circling { position, axis, circle_radius: radius, circle_frequency: frequency })
}

/// The unit of a tool path's positions (`nozzle.path_csv`'s `units`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum LengthUnit {
    /// Metres, as everywhere else in a scenario.
    Metres,
    /// Millimetres, as robot controllers often write them.
    Millimetres,
}

choices!(LengthUnit { "m" => LengthUnit::Metres, "mm" => LengthUnit::Millimetres });

impl LengthUnit {
    /// How many of the unit make a metre.
    pub(crate) fn per_metre(self) -> f64 {
        match self {
            LengthUnit::Metres => 1.0,
            LengthUnit::Millimetres => 1000.0,
        }
    }
}

/// `nozzle.path_csv`, if given: the file (relative to the scenario's folder) and the unit of
/// its positions. A string is the file, in metres; a table gives `file` and `units`.
fn read_path_csv(s: &Section<'_>) -> Read<Option<(String, LengthUnit)>> {
    if !s.is_table("path_csv") {
        let file = s.string("path_csv", Some(""))?;
        return Ok((!file.is_empty()).then_some((file, LengthUnit::Metres)));
    }
    let Some(t) = s.table("path_csv")? else { return Ok(None) };
    let file = t.string("file", None)?;
    if file.is_empty() {
        return bad(&t.key("file"), "must name a CSV file");
    }
    let units = t.choice("units", Some(LengthUnit::Metres))?;
    t.finish("nozzle.path_csv")?;
    Ok(Some((file, units)))
}

fn read_waypoints(s: &Section<'_>, base: &Path) -> Read<Vec<WaypointParams>> {
    let csv = read_path_csv(s)?;
    let listed = s.tables("waypoints")?;
    let waypoints = if let Some((csv, units)) = csv {
        if !listed.is_empty() {
            return bad(&s.key("path_csv"), "cannot be combined with nozzle.waypoints");
        }
        let poses = crate::tool_path::read(&base.join(&csv), units).map_err(|e| crate::reader::Invalid {
            key: s.key("path_csv"),
            message: format!("cannot be used: {e}"),
        })?;
        poses
            .into_iter()
            .map(|p| WaypointParams { time: p.time, position: p.position, axis: p.axis, spray: p.spray })
            .collect()
    } else {
        listed.iter().map(read_waypoint).collect::<Read<Vec<_>>>()?
    };
    if waypoints.is_empty() {
        return bad(&s.key("waypoints"), "must hold at least one waypoint");
    }
    let mut previous: Option<&WaypointParams> = None;
    for (i, w) in waypoints.iter().enumerate() {
        let key = format!("{}[{i}]", s.key("waypoints"));
        crate::reader::number_in(&format!("{key}.time"), w.time, Check::Within(0.0, 1e6), "s")?;
        if let Some(p) = previous {
            if w.time <= p.time {
                return bad(&format!("{key}.time"), "must be later than the previous waypoint's");
            }
            let (a, b) =
                (glam::DVec3::from_array(p.axis).normalize(), glam::DVec3::from_array(w.axis).normalize());
            if a.dot(b) < -0.9999 {
                return bad(
                    &format!("{key}.axis"),
                    "turns by 180° from the previous waypoint's; the rotation is ambiguous",
                );
            }
        }
        previous = Some(w);
    }
    Ok(waypoints)
}

fn read_waypoint(w: &Section<'_>) -> Read<WaypointParams> {
    let p = WaypointParams {
        time: w.number("time", None, Check::Within(0.0, 1e6), "s")?,
        position: w.point("position", None)?,
        axis: w.direction("axis", None)?,
        spray: w.boolean("spray", true)?,
    };
    w.finish("a waypoint")?;
    Ok(p)
}

fn read_raster(r: &Section<'_>, targets: &[TargetParams]) -> Read<RasterParams> {
    let name = r.string("target", None)?;
    let Some(target) = targets.iter().find(|t| t.name == name) else {
        let names: Vec<&str> = targets.iter().map(|t| t.name.as_str()).collect();
        return bad(&r.key("target"), format!("must name a target ({}), got {name:?}", names.join(", ")));
    };
    let full = target.size();
    let size = r.numbers("size", Some(full), Check::Positive(1e3), "m")?;
    let offset = r.numbers("offset", Some([0.0, 0.0]), Check::Within(-1e3, 1e3), "m")?;
    for i in 0..2 {
        crate::reader::number_in(&r.key("offset"), offset[i], Check::Within(-full[i], full[i]), "m")?;
    }
    let d = RasterPlan::default();
    let p = RasterPlan {
        size,
        offset,
        standoff: r.number("standoff", Some(d.standoff), Check::Positive(100.0), "m")?,
        speed: r.number("speed", Some(d.speed), Check::Positive(100.0), "m/s")?,
        step_over: r.number("step_over", Some(d.step_over), Check::Positive(100.0), "m")?,
        passes: r.choice("passes", Some(d.passes))?,
        lead: r.number("lead", Some(d.lead), Check::Within(0.0, 100.0), "m")?,
        spray_on_turns: r.boolean("spray_on_turns", d.spray_on_turns)?,
        circle_radius: r.number("circle_radius", Some(d.circle_radius), Check::Within(0.0, 10.0), "m")?,
        circle_frequency: r.number(
            "circle_frequency",
            Some(d.circle_frequency),
            Check::Within(0.0, 100.0),
            "Hz",
        )?,
        start_time: r.number("start_time", Some(d.start_time), Check::Within(0.0, 1e6), "s")?,
    };
    r.finish("[nozzle.raster]")?;
    if p.circle_radius > 0.0 && p.circle_frequency == 0.0 {
        return bad(&r.key("circle_frequency"), "must be above 0 Hz when circle_radius is set");
    }
    let span = match p.passes {
        PassDirection::Horizontal => p.size[1],
        PassDirection::Vertical => p.size[0],
    };
    let passes = span / p.step_over;
    let travel = passes * (p.size[0].max(p.size[1]) + 2.0 * p.lead + p.step_over) / p.speed;
    if passes > 1e5 || travel * p.circle_frequency * 36.0 > 1e7 {
        return bad(&r.key("step_over"), "makes a path of more than 10⁷ waypoints");
    }
    Ok(RasterParams { target: name, plan: p })
}
