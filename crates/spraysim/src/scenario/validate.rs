//! Range and consistency checks on a resolved scenario, run before anything is simulated.

use super::params::*;
use crate::emitter::{ApertureShape, DirectionKind, truncated_normal_mass};
use glam::DVec3;

/// A value a scenario may not have: the dotted key (0-based indices) and what is wrong.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("`{key}` {message}")]
pub struct Invalid {
    /// Dotted path of the key, e.g. `simulation.dt` or `target[0].up`.
    pub key: String,
    /// What is wrong with it.
    pub message: String,
}

type Check = Result<(), Invalid>;

fn bad(key: &str, message: impl Into<String>) -> Invalid {
    Invalid { key: key.to_string(), message: message.into() }
}

/// `value` is finite and within `[lo, hi]`.
fn range(key: &str, value: f64, lo: f64, hi: f64, unit: &str) -> Check {
    if !value.is_finite() {
        return Err(bad(key, format!("must be a finite number, got {value}")));
    }
    if value < lo || value > hi {
        return Err(bad(key, format!("must be between {lo} and {hi} {unit}, got {value}")));
    }
    Ok(())
}

/// `value` is finite and within `(0, hi]`.
fn positive(key: &str, value: f64, hi: f64, unit: &str) -> Check {
    if value.is_finite() && value <= 0.0 {
        return Err(bad(key, format!("must be greater than 0 {unit}, got {value}")));
    }
    range(key, value, 0.0, hi, unit)
}

/// Largest coordinate magnitude accepted anywhere, m: beyond any construction site.
const MAX_COORD: f64 = 1e4;

fn point(key: &str, p: [f64; 3]) -> Check {
    if p.iter().any(|c| !c.is_finite()) {
        return Err(bad(key, format!("must be three finite numbers, got {p:?}")));
    }
    if p.iter().any(|c| c.abs() > MAX_COORD) {
        return Err(bad(key, format!("lies more than {MAX_COORD} m from the origin: {p:?}")));
    }
    Ok(())
}

fn direction(key: &str, d: [f64; 3]) -> Result<DVec3, Invalid> {
    if d.iter().any(|c| !c.is_finite()) {
        return Err(bad(key, format!("must be three finite numbers, got {d:?}")));
    }
    let v = DVec3::from_array(d);
    if v.length() < 1e-9 {
        return Err(bad(key, "must not be a zero-length vector"));
    }
    Ok(v.normalize())
}

fn name(key: &str, n: &str, seen: &mut Vec<String>) -> Check {
    if n.is_empty() || !n.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_') {
        return Err(bad(
            key,
            format!("must be non-empty and use only letters, digits, '-' and '_', got {n:?}"),
        ));
    }
    if seen.iter().any(|s| s == n) {
        return Err(bad(key, format!("{n:?} is used twice; names must be unique")));
    }
    seen.push(n.to_string());
    Ok(())
}

/// Two directions that are not parallel (sine of their angle above 1e-6).
fn not_parallel(key: &str, a: DVec3, b: DVec3, what: &str) -> Check {
    if a.cross(b).length() < 1e-6 {
        return Err(bad(key, format!("must not be parallel to {what}")));
    }
    Ok(())
}

impl Scenario {
    /// Checks every value; the first problem found is returned.
    pub fn validate(&self) -> Result<(), Invalid> {
        self.check_simulation()?;
        check_process(&self.process)?;
        self.check_emitter()?;
        self.check_nozzle()?;
        let mut names = Vec::new();
        for (i, t) in self.targets.iter().enumerate() {
            check_target(&format!("target[{i}]"), t, &mut names)?;
        }
        for (i, o) in self.obstacles.iter().enumerate() {
            check_obstacle(&format!("obstacle[{i}]"), o, &mut names)?;
        }
        point("domain.min", self.domain.min)?;
        point("domain.max", self.domain.max)?;
        if (0..3).any(|i| self.domain.min[i] >= self.domain.max[i]) {
            return Err(bad("domain.max", "must be greater than domain.min along every axis"));
        }
        range("output.impact_log", self.output.impact_log, 0.0, 1.0, "")?;
        if self.output.directory.trim().is_empty() {
            return Err(bad("output.directory", "must not be empty"));
        }
        Ok(())
    }

