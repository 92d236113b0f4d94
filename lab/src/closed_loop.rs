//! `breakaway-lab closed-loop`: a PID position loop tracking a sinusoid with
//! reversals, on two plants whose friction is not the compensator's own,
//! measured through an encoder, with nine friction compensators.
//!
//! - Plants: `lugre` — the LuGre model of [`crate::lugre`] (Canudas de Wit
//!   et al. 1995 parameters), the compensator using the library predictor
//!   fitted to its break-away curve; `model` — the MODEL.md model (reference
//!   `Friction`, f64) with Fc +25 %, Fs +20 %, V +30 %, z_max +30 % against
//!   the compensator's parameters.
//! - Loop: period T = 1 ms, x_ref = A·(1 − cos 2πft) (A = 1 mm, f = 1 Hz:
//!   reversals every 0.5 s, peak speed 6.3 mm/s), u = PID(e_m) + m·a_ref +
//!   the compensation, zero-order hold. PID by pole placement at (s + ω)³
//!   with ω = 125 rad/s on m = 1 kg.
//! - Measurement as firmware has it: the count n = ⌊x/q⌋ of an encoder of q
//!   metres per count (1 µm and 0.1 µm; q = 0 is the ideal measurement of
//!   x and v, for reference), the position read as the centre of the count
//!   (n + ½)·q, the velocity from the counts by the library's
//!   [`VelocityEstimator`] (ω_e = [`VELOCITY_BANDWIDTH`]); optionally
//!   Gaussian noise on the force the plant receives (the controller and the
//!   observer know only the command).
//! - Compensators: the feedforwards `none`; `coulomb` Fc·sgn(v_ref);
//!   `stribeck` F_ss(v_ref) (MODEL.md §2); `presliding` the library's
//!   [`Feedforward`](breakaway::compensation::Feedforward) (MODEL.md §3);
//!   each alone and with the [`DisturbanceObserver`]'s residual added (`+observer`,
//!   the same bandwidth for all, [`OBSERVER_BANDWIDTH`]), and
//!   `presliding+observer+adaptation` with the [`StictionAdaptation`] too
//!   (the Coulomb level from sliding, the stiction excess Fs − Fc from the
//!   window after each reversal; κ = [`REVERSAL_GAIN`]).
//! - Figures over the window [5 s, 8 s] (after the observer and adaptation
//!   have settled), on the true position: RMS of e = x_ref − x, the peak |e|
//!   within 50 ms after each reversal of x_ref, RMS of the total force
//!   command u.
//! - Drift: the same runs (1 µm encoder) with the plant's Fc, or Fc and Fs,
//!   stepped by +20 % at t = 2 s (`drift` `fc+20%`, `fc,fs+20%`).
//!
//! Plants are integrated with fixed sub-steps inside each period: LuGre by
//! RK4 with h = 10 µs, the MODEL.md plant by semi-implicit Euler with
//! h = 5 µs, the friction memory updated at every sub-step (a sample in the
//! sense of MODEL.md §3). The firmware example `closed_loop` runs the
//! `model` plant with the same constants in f32 on the MCU.

use breakaway::compensation::{
    AdaptationConfig, DisturbanceObserver, FeedforwardConfig, LevelAdaptation, ObserverConfig,
    StictionAdaptation, StictionConfig, VelocityConfig, VelocityEstimator,
};
use breakaway_reference as reference;

use crate::lugre::{self, LuGre};

/// Control period T [s].
pub const PERIOD: f64 = 1e-3;
/// Amplitude A [m] of x_ref = A·(1 − cos 2πft).
pub const AMPLITUDE: f64 = 1e-3;
/// Frequency f [Hz].
pub const FREQUENCY: f64 = 1.0;
/// Length of a run [s].
pub const DURATION: f64 = 8.0;
/// Start of the evaluation window [s].
pub const WINDOW_START: f64 = 5.0;
/// Time after a reversal [s] over which the peak error is taken.
pub const REVERSAL_WINDOW: f64 = 0.05;
/// Moving mass [kg] of both plants and of the controller's model.
pub const MASS: f64 = 1.0;
/// Closed-loop pole ω [rad/s]: (s + ω)³.
pub const OMEGA: f64 = 125.0;
/// Observer bandwidth [rad/s].
pub const OBSERVER_BANDWIDTH: f64 = 100.0;
/// Adaptation rate γ [1/s] of the Coulomb level.
pub const ADAPTATION_RATE: f64 = 1.0;
/// Fraction κ [-] of each reversal's stiction estimate applied (1 made the
/// `model` runs oscillate in the lab prototype; 0.3 averages the scatter of
/// the window estimates over about three reversals).
pub const REVERSAL_GAIN: f64 = 0.3;
/// A tracking error [m] beyond which a run is reported as diverged (the
/// stroke is 2 mm).
pub const DIVERGED: f64 = 0.1;
/// Seed of the force noise (the same sequence in every run).
pub const NOISE_SEED: u64 = 14;
/// Time [s] of the +20 % step of the plant's Fc in the drift runs.
pub const DRIFT_TIME: f64 = 2.0;
/// The drift factor: × 1.2.
pub const DRIFT: f64 = 1.2;

/// A step drift of the plant's friction levels at [`DRIFT_TIME`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Drift {
    /// No drift.
    None,
    /// Fc × 1.2 (Fs unchanged, raised to Fc where it would fall below).
    Coulomb,
    /// Fc and Fs × 1.2 (the `drift` effect of MODEL.md §5).
    Levels,
}

impl Drift {
    /// The name used in reports (`drift` field).
    pub fn name(self) -> &'static str {
        match self {
            Drift::None => "none",
            Drift::Coulomb => "fc+20%",
            Drift::Levels => "fc,fs+20%",
        }
    }
}
/// MODEL.md plant sub-steps per period.
pub const MODEL_SUBSTEPS: usize = 200;
/// LuGre plant sub-steps per period.
pub const LUGRE_SUBSTEPS: usize = 100;

/// PID gains (Kp [N/m], Ki [N/(m·s)], Kd [N·s/m]) for (s + ω)³ on m.
pub fn gains() -> (f64, f64, f64) {
    (
        3.0 * MASS * OMEGA * OMEGA,
        MASS * OMEGA.powi(3),
        3.0 * MASS * OMEGA,
    )
}

// The parameter sets of the benchmark, shared with the firmware example
// `closed_loop` and the library's tests.
#[path = "../../tests/support/mod.rs"]
mod support;

