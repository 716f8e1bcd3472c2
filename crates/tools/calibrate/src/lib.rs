//! Calibration: fit emitter parameters (μ and σ of the direction law, optionally the cone angle
//! and the speed range) so that the simulated deposition profile matches a measured one, as the
//! paper did for wet-mix shotcrete.
//!
//! The objective is the root-mean-square difference between the simulated and the measured
//! profile, as a fraction of the measured peak, minimised by Nelder–Mead. Every evaluation runs
//! the scenario with the same seed (common random numbers): each particle draws the same
//! random numbers whatever the parameters, and the emitter maps them to angles and speeds
//! monotonically, so the objective changes smoothly with the parameters instead of jumping
//! with the sampling noise.

pub mod files;
pub mod profile;

pub use profile::{MeasuredProfile, ProfileSampler, ProfileShape, Quantity};

use argmin::core::{CostFunction, Executor, State};
use argmin::solver::neldermead::NelderMead;
use glam::DVec3;
use spraysim_engine::deposit::{HeightField, RectangleSurface, Surface};
use spraysim_engine::{SetupError, Simulation};
use spraysim_scenario::{DirectionLaw, Scenario, ScenarioError, Value};
use std::cell::RefCell;
use std::path::PathBuf;

/// Why a calibration could not run.
#[derive(Debug, thiserror::Error)]
pub enum CalibrationError {
    /// The profile file could not be read.
    #[error("{path}: cannot read the profile: {source}", path = path.display())]
    Read {
        /// The profile file that could not be read.
        path: PathBuf,
        /// Underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The profile file is malformed.
    #[error("{location}: {message}")]
    Profile {
        /// `file:line`, or the file.
        location: String,
        /// What is wrong.
        message: String,
    },
    /// The settings do not fit the scenario or the profile.
    #[error("{0}")]
    Settings(String),
    /// The scenario could not be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The fitted values make an invalid scenario.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// The optimiser failed.
    #[error("optimiser: {0}")]
    Optimiser(String),
}

/// An emitter parameter that calibration can fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FitParam {
    /// `emitter.mu`, μ of the truncated-normal direction law, in units of θ_half.
    Mu,
    /// `emitter.sigma`, σ of the truncated-normal direction law, in units of θ_half.
    Sigma,
    /// `emitter.cone_angle`, the full cone angle, degrees.
    ConeAngle,
    /// `emitter.speed[0]`, the lowest emission speed, m/s.
    SpeedMin,
    /// `emitter.speed[1]`, the highest emission speed, m/s.
    SpeedMax,
}

impl FitParam {
    /// Every parameter, in the order of [`FitParam::name`]s.
    pub const ALL: [FitParam; 5] =
        [FitParam::Mu, FitParam::Sigma, FitParam::ConeAngle, FitParam::SpeedMin, FitParam::SpeedMax];

    /// Name on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            FitParam::Mu => "mu",
            FitParam::Sigma => "sigma",
            FitParam::ConeAngle => "cone_angle",
            FitParam::SpeedMin => "speed_min",
            FitParam::SpeedMax => "speed_max",
        }
    }

    /// Parses a [`FitParam::name`].
    pub fn parse(name: &str) -> Option<FitParam> {
        FitParam::ALL.into_iter().find(|p| p.name() == name)
    }

    /// Unit of the value.
    pub fn unit(self) -> &'static str {
        match self {
            FitParam::Mu | FitParam::Sigma => "θ_half",
            FitParam::ConeAngle => "°",
            FitParam::SpeedMin | FitParam::SpeedMax => "m/s",
        }
    }

    /// The parameter's value in `sc`.
    fn get(self, sc: &Scenario) -> f64 {
        let e = sc.emitter();
        match (self, &e.direction) {
            (FitParam::Mu, DirectionLaw::TruncatedNormal { mu, .. }) => *mu,
            (FitParam::Sigma, DirectionLaw::TruncatedNormal { sigma, .. }) => *sigma,
            (FitParam::Mu | FitParam::Sigma, _) => f64::NAN,
            (FitParam::ConeAngle, _) => e.cone_angle(),
            (FitParam::SpeedMin, _) => e.speed[0],
            (FitParam::SpeedMax, _) => e.speed[1],
        }
    }

    /// The scenario key the parameter sets (both speeds are `emitter.speed`).
    fn key(self) -> &'static str {
        match self {
            FitParam::Mu => "emitter.mu",
            FitParam::Sigma => "emitter.sigma",
            FitParam::ConeAngle => "emitter.cone_angle",
            FitParam::SpeedMin | FitParam::SpeedMax => "emitter.speed",
        }
    }

    /// The range searched: physically meaningful and accepted by validation.
    fn bounds(self) -> (f64, f64) {
        match self {
            FitParam::Mu => (0.0, 1.0),
            FitParam::Sigma => (0.01, 2.0),
            FitParam::ConeAngle => (0.5, 170.0),
            FitParam::SpeedMin | FitParam::SpeedMax => (0.1, 500.0),
        }
    }

    /// Size of the starting simplex along this parameter, from its start value.
    fn initial_step(self, start: f64) -> f64 {
        match self {
            FitParam::Mu => 0.1,
            FitParam::Sigma => (0.5 * start).max(0.05),
            _ => (0.2 * start).max(1.0),
        }
    }
}