    fn check_simulation(&self) -> Check {
        let s = &self.simulation;
        positive("simulation.dt", s.dt, 0.1, "s")?;
        if s.dt < 1e-7 {
            return Err(bad("simulation.dt", format!("must be at least 1e-7 s, got {}", s.dt)));
        }
        positive("simulation.duration", s.duration, 1e6, "s")?;
        if s.duration / s.dt > 1e9 {
            return Err(bad("simulation.duration", "needs more than 10⁹ steps at this dt"));
        }
        if s.integrator == crate::integrator::Integrator::Exact && self.process.drag != 0.0 {
            return Err(bad(
                "simulation.integrator",
                "\"exact\" has no closed form with drag; set process.drag = 0 or use \"euler\" or \"semi_implicit_euler\"",
            ));
        }
        for g in s.gravity {
            range("simulation.gravity", g, -100.0, 100.0, "m/s²")?;
        }
        if !(1..=1000).contains(&s.max_impacts_per_step) {
            return Err(bad("simulation.max_impacts_per_step", "must be between 1 and 1000"));
        }
        Ok(())
    }

    fn check_emitter(&self) -> Check {
        let e = &self.emitter;
        positive("emitter.spawn_rate", e.spawn_rate, 1e9, "particles/s")?;
        if e.spawn_rate * self.simulation.duration > f64::from(u32::MAX) {
            return Err(bad(
                "emitter.spawn_rate",
                "times the duration exceeds 2³² particles, the most one run can emit",
            ));
        }
        range("emitter.speed", e.speed[0], 0.0, 1e4, "m/s")?;
        range("emitter.speed", e.speed[1], 0.0, 1e4, "m/s")?;
        if e.speed[0] > e.speed[1] {
            return Err(bad(
                "emitter.speed",
                format!("must be [min, max] with min ≤ max, got {:?}", e.speed),
            ));
        }
        if e.speed[1] <= 0.0 {
            return Err(bad("emitter.speed", "must allow a speed above 0 m/s"));
        }
        range("emitter.cone_angle", e.cone_angle, 0.0, 179.0, "degrees")?;
        match e.shape {
            ApertureShape::Point => {}
            ApertureShape::Circle => positive("emitter.diameter", e.diameter, 10.0, "m")?,
            ApertureShape::Rectangle => {
                range("emitter.width", e.width, 0.0, 10.0, "m")?;
                range("emitter.height", e.height, 0.0, 10.0, "m")?;
            }
            ApertureShape::Annulus => {
                range("emitter.inner_diameter", e.inner_diameter, 0.0, 10.0, "m")?;
                positive("emitter.outer_diameter", e.outer_diameter, 10.0, "m")?;
                if e.inner_diameter >= e.outer_diameter {
                    return Err(bad("emitter.inner_diameter", "must be smaller than emitter.outer_diameter"));
                }
            }
        }
        match e.direction {
            DirectionKind::TruncatedNormal => {
                range("emitter.mu", e.mu, -10.0, 10.0, "")?;
                positive("emitter.sigma", e.sigma, 100.0, "")?;
                if truncated_normal_mass(e.mu, e.sigma) < 1e-3 {
                    return Err(bad(
                        "emitter.mu",
                        "and emitter.sigma put less than 0.1 % of the normal inside [0, 1]",
                    ));
                }
            }
            DirectionKind::Fan => {
                range("emitter.fan_wide_angle", e.fan_wide_angle, 0.0, 179.0, "degrees")?;
                range("emitter.fan_narrow_angle", e.fan_narrow_angle, 0.0, 179.0, "degrees")?;
            }
            DirectionKind::UniformPolar | DirectionKind::UniformSolidAngle => {}
        }
        Ok(())
    }