/// The compensator's parameters for the MODEL.md plant (the paper's Fig. 5
/// setting).
pub const MODEL_COMPENSATOR: breakaway::Params = support::FIG5;

/// The MODEL.md plant: Fc +25 %, Fs +20 %, V +30 %, z_max +30 % against
/// [`MODEL_COMPENSATOR`].
pub const MODEL_PLANT: breakaway::Params = support::CLOSED_LOOP_PLANT;

/// The friction feedforward of a compensator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feedforward {
    /// No friction feedforward.
    None,
    /// Fc·sgn(v_ref).
    Coulomb,
    /// F_ss(v_ref) (MODEL.md §2).
    Stribeck,
    /// The library's presliding feedforward (MODEL.md §3).
    Presliding,
}

/// A friction compensator: a feedforward, optionally with the disturbance
/// observer's residual added (the feedforward of the period is the force it
/// is told is explained), optionally with the level adaptation of the
/// presliding feedforward.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Compensator {
    /// The feedforward.
    pub feedforward: Feedforward,
    /// The disturbance observer adds its residual.
    pub observer: bool,
    /// The level adaptation scales the presliding feedforward (with the
    /// observer only).
    pub adaptation: bool,
}

impl Compensator {
    const fn new(feedforward: Feedforward, observer: bool, adaptation: bool) -> Self {
        Self {
            feedforward,
            observer,
            adaptation,
        }
    }
    /// No compensation.
    pub const NONE: Self = Self::new(Feedforward::None, false, false);
    /// Coulomb feedforward.
    pub const COULOMB: Self = Self::new(Feedforward::Coulomb, false, false);
    /// Stribeck feedforward.
    pub const STRIBECK: Self = Self::new(Feedforward::Stribeck, false, false);
    /// Presliding feedforward.
    pub const PRESLIDING: Self = Self::new(Feedforward::Presliding, false, false);
    /// The observer alone.
    pub const NONE_OBSERVER: Self = Self::new(Feedforward::None, true, false);
    /// Coulomb feedforward + observer.
    pub const COULOMB_OBSERVER: Self = Self::new(Feedforward::Coulomb, true, false);
    /// Stribeck feedforward + observer.
    pub const STRIBECK_OBSERVER: Self = Self::new(Feedforward::Stribeck, true, false);
    /// Presliding feedforward + observer.
    pub const PRESLIDING_OBSERVER: Self = Self::new(Feedforward::Presliding, true, false);
    /// Presliding feedforward + observer + level adaptation.
    pub const ADAPTIVE: Self = Self::new(Feedforward::Presliding, true, true);

    /// The name used in reports.
    pub fn name(self) -> &'static str {
        match (self.feedforward, self.observer, self.adaptation) {
            (Feedforward::None, false, _) => "none",
            (Feedforward::Coulomb, false, _) => "coulomb",
            (Feedforward::Stribeck, false, _) => "stribeck",
            (Feedforward::Presliding, false, _) => "presliding",
            (Feedforward::None, true, _) => "none+observer",
            (Feedforward::Coulomb, true, _) => "coulomb+observer",
            (Feedforward::Stribeck, true, _) => "stribeck+observer",
            (Feedforward::Presliding, true, false) => "presliding+observer",
            (Feedforward::Presliding, true, true) => "presliding+observer+adaptation",
        }
    }
}

/// The compensators, in table order.
pub const COMPENSATORS: [Compensator; 9] = [
    Compensator::NONE,
    Compensator::COULOMB,
    Compensator::STRIBECK,
    Compensator::PRESLIDING,
    Compensator::NONE_OBSERVER,
    Compensator::COULOMB_OBSERVER,
    Compensator::STRIBECK_OBSERVER,
    Compensator::PRESLIDING_OBSERVER,
    Compensator::ADAPTIVE,
];

/// Encoders of the benchmark [m per count]: ideal (0), 1 µm, 0.1 µm.
pub const ENCODERS: [f64; 3] = [0.0, 1e-6, 1e-7];

/// The encoder of the targets and of the drift runs [m per count].
pub const TARGET_ENCODER: f64 = 1e-6;

/// Bandwidth ω_e [rad/s] of the velocity estimator on encoder counts
/// (ω_e·T = 3); how it was chosen: docs/compensation.md.
pub const VELOCITY_BANDWIDTH: f64 = 3000.0;

/// Which plant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlantKind {
    /// LuGre, [`LuGre::CANUDAS_1995`].
    LuGre,
    /// MODEL.md, [`MODEL_PLANT`].
    Model,
}

impl PlantKind {
    /// The name used in reports.
    pub fn name(self) -> &'static str {
        match self {
            PlantKind::LuGre => "lugre",
            PlantKind::Model => "model",
        }
    }
}

/// A plant integrated inside one control period.
trait Plant {
    fn step(&mut self, u: f64);
    fn position(&self) -> f64;
    fn velocity(&self) -> f64;
    /// Scales the plant's Fc and Fs (drift).
    fn scale_levels(&mut self, fc: f64, fs: f64);
}

struct LuGrePlant(lugre::Plant);

impl Plant for LuGrePlant {
    fn step(&mut self, u: f64) {
        let h = PERIOD / LUGRE_SUBSTEPS as f64;
        for _ in 0..LUGRE_SUBSTEPS {
            self.0.step(&|_| u, 0.0, h);
        }
    }
    fn position(&self) -> f64 {
        self.0.x
    }
    fn velocity(&self) -> f64 {
        self.0.v
    }
    fn scale_levels(&mut self, fc: f64, fs: f64) {
        self.0.model.fc *= fc;
        self.0.model.fs *= fs;
    }
}

struct ModelPlant {
    model: reference::Model,
    friction: reference::Friction,
    x: f64,
    v: f64,
}

impl ModelPlant {
    fn new(p: &breakaway::Params) -> Self {
        let model = reference::Model {
            mass: MASS,
            fc: f64::from(p.fc),
            fs: f64::from(p.fs),
            v_stribeck: f64::from(p.v_stribeck),
            delta: f64::from(p.delta),
            sigma: f64::from(p.sigma),
            z_max: f64::from(p.z_max),
            epsilon: f64::from(p.epsilon),
            effects: reference::Effects::default(),
        };
        let friction = reference::Friction::new(&model, 0.0, 0.0, 0.0);
        ModelPlant {
            model,
            friction,
            x: 0.0,
            v: 0.0,
        }
    }
}