/// How to compare and how long to search.
#[derive(Clone, Debug, PartialEq)]
pub struct CalibrationSettings {
    /// Parameters to fit, each at most once; at least one.
    pub fit: Vec<FitParam>,
    /// Name of the target whose layer is compared; `None`: the first target.
    pub target: Option<String>,
    /// How the profile runs across the target.
    pub shape: ProfileShape,
    /// Profile centre in the target's (right, up) coordinates, m; `None`: where the nozzle's
    /// axis at time 0 meets the target (its centre if the axis misses it).
    pub center: Option<[f64; 2]>,
    /// Width of the band of cells averaged for a line profile, m.
    pub band: f64,
    /// Compare shapes only: scale the simulated profile by the least-squares factor before
    /// comparing (for measurements whose absolute level is unknown).
    pub shape_only: bool,
    /// Nelder–Mead iterations at most.
    pub max_iterations: u64,
    /// Stop when the objective's standard deviation over the simplex falls below this, as a
    /// fraction of the measured peak.
    pub tolerance: f64,
    /// Worker threads per simulation (0: every core).
    pub threads: usize,
}

impl Default for CalibrationSettings {
    fn default() -> Self {
        CalibrationSettings {
            fit: vec![FitParam::Mu, FitParam::Sigma],
            target: None,
            shape: ProfileShape::Radial,
            center: None,
            band: 0.02,
            shape_only: false,
            max_iterations: 100,
            tolerance: 1e-5,
            threads: 0,
        }
    }
}

/// The paper's three error measures, as fractions of the measured peak.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct ProfileErrors {
    /// Largest absolute difference.
    pub max_abs: f64,
    /// Root-mean-square difference.
    pub rms: f64,
    /// Mean absolute difference.
    pub mean_abs: f64,
}

impl ProfileErrors {
    /// Errors of `simulated` against `measured`, relative to `peak`.
    pub fn between(simulated: &[f64], measured: &[f64], peak: f64) -> ProfileErrors {
        let n = measured.len().max(1) as f64;
        let d: Vec<f64> = simulated.iter().zip(measured).map(|(s, m)| (s - m).abs()).collect();
        ProfileErrors {
            max_abs: d.iter().copied().fold(0.0, f64::max) / peak,
            rms: (d.iter().map(|x| x * x).sum::<f64>() / n).sqrt() / peak,
            mean_abs: d.iter().sum::<f64>() / n / peak,
        }
    }
}

/// One evaluation of the objective, for progress displays.
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    /// 1 for the first.
    pub index: usize,
    /// Parameter values, in the order of the settings' `fit`.
    pub values: Vec<f64>,
    /// RMS error at these values, fraction of the measured peak.
    pub rms: f64,
    /// Lowest RMS error so far, fraction of the measured peak.
    pub best_rms: f64,
}

/// The outcome of a calibration.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Calibration {
    /// The parameters fitted, in the order of `initial` and `fitted`.
    pub params: Vec<FitParam>,
    /// Their values at the start, in the parameters' units.
    pub initial: Vec<f64>,
    /// Their fitted values.
    pub fitted: Vec<f64>,
    /// Errors at the start.
    pub initial_errors: ProfileErrors,
    /// Errors at the fitted values.
    pub errors: ProfileErrors,
    /// Simulations run by the fit, each one evaluation of the error.
    pub evaluations: usize,
    /// Nelder–Mead iterations.
    pub iterations: u64,
    /// Why the optimiser stopped.
    pub termination: String,
    /// What the profile measures.
    pub quantity: Quantity,
    /// Profile positions, m.
    pub positions: Vec<f64>,
    /// Measured values, m or kg/m².
    pub measured: Vec<f64>,
    /// Simulated values at the start, same unit.
    pub initial_simulated: Vec<f64>,
    /// Simulated values at the fitted parameters, same unit.
    pub simulated: Vec<f64>,
    /// Factor applied to the simulated profile (1 unless `shape_only`).
    pub scale: f64,
    /// The scenario with the fitted values.
    #[serde(skip)]
    pub scenario: Scenario,
}