    fn check_nozzle(&self) -> Check {
        let n = &self.nozzle;
        range("nozzle.roll", n.roll, -360.0, 360.0, "degrees")?;
        if let Some(r) = &n.raster {
            if !n.waypoints.is_empty() {
                return Err(bad(
                    "nozzle.raster",
                    "cannot be combined with nozzle.waypoints or nozzle.path_csv",
                ));
            }
            return self.check_raster(r);
        }
        range("nozzle.circle_radius", n.circle_radius, 0.0, 10.0, "m")?;
        range("nozzle.circle_frequency", n.circle_frequency, 0.0, 100.0, "Hz")?;
        let circling = n.circle_radius > 0.0;
        if circling && (n.circle_frequency == 0.0 || !n.waypoints.is_empty() || n.raster.is_some()) {
            return Err(bad(
                "nozzle.circle_radius",
                "needs circle_frequency > 0 and a static nozzle (a raster has its own circle_radius)",
            ));
        }
        if circling && n.circle_frequency * self.simulation.duration * 36.0 > 1e7 {
            return Err(bad("nozzle.circle_frequency", "makes a path of more than 10⁷ waypoints"));
        }
        if n.waypoints.is_empty() {
            point("nozzle.position", n.position)?;
            direction("nozzle.axis", n.axis)?;
            return Ok(());
        }
        let mut previous: Option<(f64, DVec3)> = None;
        for (i, w) in n.waypoints.iter().enumerate() {
            let key = format!("nozzle.waypoints[{i}]");
            range(&format!("{key}.time"), w.time, 0.0, 1e6, "s")?;
            point(&format!("{key}.position"), w.position)?;
            let axis = direction(&format!("{key}.axis"), w.axis)?;
            if let Some((t, a)) = previous {
                if w.time <= t {
                    return Err(bad(&format!("{key}.time"), "must be later than the previous waypoint's"));
                }
                if a.dot(axis) < -0.9999 {
                    return Err(bad(
                        &format!("{key}.axis"),
                        "turns by 180° from the previous waypoint's; the rotation is ambiguous",
                    ));
                }
            }
            previous = Some((w.time, axis));
        }
        Ok(())
    }
}

impl Scenario {
    fn check_raster(&self, r: &RasterParams) -> Check {
        let Some(target) = self.targets.iter().find(|t| t.name == r.target) else {
            let names: Vec<&str> = self.targets.iter().map(|t| t.name.as_str()).collect();
            return Err(bad(
                "nozzle.raster.target",
                format!("must name a target ({}), got {:?}", names.join(", "), r.target),
            ));
        };
        if let Some(size) = r.size {
            for s in size {
                positive("nozzle.raster.size", s, 1e3, "m")?;
            }
        }
        let [w, h] = r.size.unwrap_or(target.size);
        for (i, o) in r.offset.iter().enumerate() {
            range("nozzle.raster.offset", *o, -target.size[i], target.size[i], "m")?;
        }
        positive("nozzle.raster.standoff", r.standoff, 100.0, "m")?;
        positive("nozzle.raster.speed", r.speed, 100.0, "m/s")?;
        positive("nozzle.raster.step_over", r.step_over, 100.0, "m")?;
        range("nozzle.raster.lead", r.lead, 0.0, 100.0, "m")?;
        range("nozzle.raster.circle_radius", r.circle_radius, 0.0, 10.0, "m")?;
        range("nozzle.raster.circle_frequency", r.circle_frequency, 0.0, 100.0, "Hz")?;
        if r.circle_radius > 0.0 && r.circle_frequency == 0.0 {
            return Err(bad(
                "nozzle.raster.circle_frequency",
                "must be above 0 Hz when circle_radius is set",
            ));
        }
        range("nozzle.raster.start_time", r.start_time, 0.0, 1e6, "s")?;
        let span = match r.passes {
            PassDirection::Horizontal => h,
            PassDirection::Vertical => w,
        };
        let passes = span / r.step_over;
        let travel = passes * (w.max(h) + 2.0 * r.lead + r.step_over) / r.speed;
        if passes > 1e5 || travel * r.circle_frequency * 36.0 > 1e7 {
            return Err(bad("nozzle.raster.step_over", "makes a path of more than 10⁷ waypoints"));
        }
        Ok(())
    }
}