impl Plant for ModelPlant {
    fn step(&mut self, u: f64) {
        let h = PERIOD / MODEL_SUBSTEPS as f64;
        for _ in 0..MODEL_SUBSTEPS {
            // Time only matters for effects; the plant has none.
            let f = self.friction.update(&self.model, 0.0, self.x, self.v);
            self.v += h * (u - f) / self.model.mass;
            self.x += h * self.v;
        }
    }
    fn position(&self) -> f64 {
        self.x
    }
    fn velocity(&self) -> f64 {
        self.v
    }
    fn scale_levels(&mut self, fc: f64, fs: f64) {
        self.model.fc *= fc;
        self.model.fs = (self.model.fs * fs).max(self.model.fc);
    }
}

/// The figures of one run.
#[derive(Clone, Debug, PartialEq)]
pub struct Figures {
    /// Plant name (`lugre`, `model`).
    pub plant: &'static str,
    /// Compensator name.
    pub compensator: &'static str,
    /// The step drift of the plant's levels at [`DRIFT_TIME`].
    pub drift: Drift,
    /// Metres per encoder count (0: ideal measurement).
    pub encoder: f64,
    /// RMS tracking error [m] over the window (true position).
    pub rms_error: f64,
    /// Peak |e| [m] within 50 ms after a reversal, over the window.
    pub peak_reversal_error: f64,
    /// RMS force command [N] over the window.
    pub rms_effort: f64,
    /// (t [s], e [m]) of every period (for plots).
    pub trace: Vec<(f64, f64)>,
}

/// How the controller measures and what disturbs the command.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setup {
    /// Metres per encoder count q [m], ≥ 0 (0: ideal measurement of x and v).
    pub encoder: f64,
    /// Standard deviation [N], ≥ 0, of the Gaussian noise added to the force
    /// the plant receives (fixed seed).
    pub force_noise: f64,
    /// Bandwidth [rad/s] of the disturbance observer, > 0.
    pub observer_bandwidth: f64,
    /// Bandwidth ω_e [rad/s] of the velocity estimator, > 0.
    pub velocity_bandwidth: f64,
    /// Shift [counts], 0 ≤ P < 1, of the encoder's zero: the count is
    /// ⌊x/q + P⌋, read as (n + ½ − P)·q (the same unbiased reading, the
    /// count boundaries moved by P·q).
    pub count_phase: f64,
    /// The adaptive row adapts the single level scale θ
    /// ([`LevelAdaptation`]) instead of the split Coulomb and stiction
    /// scales ([`StictionAdaptation`]), for comparison.
    pub single_scale: bool,
    /// Factor [-], > 0, on the compensator's presliding distance z_max (1 in
    /// the benchmark; other values only for the diagnosis in
    /// docs/compensation.md).
    pub z_max_scale: f64,
    /// Fixed level scales (θ_c, θ_s) [-] of the `presliding` feedforward-only
    /// row (split levels; `None` in the benchmark: the model's own Fc and
    /// Fs); for the diagnosis in docs/compensation.md.
    pub feedforward_levels: Option<(f64, f64)>,
}

impl Setup {
    /// The benchmark's setup with an encoder of `encoder` metres per count
    /// (0: ideal) and no force noise.
    pub const fn encoder(encoder: f64) -> Self {
        Self {
            encoder,
            force_noise: 0.0,
            observer_bandwidth: OBSERVER_BANDWIDTH,
            velocity_bandwidth: VELOCITY_BANDWIDTH,
            count_phase: 0.0,
            single_scale: false,
            z_max_scale: 1.0,
            feedforward_levels: None,
        }
    }

    /// `Err` naming the setting that is out of range.
    pub fn check(&self) -> Result<(), String> {
        let ok = |x: f64, zero: bool| x.is_finite() && (x > 0.0 || (zero && x == 0.0));
        if !ok(self.encoder, true) {
            return Err(format!(
                "encoder {} m per count: must be >= 0",
                self.encoder
            ));
        }
        if !ok(self.force_noise, true) {
            return Err(format!("force noise {} N: must be >= 0", self.force_noise));
        }
        if !ok(self.observer_bandwidth, false) {
            return Err(format!(
                "observer bandwidth {} rad/s: must be > 0",
                self.observer_bandwidth
            ));
        }
        if !ok(self.velocity_bandwidth, false) {
            return Err(format!(
                "velocity bandwidth {} rad/s: must be > 0",
                self.velocity_bandwidth
            ));
        }
        // The library's own ranges (bandwidth times period among them),
        // checked here where the option can be named.
        let period = PERIOD as f32;
        DisturbanceObserver::new(ObserverConfig {
            mass: MASS as f32,
            bandwidth: self.observer_bandwidth as f32,
            period,
        })
        .map_err(|e| {
            format!(
                "observer bandwidth {:e} rad/s: {e}",
                self.observer_bandwidth
            )
        })?;
        VelocityEstimator::<i64>::new(
            VelocityConfig {
                bandwidth: self.velocity_bandwidth as f32,
                period,
            },
            1e-6,
        )
        .map_err(|e| {
            format!(
                "velocity bandwidth {:e} rad/s: {e}",
                self.velocity_bandwidth
            )
        })?;
        if !ok(self.z_max_scale, false) {
            return Err(format!("z_max scale {}: must be > 0", self.z_max_scale));
        }
        if let Some((c, s)) = self.feedforward_levels {
            if !(ok(c, false) && ok(s, true)) {
                return Err(format!(
                    "feedforward levels ({c}, {s}): must be > 0 and >= 0"
                ));
            }
        }
        if !(ok(self.count_phase, true) && self.count_phase < 1.0) {
            return Err(format!(
                "count phase {} counts: must be in [0, 1)",
                self.count_phase
            ));
        }
        Ok(())
    }
}

/// What the controller measures: the count ⌊x/q⌋ of an encoder of q metres
/// per count (an incremental encoder zeroed at x = 0), read as the centre of
/// the count (the unbiased estimate; n·q would offset every row by q/2), and
/// the velocity from the library's [`VelocityEstimator`] on the counts; or,
/// for q = 0, the plant's own position and velocity.
struct Measurement {
    q: f64,
    phase: f64,
    estimator: Option<VelocityEstimator<i64>>,
}

impl Measurement {
    fn new(setup: &Setup) -> Result<Self, String> {
        let q = setup.encoder;
        let estimator = if q > 0.0 {
            let config = VelocityConfig {
                bandwidth: setup.velocity_bandwidth as f32,
                period: PERIOD as f32,
            };
            Some(VelocityEstimator::new(config, q as f32).map_err(|e| e.to_string())?)
        } else {
            None
        };
        Ok(Self {
            q,
            phase: setup.count_phase,
            estimator,
        })
    }