/// What the objective needs, fixed across evaluations.
struct Problem<'a, F: FnMut(&Evaluation)> {
    base: &'a Scenario,
    settings: &'a CalibrationSettings,
    measured: &'a MeasuredProfile,
    target: usize,
    sampler: ProfileSampler,
    /// Thickness → the measured quantity (1, or the density).
    to_quantity: f64,
    state: RefCell<Progress<F>>,
}

struct Progress<F> {
    count: usize,
    best: f64,
    report: F,
    failure: Option<CalibrationError>,
}

/// A simulated profile: values in the measured quantity and the shape-only scale applied.
struct Simulated {
    values: Vec<f64>,
    scale: f64,
}

impl<F: FnMut(&Evaluation)> Problem<'_, F> {
    /// The scenario at `values`, clamped to the parameters' bounds (or the reason it is
    /// invalid, say a σ too small for μ), and how far outside them `values` were (relative to
    /// each range), which the objective penalises.
    fn scenario_at(&self, values: &[f64]) -> (Result<Scenario, ScenarioError>, f64) {
        let mut excess = 0.0;
        let mut overrides: Vec<(String, Value)> = Vec::new();
        let mut speed = self.base.emitter().speed;
        for (&p, &v) in self.settings.fit.iter().zip(values) {
            let (lo, hi) = p.bounds();
            let clamped = if v.is_nan() { lo } else { v.clamp(lo, hi) };
            excess += (v - clamped).abs() / (hi - lo);
            match p {
                FitParam::SpeedMin => speed[0] = clamped,
                FitParam::SpeedMax => speed[1] = clamped,
                _ => overrides.push((p.key().to_string(), Value::Number(clamped))),
            }
        }
        if self.settings.fit.iter().any(|p| matches!(p, FitParam::SpeedMin | FitParam::SpeedMax)) {
            if speed[0] > speed[1] {
                excess += (speed[0] - speed[1]) / speed[1];
                speed = [speed[1], speed[1]];
            }
            overrides.push(("emitter.speed".to_string(), Value::from(speed)));
        }
        (self.base.with_all(&overrides), excess)
    }

    fn simulate(&self, sc: &Scenario) -> Result<Simulated, CalibrationError> {
        let mut sim = sc.build()?;
        sim.set_threads(self.settings.threads)?;
        sim.run(|_| {});
        let raw = self.sampler.sample(field(&sim, self.target)?.thickness());
        let mut values: Vec<f64> = raw.iter().map(|t| t * self.to_quantity).collect();
        let mut scale = 1.0;
        if self.settings.shape_only {
            let ss: f64 = values.iter().map(|s| s * s).sum();
            let sm: f64 = values.iter().zip(&self.measured.values).map(|(s, m)| s * m).sum();
            if ss > 0.0 {
                scale = sm / ss;
                values.iter_mut().for_each(|s| *s *= scale);
            }
        }
        Ok(Simulated { values, scale })
    }

    fn rms(&self, simulated: &[f64]) -> f64 {
        ProfileErrors::between(simulated, &self.measured.values, self.measured.peak()).rms
    }
}

impl<F: FnMut(&Evaluation)> CostFunction for Problem<'_, F> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, values: &Vec<f64>) -> Result<f64, argmin::core::Error> {
        let (sc, excess) = self.scenario_at(values);
        // Values validation refuses (say a σ too small for μ) cost more than any real fit.
        let rms = match sc {
            Ok(sc) => match self.simulate(&sc) {
                Ok(s) => self.rms(&s.values),
                Err(e) => {
                    let message = e.to_string();
                    self.state.borrow_mut().failure = Some(e);
                    return Err(argmin::core::Error::msg(message));
                }
            },
            Err(_) => 10.0,
        };
        let mut state = self.state.borrow_mut();
        state.count += 1;
        state.best = state.best.min(rms);
        let evaluation = Evaluation { index: state.count, values: values.clone(), rms, best_rms: state.best };
        (state.report)(&evaluation);
        Ok(rms + 10.0 * excess)
    }
}