fn check_process(p: &ProcessParams) -> Check {
    positive("process.density", p.density, 25_000.0, "kg/m³")?;
    positive("process.flow_rate", p.flow_rate, 10.0, "m³/s")?;
    range("process.drag", p.drag, 0.0, 1e3, "1/m")?;
    positive("process.max_lifetime", p.max_lifetime, 1e6, "s")?;
    range("process.coverage_threshold", p.coverage_threshold, 0.0, 10.0, "m")?;
    range("process.sag_threshold", p.sag_threshold, 0.0, 1.0, "m")?;
    range("process.drip_interval", p.drip_interval, 0.0, 1e6, "s")?;
    let w = &p.window;
    for (key, pair, hi) in
        [("process.window.standoff", w.standoff, 1e3), ("process.window.speed", w.speed, 1e3)]
    {
        range(key, pair[0], 0.0, hi, "")?;
        range(key, pair[1], 0.0, hi, "")?;
        if pair[0] > pair[1] {
            return Err(bad(key, format!("must be [min, max] with min ≤ max, got {pair:?}")));
        }
    }
    range("process.window.max_angle", w.max_angle, 0.0, 90.0, "degrees")?;
    let e = &p.erosion;
    range("process.erosion.finnie_k", e.finnie_k, 0.0, 1.0, "m³/J")?;
    range("process.erosion.oka_e90", e.oka_e90, 0.0, 1.0, "m³/kg")?;
    for (k, v, hi) in [
        ("oka_n1", e.oka_n1, 10.0),
        ("oka_n2", e.oka_n2, 10.0),
        ("oka_hv", e.oka_hv, 100.0),
        ("oka_k2", e.oka_k2, 10.0),
        ("oka_k3", e.oka_k3, 10.0),
    ] {
        range(&format!("process.erosion.{k}"), v, 0.0, hi, "")?;
    }
    positive("process.erosion.oka_v_ref", e.oka_v_ref, 1e4, "m/s")?;
    positive("process.erosion.oka_d_ref", e.oka_d_ref, 1.0, "m")?;
    positive("process.erosion.grain_diameter", e.grain_diameter, 1.0, "m")?;
    let c = &p.cohesion;
    range("process.cohesion.interval", c.interval, 0.0, 1e6, "s")?;
    positive("process.cohesion.tensile_strength", c.tensile_strength, 1e9, "Pa")?;
    positive("process.cohesion.shear_strength", c.shear_strength, 1e9, "Pa")?;
    range("process.cohesion.cohesion", c.cohesion, 0.0, 1e9, "Pa")?;
    check_impact("process.impact", &p.impact)
}

fn check_impact(key: &str, i: &ImpactParams) -> Check {
    range(&format!("{key}.alpha"), i.alpha, 0.0, 1.0, "")?;
    let poly = format!("{key}.rebound_polynomial");
    if i.rebound_polynomial.is_empty() || i.rebound_polynomial.len() > 16 {
        return Err(bad(&poly, "must have between 1 and 16 coefficients"));
    }
    for c in &i.rebound_polynomial {
        range(&poly, *c, -1e6, 1e6, "")?;
    }
    range(&format!("{key}.restitution"), i.restitution, 0.0, 1.0, "")?;
    range(&format!("{key}.scatter_angle"), i.scatter_angle, 0.0, 90.0, "degrees")?;
    range(&format!("{key}.rest_speed"), i.rest_speed, 0.0, 1e3, "m/s")?;
    range(&format!("{key}.rest_max_slope"), i.rest_max_slope, 0.0, 180.0, "degrees")?;
    range(&format!("{key}.cushion_factor"), i.cushion_factor, 0.0, 100.0, "")?;
    range(&format!("{key}.cushion_thickness"), i.cushion_thickness, 0.0, 10.0, "m")
}

/// Checks an override by laying it over neutral values: only the keys it sets can fail.
fn check_override(key: &str, o: &ImpactOverride) -> Check {
    let mut neutral = super::Preset::Shotcrete.process().impact;
    neutral.apply(o);
    check_impact(key, &neutral)
}

fn check_target(key: &str, t: &TargetParams, names: &mut Vec<String>) -> Check {
    name(&format!("{key}.name"), &t.name, names)?;
    point(&format!("{key}.center"), t.center)?;
    let normal = direction(&format!("{key}.normal"), t.normal)?;
    let up = direction(&format!("{key}.up"), t.up)?;
    not_parallel(&format!("{key}.up"), up, normal, "normal")?;
    for s in t.size {
        positive(&format!("{key}.size"), s, 1e3, "m")?;
    }
    for r in t.resolution {
        if !(1..=4096).contains(&r) {
            return Err(bad(
                &format!("{key}.resolution"),
                format!("must be between 1 and 4096 cells per side, got {r}"),
            ));
        }
    }
    range(&format!("{key}.splat_radius"), t.splat_radius, 0.0, t.size[0].min(t.size[1]) / 2.0, "m")?;
    range(&format!("{key}.coating"), t.coating, 0.0, 1.0, "m")?;
    let cells =
        t.splat_radius / (t.size[0] / f64::from(t.resolution[0])).min(t.size[1] / f64::from(t.resolution[1]));
    if cells > 32.0 {
        return Err(bad(
            &format!("{key}.splat_radius"),
            "spans more than 32 cells; lower it or the resolution",
        ));
    }
    check_override(&format!("{key}.impact"), &t.impact)
}