    /// (position [m], velocity [m/s]) as the controller sees them.
    fn read(&mut self, x: f64, v: f64) -> Result<(f64, f64), String> {
        match self.estimator.as_mut() {
            None => Ok((x, v)),
            Some(estimator) => {
                let count = (x / self.q + self.phase).floor() as i64;
                let v = estimator.update(count).map_err(|e| e.to_string())?;
                Ok(((count as f64 + 0.5 - self.phase) * self.q, f64::from(v)))
            }
        }
    }
}

/// The reference x_ref [m], v_ref [m/s], a_ref [m/s²] at `t` [s].
pub fn reference_at(t: f64) -> (f64, f64, f64) {
    let w = 2.0 * std::f64::consts::PI * FREQUENCY;
    (
        AMPLITUDE * (1.0 - (w * t).cos()),
        AMPLITUDE * w * (w * t).sin(),
        AMPLITUDE * w * w * (w * t).cos(),
    )
}

/// The compensator's model parameters for a plant: for the LuGre plant the
/// library predictor fitted to the LuGre break-away curve
/// ([`lugre::fit_predictor`] on Fc, Fs, σ2 and z_max = 2·Fs/σ0, the bristle
/// travel from −Fs to +Fs).
pub fn compensator_params(plant: PlantKind) -> breakaway::Params {
    match plant {
        PlantKind::Model => MODEL_COMPENSATOR,
        PlantKind::LuGre => {
            let m = LuGre::CANUDAS_1995;
            let base = breakaway::Params {
                z_max: (2.0 * m.fs / m.sigma0) as f32,
                ..lugre::lugre_base()
            };
            let fit = lugre::fit_predictor(&base, &lugre::PUBLISHED_BREAK_AWAY);
            breakaway::Params {
                v_stribeck: fit.v_stribeck as f32,
                delta: fit.delta as f32,
                ..base
            }
        }
    }
}

/// Runs one closed loop with a step `drift` of the plant's levels at
/// [`DRIFT_TIME`], measured and disturbed as `setup` says.
pub fn run(
    plant_kind: PlantKind,
    compensator: Compensator,
    drift: Drift,
    setup: &Setup,
) -> Result<Figures, String> {
    run_on(plant_kind, &MODEL_PLANT, compensator, drift, setup)
}

/// The peak reversal error [m] of [`run`] at each count phase of `phases`
/// [counts] (in that order, run in parallel), the rest of the setup as
/// `base`: the spread of a row over where the counts fall.
pub fn peaks_over_phases(
    plant_kind: PlantKind,
    compensator: Compensator,
    drift: Drift,
    base: &Setup,
    phases: &[f64],
) -> Result<Vec<f64>, String> {
    use rayon::prelude::*;
    phases
        .par_iter()
        .map(|&count_phase| {
            let setup = Setup {
                count_phase,
                ..*base
            };
            run(plant_kind, compensator, drift, &setup).map(|f| f.peak_reversal_error)
        })
        .collect()
}

/// The parameters of a MODEL.md plant carrying the fractions `errors` =
/// [Fc, Fs, V, z_max] (dimensionless) of the parameter errors of
/// [`MODEL_PLANT`] against [`MODEL_COMPENSATOR`], each interpolated
/// linearly in its own unit (N, N, m/s, m): 0 gives the compensator's value,
/// 1 the benchmark plant's; the other parameters are the compensator's.
pub fn model_plant_with_error(errors: [f64; 4]) -> breakaway::Params {
    let (c, p) = (MODEL_COMPENSATOR, MODEL_PLANT);
    let mix = |c: f32, p: f32, e: f64| (f64::from(c) + e * f64::from(p - c)) as f32;
    breakaway::Params {
        fc: mix(c.fc, p.fc, errors[0]),
        fs: mix(c.fs, p.fs, errors[1]),
        v_stribeck: mix(c.v_stribeck, p.v_stribeck, errors[2]),
        z_max: mix(c.z_max, p.z_max, errors[3]),
        ..c
    }
}