/// The rectangle of target `target`, whose layer calibration compares.
fn rectangle(sim: &Simulation, target: usize) -> Result<&RectangleSurface, CalibrationError> {
    match sim.targets().get(target).map(|t| &t.surface) {
        Some(Surface::Rectangle(r)) => Ok(r),
        Some(_) => Err(CalibrationError::Settings(
            "the first target is not a rectangle: calibration compares profiles on a flat face".into(),
        )),
        None => Err(CalibrationError::Settings("the scenario has no target to compare with".into())),
    }
}

/// The heightfield of target `target`.
fn field(sim: &Simulation, target: usize) -> Result<&HeightField, CalibrationError> {
    Ok(&rectangle(sim, target)?.field)
}

/// Where the nozzle's axis at time 0 meets the target, in its (right, up) coordinates, m; the
/// target's centre when the axis points away from it.
fn aim_point(sim: &Simulation, target: usize) -> Result<(f64, f64), CalibrationError> {
    let face = &rectangle(sim, target)?.chart;
    let (frame, _) = sim.nozzle().at(0.0);
    let facing = frame.axis.dot(face.normal);
    if facing >= -1e-9 {
        return Ok((0.0, 0.0));
    }
    let s = (face.center - frame.position).dot(face.normal) / facing;
    if s < 0.0 {
        return Ok((0.0, 0.0));
    }
    let hit: DVec3 = frame.position + frame.axis * s - face.center;
    Ok((hit.dot(face.right), hit.dot(face.up)))
}

/// Fits `settings.fit` so that `scenario`'s layer on the chosen target matches `measured`.
/// `progress` sees every evaluation. The returned scenario holds the fitted values.
pub fn calibrate(
    scenario: &Scenario,
    measured: &MeasuredProfile,
    settings: &CalibrationSettings,
    progress: impl FnMut(&Evaluation),
) -> Result<Calibration, CalibrationError> {
    check_settings(scenario, settings)?;
    let (target, sampler) = profile_bins(scenario, measured, settings)?;
    let to_quantity = match measured.quantity {
        Quantity::Thickness => 1.0,
        Quantity::MassPerArea => scenario.process().density,
    };
    let initial: Vec<f64> = settings.fit.iter().map(|p| p.get(scenario)).collect();
    let problem = Problem {
        base: scenario,
        settings,
        measured,
        target,
        sampler,
        to_quantity,
        state: RefCell::new(Progress { count: 0, best: f64::INFINITY, report: progress, failure: None }),
    };

    let initial_sim = problem.simulate(scenario)?;
    // With nothing on the profile, every nearby parameter gives the same error: the simplex
    // "converges" at once, to nothing. Refuse instead of reporting that as a fit.
    if initial_sim.values.iter().all(|&v| v == 0.0) {
        return Err(CalibrationError::Settings(format!(
            "nothing the nozzle sprays reaches the profile on target `{}` at the starting values (is the nozzle \
             aimed at the target?): there is nothing to fit",
            scenario.targets().get(target).map_or("?", |t| t.name.as_str())
        )));
    }
    let solver = NelderMead::new(start_simplex(&initial, &settings.fit))
        .with_sd_tolerance(settings.tolerance)
        .map_err(|e| CalibrationError::Optimiser(e.to_string()))?;
    let run = Executor::new(problem, solver).configure(|s| s.max_iters(settings.max_iterations)).run();
    let result = match run {
        Ok(r) => r,
        Err(e) => return Err(CalibrationError::Optimiser(e.to_string())),
    };
    let state = result.state();
    let best = state.get_best_param().cloned().unwrap_or_else(|| initial.clone());
    let iterations = state.get_iter();
    let termination =
        state.get_termination_reason().map_or_else(|| "unknown".into(), |r| r.text().to_string());
    let problem =
        result.problem.problem.ok_or_else(|| CalibrationError::Optimiser("lost the problem".into()))?;
    if let Some(e) = problem.state.borrow_mut().failure.take() {
        return Err(e);
    }
    let fitted_scenario = problem.scenario_at(&best).0?;
    let fitted: Vec<f64> = settings.fit.iter().map(|p| p.get(&fitted_scenario)).collect();
    let fitted_sim = problem.simulate(&fitted_scenario)?;
    if fitted_sim.values.iter().all(|&v| v == 0.0) {
        return Err(CalibrationError::Settings(format!(
            "the fit ended where nothing reaches the profile on target `{}` ({termination}): no fit found",
            scenario.targets().get(target).map_or("?", |t| t.name.as_str())
        )));
    }
    let peak = measured.peak();
    Ok(Calibration {
        params: settings.fit.clone(),
        initial,
        fitted,
        initial_errors: ProfileErrors::between(&initial_sim.values, &measured.values, peak),
        errors: ProfileErrors::between(&fitted_sim.values, &measured.values, peak),
        evaluations: problem.state.borrow().count,
        iterations,
        termination,
        quantity: measured.quantity,
        positions: measured.positions.clone(),
        measured: measured.values.clone(),
        initial_simulated: initial_sim.values,
        simulated: fitted_sim.values,
        scale: fitted_sim.scale,
        scenario: fitted_scenario,
    })
}