fn check_obstacle(key: &str, o: &ObstacleParams, names: &mut Vec<String>) -> Check {
    name(&format!("{key}.name"), &o.name, names)?;
    let shape_name = format!("{:?}", o.shape).to_lowercase();
    let given: [(&str, bool); 11] = [
        ("file", o.file.is_some()),
        ("scale", o.scale.is_some()),
        ("center", o.center.is_some()),
        ("normal", o.normal.is_some()),
        ("up", o.up.is_some()),
        ("size", o.size.is_some()),
        ("radius", o.radius.is_some()),
        ("start", o.start.is_some()),
        ("end", o.end.is_some()),
        ("x_axis", o.x_axis.is_some()),
        ("y_axis", o.y_axis.is_some()),
    ];
    let (required, optional): (&[&str], &[&str]) = match o.shape {
        ObstacleShape::Plane => (&["center", "normal"], &[]),
        ObstacleShape::Face => (&["center", "normal", "up", "size"], &[]),
        ObstacleShape::Disk => (&["center", "normal", "radius"], &[]),
        ObstacleShape::Sphere => (&["center", "radius"], &[]),
        ObstacleShape::Box => (&["center", "size"], &["x_axis", "y_axis"]),
        ObstacleShape::Cylinder => (&["start", "end", "radius"], &[]),
        ObstacleShape::Mesh => (&["file"], &["center", "scale"]),
    };
    for (field, present) in given {
        let k = format!("{key}.{field}");
        if required.contains(&field) && !present {
            return Err(bad(&k, format!("is required for a {shape_name}")));
        }
        if present && !required.contains(&field) && !optional.contains(&field) {
            return Err(bad(&k, format!("is not used by a {shape_name}")));
        }
    }
    for (field, p) in [("center", o.center), ("start", o.start), ("end", o.end)] {
        if let Some(p) = p {
            point(&format!("{key}.{field}"), p)?;
        }
    }
    for (field, d) in [("normal", o.normal), ("up", o.up), ("x_axis", o.x_axis), ("y_axis", o.y_axis)] {
        if let Some(d) = d {
            direction(&format!("{key}.{field}"), d)?;
        }
    }
    if let (Some(n), Some(u)) = (o.normal, o.up) {
        not_parallel(&format!("{key}.up"), DVec3::from_array(u), DVec3::from_array(n), "normal")?;
    }
    let x = DVec3::from_array(o.x_axis.unwrap_or([1.0, 0.0, 0.0]));
    let y = DVec3::from_array(o.y_axis.unwrap_or([0.0, 1.0, 0.0]));
    if o.shape == ObstacleShape::Box {
        not_parallel(&format!("{key}.y_axis"), y, x, "x_axis")?;
    }
    if let Some(s) = o.scale {
        positive(&format!("{key}.scale"), s, 1e6, "")?;
    }
    if let Some(r) = o.radius {
        positive(&format!("{key}.radius"), r, 1e3, "m")?;
    }
    if let Some(size) = &o.size {
        let want = if o.shape == ObstacleShape::Box { 3 } else { 2 };
        if size.len() != want {
            return Err(bad(
                &format!("{key}.size"),
                format!("must have {want} values for a {shape_name}, got {}", size.len()),
            ));
        }
        for s in size {
            positive(&format!("{key}.size"), *s, 1e4, "m")?;
        }
    }
    if let (Some(a), Some(b)) = (o.start, o.end)
        && DVec3::from_array(a).distance(DVec3::from_array(b)) < 1e-9
    {
        return Err(bad(&format!("{key}.end"), "must differ from start"));
    }
    check_override(&format!("{key}.impact"), &o.impact)
}