/// [`run`] with the parameters of the `model` plant given (the `lugre`
/// plant ignores them).
pub fn run_on(
    plant_kind: PlantKind,
    model_plant: &breakaway::Params,
    compensator: Compensator,
    drift: Drift,
    setup: &Setup,
) -> Result<Figures, String> {
    setup.check()?;
    let tuned = compensator_params(plant_kind);
    let params = breakaway::Params {
        z_max: (f64::from(tuned.z_max) * setup.z_max_scale) as f32,
        ..tuned
    };
    let model = breakaway::Model::<f32>::new(params).map_err(|e| e.to_string())?;
    let mut plant: Box<dyn Plant> = match plant_kind {
        PlantKind::LuGre => Box::new(LuGrePlant(lugre::Plant::new(LuGre::CANUDAS_1995))),
        PlantKind::Model => Box::new(ModelPlant::new(model_plant)),
    };
    let mut sensor = Measurement::new(setup)?;
    let mut noise = crate::synth::Rng::new(NOISE_SEED);
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let mut ff =
        breakaway::compensation::Feedforward::<f32>::new(FeedforwardConfig::default(), 0.0, 1.0)
            .map_err(|e| err(&e))?;
    let split = compensator.adaptation && !setup.single_scale;
    if split {
        ff = ff.with_split_levels();
    }
    if let (Some((coulomb, stiction)), false) = (setup.feedforward_levels, compensator.observer) {
        ff = ff.with_split_levels();
        ff.set_level_scales(coulomb as f32, stiction as f32);
    }
    let mut single = LevelAdaptation::new(AdaptationConfig {
        rate: ADAPTATION_RATE as f32,
        min_scale: 0.5,
        max_scale: 2.0,
        min_speed: params.v_stribeck,
        period: PERIOD as f32,
    })
    .map_err(|e| err(&e))?;
    let mut adaptation = StictionAdaptation::new(StictionConfig {
        rate: ADAPTATION_RATE as f32,
        reversal_gain: REVERSAL_GAIN as f32,
        bandwidth: setup.observer_bandwidth as f32,
        min_scale: 0.5,
        max_scale: 2.0,
        max_stiction_scale: 3.0,
        min_speed: params.v_stribeck,
        period: PERIOD as f32,
    })
    .map_err(|e| err(&e))?;
    let mut observer = DisturbanceObserver::new(ObserverConfig {
        mass: MASS as f32,
        bandwidth: setup.observer_bandwidth as f32,
        period: PERIOD as f32,
    })
    .map_err(|e| err(&e))?;
    let (kp, ki, kd) = gains();
    let steps = (DURATION / PERIOD).round() as usize;
    let (mut integral, mut u, mut u_ff) = (0.0f64, 0.0f64, 0.0f32);
    let (mut sum_e2, mut sum_u2, mut count) = (0.0, 0.0, 0usize);
    let mut trace = Vec::with_capacity(steps);
    let mut drifted = false;
    for n in 0..steps {
        let t = n as f64 * PERIOD;
        if !drifted && t >= DRIFT_TIME {
            match drift {
                Drift::None => {}
                Drift::Coulomb => plant.scale_levels(DRIFT, 1.0),
                Drift::Levels => plant.scale_levels(DRIFT, DRIFT),
            }
            drifted = true;
        }
        let (x_ref, v_ref, a_ref) = reference_at(t);
        let (x_m, v_m) = sensor.read(plant.position(), plant.velocity())?;
        // The figures judge the true position; the controller sees x_m.
        let e = x_ref - plant.position();
        if !e.is_finite() || e.abs() >= DIVERGED {
            return Err(format!(
                "closed loop diverged: plant {}, compensator {}, drift {}, encoder {} m, |e| > {DIVERGED} m at t = {t:.3} s",
                plant_kind.name(),
                compensator.name(),
                drift.name(),
                setup.encoder
            ));
        }
        trace.push((t, e));
        // The observer first: it explains the period that just ended with
        // the command and the feedforward applied in it.
        let residual = if compensator.observer {
            let r = observer
                .update(u as f32, v_m as f32, u_ff)
                .map_err(|e| err(&e))?;
            if split {
                // Regressors of the period just ended: `ff` is updated below.
                let (coulomb, stiction) = adaptation
                    .update(r, &ff, v_ref as f32)
                    .map_err(|e| err(&e))?;
                ff.set_level_scales(coulomb, stiction);
            } else if compensator.adaptation {
                let theta = single
                    .update(r, ff.dry(), v_ref as f32, ff.is_sliding())
                    .map_err(|e| err(&e))?;
                ff.set_level_scale(theta);
            }
            r
        } else {
            0.0
        };
        u_ff = match compensator.feedforward {
            Feedforward::None => 0.0,
            // Fc·sgn(v_ref), 0 at v_ref = 0.
            Feedforward::Coulomb if v_ref == 0.0 => 0.0,
            Feedforward::Coulomb => params.fc.copysign(v_ref as f32),
            Feedforward::Stribeck => model.steady_state(v_ref as f32),
            Feedforward::Presliding => ff
                .update(&model, x_ref as f32, v_ref as f32)
                .map_err(|e| err(&e))?,
        };
        let compensation = f64::from(u_ff) + f64::from(residual);
        let e_m = x_ref - x_m;
        integral += e_m * PERIOD;
        u = kp * e_m + ki * integral + kd * (v_ref - v_m) + MASS * a_ref + compensation;
        if t >= WINDOW_START - 1e-9 {
            sum_e2 += e * e;
            sum_u2 += u * u;
            count += 1;
        }
        plant.step(u + setup.force_noise * noise.normal());
    }
    let peak = peak_reversal_error(&trace);
    Ok(Figures {
        plant: plant_kind.name(),
        compensator: compensator.name(),
        drift,
        encoder: setup.encoder,
        rms_error: (sum_e2 / count.max(1) as f64).sqrt(),
        peak_reversal_error: peak,
        rms_effort: (sum_u2 / count.max(1) as f64).sqrt(),
        trace,
    })
}

/// The largest |e| [m] of `trace` ((t [s], e [m]) per period) within
/// [`REVERSAL_WINDOW`] after each reversal of x_ref from [`WINDOW_START`]
/// on (the last one only if its window ends within the run).
fn peak_reversal_error(trace: &[(f64, f64)]) -> f64 {
    let half = 0.5 / FREQUENCY;
    let mut peak = 0.0f64;
    for &(t, e) in trace {
        let since = t - (t / half).floor() * half;
        let reversal = t - since;
        if reversal >= WINDOW_START - 1e-9
            && since <= REVERSAL_WINDOW + 1e-9
            && reversal + REVERSAL_WINDOW < DURATION
        {
            peak = peak.max(e.abs());
        }
    }
    peak
}

/// Every run of the benchmark, in table order: both plants, every encoder
/// of [`ENCODERS`], every compensator, no drift; then both plants, both
/// drifts, every compensator at [`TARGET_ENCODER`]. `base` gives the force
/// noise and the bandwidths (its encoder is replaced).
pub fn benchmark(base: &Setup) -> Result<Vec<Figures>, String> {
    let mut jobs = Vec::new();
    for plant in [PlantKind::LuGre, PlantKind::Model] {
        for encoder in ENCODERS {
            for c in COMPENSATORS {
                jobs.push((plant, c, Drift::None, encoder));
            }
        }
    }
    for plant in [PlantKind::LuGre, PlantKind::Model] {
        for drift in [Drift::Coulomb, Drift::Levels] {
            for c in COMPENSATORS {
                jobs.push((plant, c, drift, TARGET_ENCODER));
            }
        }
    }
    let threads = std::thread::available_parallelism().map_or(2, usize::from);
    std::thread::scope(|scope| {
        let handles: Vec<_> = jobs
            .chunks(jobs.len().div_ceil(threads))
            .map(|chunk| {
                scope.spawn(move || {
                    chunk
                        .iter()
                        .map(|&(p, c, d, encoder)| run(p, c, d, &Setup { encoder, ..*base }))
                        .collect::<Result<Vec<_>, String>>()
                })
            })
            .collect();
        let mut all = Vec::new();
        for h in handles {
            all.extend(
                h.join()
                    .map_err(|_| "benchmark thread panicked".to_string())??,
            );
        }
        Ok(all)
    })
}

/// The JSON array of the figures (keys `plant`, `compensator`, `drift`,
/// `encoder` [m per count, 0 for ideal], `rms_error`, `peak_reversal_error`,
/// `rms_effort`; SI units).
pub fn to_json(rows: &[Figures]) -> String {
    let array: Vec<serde_json::Value> = rows
        .iter()
        .map(|r| {
            serde_json::json!({
                "plant": r.plant,
                "compensator": r.compensator,
                "drift": r.drift.name(),
                "encoder": r.encoder,
                "rms_error": r.rms_error,
                "peak_reversal_error": r.peak_reversal_error,
                "rms_effort": r.rms_effort,
            })
        })
        .collect();
    let mut text = serde_json::to_string_pretty(&array).unwrap_or_default();
    text.push('\n');
    text
}