/// Refuses settings that cannot work with `scenario`, before anything runs.
fn check_settings(scenario: &Scenario, settings: &CalibrationSettings) -> Result<(), CalibrationError> {
    let bad = |m: String| Err(CalibrationError::Settings(m));
    if settings.fit.is_empty() {
        return bad("nothing to fit: name at least one parameter".into());
    }
    for (i, p) in settings.fit.iter().enumerate() {
        if settings.fit[..i].contains(p) {
            return bad(format!("`{}` is named twice", p.name()));
        }
    }
    let direction_law = settings.fit.iter().any(|p| matches!(p, FitParam::Mu | FitParam::Sigma));
    if direction_law && !matches!(scenario.emitter().direction, DirectionLaw::TruncatedNormal { .. }) {
        return bad(format!(
            "μ and σ shape only the `truncated_normal` direction law; the scenario's emitter uses `{}`",
            serde_json::to_value(&scenario.emitter().direction)
                .ok()
                .and_then(|v| v.get("direction").and_then(|d| d.as_str()).map(str::to_string))
                .unwrap_or_default()
        ));
    }
    if !(settings.band > 0.0 && settings.band.is_finite()) {
        return bad(format!("the band width must be a positive length in m, got {}", settings.band));
    }
    if !(settings.tolerance > 0.0 && settings.tolerance.is_finite()) {
        return bad(format!("the tolerance must be positive, got {}", settings.tolerance));
    }
    if let Some(c) = settings.center
        && !c.iter().all(|x| x.is_finite())
    {
        return bad("the profile centre must be finite".into());
    }
    Ok(())
}

/// The starting simplex: `initial` and one vertex a step away along each parameter.
fn start_simplex(initial: &[f64], fit: &[FitParam]) -> Vec<Vec<f64>> {
    let mut simplex = vec![initial.to_vec()];
    for (i, p) in fit.iter().enumerate() {
        let mut vertex = initial.to_vec();
        let (lo, hi) = p.bounds();
        let step = p.initial_step(initial[i]);
        // Step inwards when the start sits near the upper bound.
        vertex[i] = if initial[i] + step <= hi { initial[i] + step } else { (initial[i] - step).max(lo) };
        simplex.push(vertex);
    }
    simplex
}

/// The target compared (its index) and the bins of the measured profile over its cells.
fn profile_bins(
    scenario: &Scenario,
    measured: &MeasuredProfile,
    settings: &CalibrationSettings,
) -> Result<(usize, ProfileSampler), CalibrationError> {
    let probe = scenario.build()?;
    let target = match &settings.target {
        None => 0,
        Some(name) => probe.targets().iter().position(|t| &t.name == name).ok_or_else(|| {
            let names: Vec<&str> = probe.targets().iter().map(|t| t.name.as_str()).collect();
            CalibrationError::Settings(format!("no target named `{name}`; the scenario has {names:?}"))
        })?,
    };
    let center = match settings.center {
        Some(c) => (c[0], c[1]),
        None => aim_point(&probe, target)?,
    };
    let sampler = ProfileSampler::new(
        field(&probe, target)?,
        &measured.positions,
        settings.shape,
        center,
        settings.band,
    )
    .map_err(|m| CalibrationError::Settings(format!("{}: {m}", measured.origin)))?;
    Ok((target, sampler))
}