/// The peak reversal error of a run in `rows`.
pub fn peak(
    rows: &[Figures],
    plant: &str,
    compensator: &str,
    drift: Drift,
    encoder: f64,
) -> Option<f64> {
    rows.iter()
        .find(|r| {
            r.plant == plant
                && r.compensator == compensator
                && r.drift == drift
                && r.encoder == encoder
        })
        .map(|r| r.peak_reversal_error)
}

/// The text table (errors in µm) with the target ratios.
pub fn to_table(rows: &[Figures]) -> String {
    let mut text = format!(
        "{:<6} {:<10} {:>8} {:<31} {:>9} {:>10} {:>9}\n",
        "plant", "drift", "encoder", "compensator", "rms_um", "peak_um", "effort_N"
    );
    for r in rows {
        let encoder = if r.encoder > 0.0 {
            format!("{} um", (r.encoder * 1e9).round() / 1e3)
        } else {
            "ideal".to_string()
        };
        text.push_str(&format!(
            "{:<6} {:<10} {:>8} {:<31} {:>9.3} {:>10.3} {:>9.4}\n",
            r.plant,
            r.drift.name(),
            encoder,
            r.compensator,
            r.rms_error * 1e6,
            r.peak_reversal_error * 1e6,
            r.rms_effort
        ));
    }
    let at = |plant: &str, c: &str, drift: Drift| peak(rows, plant, c, drift, TARGET_ENCODER);
    text.push_str("\ntargets (peak reversal error, 1 um encoder):\n");
    for plant in ["lugre", "model"] {
        let adaptive = Compensator::ADAPTIVE.name();
        if let (Some(none), Some(coulomb), Some(pre), Some(co), Some(ad)) = (
            at(plant, "none", Drift::None),
            at(plant, "coulomb", Drift::None),
            at(plant, "presliding", Drift::None),
            at(plant, "coulomb+observer", Drift::None),
            at(plant, adaptive, Drift::None),
        ) {
            text.push_str(&format!(
                "  {plant}: none/{adaptive} = {:.1} (target >= 10), coulomb+observer/{adaptive} = {:.2} (target >= 2), \
                 coulomb/presliding = {:.2} (target >= 2)\n",
                none / ad,
                co / ad,
                coulomb / pre
            ));
            for drift in [Drift::Coulomb, Drift::Levels] {
                if let Some(after) = at(plant, adaptive, drift) {
                    text.push_str(&format!(
                        "  {plant}, drift {}: {adaptive} {:.3} um vs tuned {:.3} um: {:+.1} % (target within 25 %)\n",
                        drift.name(),
                        after * 1e6,
                        ad * 1e6,
                        (after / ad - 1.0) * 100.0
                    ));
                }
            }
        }
    }
    text
}

/// The compensators in the SVG plot (1 µm encoder, no drift).
const PLOTTED: [Compensator; 5] = [
    Compensator::NONE,
    Compensator::COULOMB,
    Compensator::PRESLIDING,
    Compensator::COULOMB_OBSERVER,
    Compensator::ADAPTIVE,
];

/// Time [s] of the reversal shown in the SVG plot.
pub const PLOT_REVERSAL: f64 = 6.0;

/// An SVG plot of e(t) around the reversal at [`PLOT_REVERSAL`], one panel
/// per plant, one curve per compensator (no drift).
pub fn to_svg(rows: &[Figures]) -> String {
    const COLOURS: [&str; 5] = ["#7f7f7f", "#d62728", "#ff7f0e", "#1f77b4", "#2ca02c"];
    let (t0, t1) = (PLOT_REVERSAL - 0.02, PLOT_REVERSAL + 0.1);
    let (w, h, margin) = (460.0, 300.0, 55.0);
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
        2.0 * w,
        h + 40.0
    );
    for (panel, plant) in ["lugre", "model"].iter().enumerate() {
        let x0 = panel as f64 * w;
        let curves: Vec<(&Figures, Vec<(f64, f64)>)> = PLOTTED
            .iter()
            .filter_map(|c| {
                rows.iter().find(|r| {
                    r.plant == *plant
                        && r.compensator == c.name()
                        && r.drift == Drift::None
                        && r.encoder == TARGET_ENCODER
                })
            })
            .map(|r| {
                let pts = r
                    .trace
                    .iter()
                    .filter(|(t, _)| *t >= t0 - 1e-9 && *t <= t1 + 1e-9)
                    .map(|&(t, e)| (t, e * 1e6))
                    .collect();
                (r, pts)
            })
            .collect();
        let limit = curves
            .iter()
            .flat_map(|(_, p)| p.iter().map(|(_, e)| e.abs()))
            .fold(1.0f64, f64::max)
            * 1.1;
        let px = |t: f64| x0 + margin + (t - t0) / (t1 - t0) * (w - 1.5 * margin);
        let py = |e: f64| 20.0 + (1.0 - (e + limit) / (2.0 * limit)) * (h - margin);
        svg.push_str(&format!(
            "<text x=\"{:.1}\" y=\"14\" font-size=\"13\">{plant} plant: e = x_ref − x [µm] around the reversal at t = {PLOT_REVERSAL} s</text>\n",
            x0 + margin
        ));
        svg.push_str(&format!(
            "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"black\"/>\n",
            px(t0),
            py(0.0),
            px(t1),
            py(0.0)
        ));
        svg.push_str(&format!(
            "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"black\"/>\n",
            px(t0),
            py(limit),
            px(t0),
            py(-limit)
        ));
        svg.push_str(&format!(
            "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"#aaa\" stroke-dasharray=\"3,3\"/>\n",
            px(PLOT_REVERSAL), py(limit), px(PLOT_REVERSAL), py(-limit)
        ));
        for (value, anchor) in [(limit / 1.1, "end"), (0.0, "end"), (-limit / 1.1, "end")] {
            svg.push_str(&format!(
                "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"{anchor}\">{value:.1}</text>\n",
                px(t0) - 4.0,
                py(value) + 4.0
            ));
        }
        for ms in [-20, 0, 20, 40, 60, 80, 100] {
            let t = PLOT_REVERSAL + f64::from(ms) * 1e-3;
            svg.push_str(&format!(
                "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{ms} ms</text>\n",
                px(t),
                h - margin + 38.0
            ));
        }
        for (i, (r, pts)) in curves.iter().enumerate() {
            let colour = COLOURS[i % COLOURS.len()];
            let path: Vec<String> = pts
                .iter()
                .map(|&(t, e)| format!("{:.1},{:.1}", px(t), py(e)))
                .collect();
            svg.push_str(&format!(
                "<polyline fill=\"none\" stroke=\"{colour}\" stroke-width=\"1.5\" points=\"{}\"/>\n",
                path.join(" ")
            ));
            svg.push_str(&format!(
                "<text x=\"{:.1}\" y=\"{:.1}\" fill=\"{colour}\">{}</text>\n",
                x0 + w - 1.5 * margin - 60.0,
                40.0 + 14.0 * i as f64,
                r.compensator
            ));
        }
    }
    svg.push_str("</svg>\n");
    svg
}

/// `breakaway-lab closed-loop`: the benchmark as a table or JSON, and
/// optionally the SVG plot.
pub fn command(
    args: &crate::cli::ClosedLoopArgs,
    out: &mut dyn std::io::Write,
) -> Result<(), crate::Error> {
    use crate::Error;
    let setup = Setup {
        encoder: 0.0,
        force_noise: args.force_noise,
        observer_bandwidth: args.observer_bandwidth,
        velocity_bandwidth: args.velocity_bandwidth,
        count_phase: args.count_phase,
        single_scale: args.single_scale,
        ..Setup::encoder(0.0)
    };
    setup.check().map_err(Error::Usage)?;
    let to_stdout = crate::workflow::stdout_beside_flag(args.svg.as_deref(), "--svg", args.json)?;
    if let Some(path) = &args.svg {
        crate::workflow::not_input(path, &[])?;
    }
    let rows = benchmark(&setup).map_err(Error::Runtime)?;
    if let Some(path) = &args.svg {
        crate::workflow::write_file(path, &to_svg(&rows), out)?;
        if to_stdout {
            return Ok(());
        }
    }
    let text = if args.json {
        to_json(&rows)
    } else {
        to_table(&rows)
    };
    crate::emit(out, &text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn force_noise_is_seeded_and_bad_setups_are_named() {
        let quiet = Setup::encoder(TARGET_ENCODER);
        let noisy = Setup {
            force_noise: 0.05,
            ..quiet
        };
        let c = Compensator::COULOMB_OBSERVER;
        let a = run(PlantKind::Model, c, Drift::None, &noisy).unwrap();
        let b = run(PlantKind::Model, c, Drift::None, &noisy).unwrap();
        let q = run(PlantKind::Model, c, Drift::None, &quiet).unwrap();
        assert_eq!(a, b);
        assert_ne!(a.rms_error, q.rms_error);
        // 0.05 N of noise on the `model` plant, 1 µm encoder: measured
        // +3.6 % on the RMS error (2.10 against 2.03 µm).
        assert!((a.rms_error / q.rms_error - 1.0).abs() < 0.2);
        for (setup, needle) in [
            (
                Setup {
                    encoder: -1e-6,
                    ..quiet
                },
                "encoder",
            ),
            (
                Setup {
                    force_noise: f64::NAN,
                    ..quiet
                },
                "force noise",
            ),
            (
                Setup {
                    observer_bandwidth: 0.0,
                    ..quiet
                },
                "observer bandwidth",
            ),
            (
                Setup {
                    velocity_bandwidth: -3.0,
                    ..quiet
                },
                "velocity bandwidth",
            ),
            (
                Setup {
                    count_phase: 1.0,
                    ..quiet
                },
                "count phase",
            ),
            (
                Setup {
                    z_max_scale: 0.0,
                    ..quiet
                },
                "z_max scale",
            ),
            (
                Setup {
                    feedforward_levels: Some((1.0, -0.5)),
                    ..quiet
                },
                "feedforward levels",
            ),
        ] {
            let e = run(PlantKind::Model, c, Drift::None, &setup).unwrap_err();
            assert!(e.contains(needle), "{e}");
        }
    }

    #[test]
    fn parameter_error_fractions_span_compensator_to_plant() {
        let (c, p) = (MODEL_COMPENSATOR, MODEL_PLANT);
        assert_eq!(model_plant_with_error([0.0; 4]), c);
        assert_eq!(model_plant_with_error([1.0; 4]), p);
        let half = model_plant_with_error([0.0, 0.5, 0.0, 0.0]);
        assert_eq!(
            (half.fc, half.v_stribeck, half.z_max),
            (c.fc, c.v_stribeck, c.z_max)
        );
        assert!((f64::from(half.fs) - 0.5 * f64::from(c.fs + p.fs)).abs() < 1e-6);
        // `run` is `run_on` the benchmark's plant.
        let setup = Setup::encoder(TARGET_ENCODER);
        let c = Compensator::PRESLIDING;
        assert_eq!(
            run(PlantKind::Model, c, Drift::None, &setup).unwrap(),
            run_on(PlantKind::Model, &MODEL_PLANT, c, Drift::None, &setup).unwrap()
        );
    }

    /// `presliding` against `coulomb` (feedforward only, peak reversal
    /// error) on the `model` plant as its parameter error grows from none
    /// to the benchmark's, all four parameters together and each alone;
    /// ideal measurement and the 1 µm encoder at four count phases.
    /// `cargo test -p breakaway-lab --release closed_loop::tests::feedforward_ratio_against_parameter_error -- --ignored --nocapture`
    #[test]
    #[ignore = "a sweep for docs/compensation.md (2 × 9 × 5 runs)"]
    fn feedforward_ratio_against_parameter_error() {
        let phases = [0.0, 0.25, 0.5, 0.75];
        let cases: [(&str, [f64; 4]); 5] = [
            ("all", [1.0; 4]),
            ("fc", [1.0, 0.0, 0.0, 0.0]),
            ("fs", [0.0, 1.0, 0.0, 0.0]),
            ("v", [0.0, 0.0, 1.0, 0.0]),
            ("z_max", [0.0, 0.0, 0.0, 1.0]),
        ];
        println!("error  fraction  ideal: coulomb presliding ratio | 1 um (mean of 4 phases): coulomb presliding ratio");
        for (name, errors) in cases {
            for fraction in [0.0, 0.25, 0.5, 0.75, 1.0] {
                if name != "all" && fraction != 1.0 {
                    continue;
                }
                let plant = model_plant_with_error(errors.map(|e| e * fraction));
                let peak = |c: Compensator, setup: &Setup| {
                    run_on(PlantKind::Model, &plant, c, Drift::None, setup)
                        .unwrap()
                        .peak_reversal_error
                };
                let ideal = Setup::encoder(0.0);
                let (ci, pi) = (
                    peak(Compensator::COULOMB, &ideal),
                    peak(Compensator::PRESLIDING, &ideal),
                );
                let (mut cq, mut pq) = (0.0, 0.0);
                for count_phase in phases {
                    let setup = Setup {
                        count_phase,
                        ..Setup::encoder(TARGET_ENCODER)
                    };
                    cq += peak(Compensator::COULOMB, &setup) / phases.len() as f64;
                    pq += peak(Compensator::PRESLIDING, &setup) / phases.len() as f64;
                }
                println!(
                    "{name:<6} {fraction:>8.2}  {:>7.2} {:>7.2} {:>5.2} | {:>7.2} {:>7.2} {:>5.2}",
                    ci * 1e6,
                    pi * 1e6,
                    ci / pi,
                    cq * 1e6,
                    pq * 1e6,
                    cq / pq
                );
            }
        }
    }

    /// The diagnosis of the two missed targets in docs/compensation.md, 1 µm
    /// encoder, peak reversal error averaged over the count phases 0, 0.25,
    /// 0.5, 0.75: (1) `presliding+observer+adaptation` on both plants and
    /// every drift with the compensator's z_max as in the benchmark and
    /// × 1.2 (the LuGre bristles' presliding travel grows with Fs); (2)
    /// `presliding` alone on `lugre` with the model's Fc (θ_c = 1) and the
    /// stiction excess Fs − Fc scaled by θ_s, against `coulomb`.
    /// `cargo test -p breakaway-lab --release closed_loop::tests::drift_and_feedforward_diagnosis -- --ignored --nocapture`
    #[test]
    #[ignore = "a diagnosis for docs/compensation.md (88 runs)"]
    fn drift_and_feedforward_diagnosis() {
        let phases = [0.0, 0.25, 0.5, 0.75];
        let mean = |plant: PlantKind, c: Compensator, drift: Drift, base: Setup| {
            let peaks = peaks_over_phases(plant, c, drift, &base, &phases).unwrap();
            peaks.iter().sum::<f64>() / peaks.len() as f64 * 1e6
        };
        let quiet = Setup::encoder(TARGET_ENCODER);
        println!(
            "(1) {}, mean peak [um]: z_max as benchmark | z_max x 1.2",
            Compensator::ADAPTIVE.name()
        );
        for plant in [PlantKind::LuGre, PlantKind::Model] {
            for drift in [Drift::None, Drift::Coulomb, Drift::Levels] {
                let [a, b] = [1.0, 1.2].map(|z_max_scale| {
                    mean(
                        plant,
                        Compensator::ADAPTIVE,
                        drift,
                        Setup {
                            z_max_scale,
                            ..quiet
                        },
                    )
                });
                println!(
                    "{:<6} {:<10} {a:>6.2} | {b:>6.2}",
                    plant.name(),
                    drift.name()
                );
            }
        }
        let coulomb = mean(PlantKind::LuGre, Compensator::COULOMB, Drift::None, quiet);
        println!("(2) lugre, feedforward only, mean peak [um]: coulomb {coulomb:.2}");
        for levels in [
            None,
            Some((1.0, 1.0)),
            Some((1.0, 0.5)),
            Some((1.0, 0.34)),
            Some((1.0, 0.2)),
            Some((1.0, 0.0)),
        ] {
            let setup = Setup {
                feedforward_levels: levels,
                ..quiet
            };
            let p = mean(
                PlantKind::LuGre,
                Compensator::PRESLIDING,
                Drift::None,
                setup,
            );
            println!(
                "presliding, levels {levels:?}: {p:.2} (coulomb / presliding = {:.2})",
                coulomb / p
            );
        }
    }

    #[test]
    fn closed_loop_json_and_measured_ratios() {
        let mut out = Vec::new();
        crate::run(&["closed-loop".to_string(), "--json".to_string()], &mut out).unwrap();
        let rows: Vec<serde_json::Value> = serde_json::from_slice(&out).unwrap();
        // 2 plants × 3 encoders × 9 compensators, then 2 plants × 2 drifts
        // × 9 compensators at the 1 µm encoder.
        assert_eq!(rows.len(), 54 + 36);
        let keys = [
            "compensator",
            "drift",
            "encoder",
            "peak_reversal_error",
            "plant",
            "rms_effort",
            "rms_error",
        ];
        for row in &rows {
            let mut got: Vec<&str> = row
                .as_object()
                .unwrap()
                .keys()
                .map(String::as_str)
                .collect();
            got.sort_unstable();
            assert_eq!(got, keys);
        }
        let peak = |plant: &str, c: &str, drift: &str, encoder: f64| {
            rows.iter()
                .find(|r| {
                    r["plant"] == plant
                        && r["compensator"] == c
                        && r["drift"] == drift
                        && r["encoder"].as_f64() == Some(encoder)
                })
                .and_then(|r| r["peak_reversal_error"].as_f64())
                .unwrap()
        };
        let adaptive = Compensator::ADAPTIVE.name();
        for plant in ["lugre", "model"] {
            // Ideal measurement: the observer with the Coulomb and stiction
            // adaptation 28× and 41× better than none.
            let none = peak(plant, "none", "none", 0.0);
            let ad = peak(plant, adaptive, "none", 0.0);
            assert!(none / ad > 15.0, "{plant}: {none} / {ad}");
            // 0.1 µm per count: within a factor 1.5 of ideal (measured
            // +1 % and +31 %: 0.90 and 1.14 µm against 0.89 and 0.87 µm).
            let fine = peak(plant, adaptive, "none", 1e-7);
            assert!(
                fine / ad < 1.5 && ad / fine < 1.5,
                "{plant}: {fine} vs {ad}"
            );
            // Through the 1 µm encoder (measured: 19.1× and 12.6× better
            // than none, 7.3× and 3.8× better than coulomb+observer).
            let q = TARGET_ENCODER;
            let none = peak(plant, "none", "none", q);
            let co = peak(plant, "coulomb+observer", "none", q);
            let ad = peak(plant, adaptive, "none", q);
            assert!(none / ad > 5.0, "{plant}: none {none} / {ad}");
            assert!(co / ad > 1.5, "{plant}: coulomb+observer {co} / {ad}");
            // Every observer row beats its feedforward alone.
            for ff in ["none", "coulomb", "presliding"] {
                let alone = peak(plant, ff, "none", q);
                let observed = peak(plant, &format!("{ff}+observer"), "none", q);
                assert!(observed < alone, "{plant} {ff}: {observed} vs {alone}");
            }
        }
    }
}
