//! Online adaptation of the Coulomb level and of the stiction level, each
//! where it shows ([Stribeck curve](crate::model_overview#stribeck-curve),
//! [presliding](crate::model_overview#presliding); the `drift` of the
//! [effects](crate::model_overview#effects)).
//!
//! H is linear in Fc and in the stiction excess Fs − Fc, turning points
//! included: H = H_c + H_s, H_c the dry friction of the model with S ≡ Fc
//! and H_s = H − H_c ([`Feedforward::with_split_levels`]). A feedforward
//! θ_c·H_c + θ_s·H_s against a plant at (θ_c*, θ_s*) leaves the observer's
//! residual
//!
//! ```text
//! r ≈ (θ_c* − θ_c)·Q[H_c] + (θ_s* − θ_s)·Q[H_s]
//! ```
//!
//! Q the observer's low pass (bandwidth g), applied here to the regressors
//! too, so that they carry the observer's lag.
//!
//! - **Coulomb scale θ_c, from sliding**: while the reference slides with
//!   |v| ≥ min_speed, where H_s has faded, the normalised step
//!   θ_c ← clamp(θ_c + γ·T·r/Q[H_c], θ_c,min, θ_c,max) (a first-order lag
//!   of rate γ [1/s], as [`LevelAdaptation`](super::LevelAdaptation)).
//! - **Stiction scale θ_s, at reversals and break-aways**: from each turning
//!   point of the reference until it slides again at |v| ≥ min_speed (the
//!   presliding swing, the break-away and the Stribeck hump, where H_s
//!   shows), the window's least-squares fit of r on Q[H_s] alone gives the
//!   stiction error Δθ_s = Σ r·Q[H_s] / Σ Q[H_s]²; at the end of the window
//!   θ_s ← clamp(θ_s + κ·Δθ_s, 0, θ_s,max). κ ≤ 1 averages over reversals.
//!   The Coulomb error is not fitted again in the window: it is the sliding
//!   estimate's (θ_c is already there), and the window's two regressors are
//!   too strongly correlated to separate it from the stiction error (on the
//!   repository's closed-loop benchmark the squared correlation is 0.92, so
//!   a joint fit of both multiplies the variance of Δθ_s by
//!   1/(1 − 0.92) ≈ 12: its Δθ_s scattered over −0.8 … +1.0 per window
//!   with a 1 µm encoder, and θ_s followed the last few windows' noise
//!   rather than a drift).
//!
//! # Limits
//!
//! - While θ_c is still away from the plant (after a drift, before the
//!   sliding estimate has followed it, time constant 1/γ), the Coulomb error
//!   (θ_c* − θ_c) leaks into Δθ_s by Σ Q[H_c]·Q[H_s] / Σ Q[H_s]² (about 2 on
//!   the benchmark); θ_s comes back as θ_c settles. A window without
//!   excitation (Σ Q[H_s]² = 0, e.g. a feedforward without split levels) is
//!   skipped.
//! - A model error in z_max, V or δ and a mass error show in the window
//!   too and bias θ_s towards the level that best explains them: θ_s is the
//!   effective stiction level of the motion seen, not the static Fs (on the
//!   benchmark's LuGre plant, Fs − Fc = 0.5 N static, θ_s settles near 0.3).
//! - A change of the presliding distance z_max is not estimated.
//! - In Q16 (forces in units of Fs) the window sums saturate at 32768, a
//!   window of about 32768/|r·Q[H]| samples (a window that slides below
//!   min_speed that long is skipped); the step γ·T·r/Q[H_c] is rounded to
//!   2⁻¹⁶ as in `LevelAdaptation`, and each product in the sums too.

// Arithmetic here is on the generic number type `T`, whose operators are
// total by the `Scalar` contract (IEEE `f32`; saturating `Q16`): no panic, no
// wrap.
#![allow(clippy::arithmetic_side_effects)]

use super::adaptation::ScaleStep;
use super::{clamp, positive, setting_in, ConfigError, Feedforward, Setting};
use crate::position::Position;
use crate::scalar::{Scalar, Units};
use crate::SampleError;

/// Settings of a [`StictionAdaptation`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StictionConfig {
    /// Rate γ [1/s] of the Coulomb scale, > 0, with γ·period ≤ 1.
    pub rate: f32,
    /// Fraction κ [-] of each window's stiction estimate applied, > 0 and
    /// ≤ 1.
    pub reversal_gain: f32,
    /// Bandwidth g [rad/s] of the disturbance observer whose residual is fed
    /// (the regressors are filtered alike), > 0.
    pub bandwidth: f32,
    /// Lower bound θ_c,min [-] on the Coulomb scale, > 0 and ≤ 1.
    pub min_scale: f32,
    /// Upper bound θ_c,max [-] on the Coulomb scale, ≥ 1.
    pub max_scale: f32,
    /// Upper bound θ_s,max [-] on the stiction scale (its lower bound is 0),
    /// ≥ 1.
    pub max_stiction_scale: f32,
    /// Speed [m/s], ≥ 0: the Coulomb scale adapts while sliding at least
    /// this fast; the window of a reversal ends there.
    pub min_speed: f32,
    /// Sample period T [s], > 0.
    pub period: f32,
}

/// The estimator of the Coulomb scale θ_c and the stiction scale θ_s; both
/// start at 1. In the number type `T` (`f32`, or [`Q16`](crate::Q16) with
/// forces in units of Fs and velocities in units of V).
#[derive(Clone, Debug, PartialEq)]
pub struct StictionAdaptation<T: Scalar = f32> {
    /// The Coulomb step (γ·T, θ_c bounds, min_speed).
    step: ScaleStep<T>,
    /// κ [-], α [-].
    gain: T,
    alpha: T,
    max_stiction_scale: T,
    /// θ_c, θ_s [-].
    coulomb: T,
    stiction: T,
    /// Q[H_c], Q[H_s] [N] (model units).
    filtered: [T; 2],
    /// The reference's direction at the last sample.
    direction: i8,
    /// The open window's sums of Q[H_s]² and r·Q[H_s] [N²]; a window is
    /// open from a turning point until sliding at speed, `None` otherwise.
    window: Option<[T; 2]>,
}

impl StictionAdaptation<f32> {
    /// Validates the settings; θ_c = θ_s = 1.
    ///
    /// ```
    /// use breakaway::compensation::{DisturbanceObserver, Feedforward, FeedforwardConfig,
    ///     ObserverConfig, StictionAdaptation, StictionConfig};
    /// use breakaway::{Model, Params};
    /// let model = Model::<f32>::new(Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3,
    ///     delta: 1.0, sigma: 0.0, z_max: 1e-5, epsilon: 0.0 })?;
    /// let mut ff = Feedforward::<f32>::new(FeedforwardConfig::default(), 0.0, 1.0)
    ///     .unwrap()
    ///     .with_split_levels();
    /// let mut dob = DisturbanceObserver::new(ObserverConfig {
    ///     mass: 1.0, bandwidth: 100.0, period: 1e-3 }).unwrap();
    /// let mut adaptation = StictionAdaptation::new(StictionConfig {
    ///     rate: 1.0, reversal_gain: 0.3, bandwidth: 100.0, min_scale: 0.5,
    ///     max_scale: 2.0, max_stiction_scale: 3.0, min_speed: 1e-3, period: 1e-3,
    /// }).unwrap();
    /// let (mut command, mut u_ff) = (0.0, 0.0);
    /// for n in 0..100 {
    ///     let (x_ref, v_ref, v) = (n as f32 * 1e-5, 1e-2, 1e-2); // m, m/s, m/s
    ///     let r = dob.update(command, v, u_ff).unwrap();
    ///     // `ff` still holds the period just ended: its regressors match r.
    ///     let (coulomb, stiction) = adaptation.update(r, &ff, v_ref).unwrap();
    ///     ff.set_level_scales(coulomb, stiction);
    ///     u_ff = ff.update(&model, x_ref, v_ref).unwrap();
    ///     command = u_ff + r; // plus the controller's own output
    /// }
    /// assert!((0.5..=2.0).contains(&adaptation.coulomb_scale()));
    /// # Ok::<(), breakaway::ParamError>(())
    /// ```
    pub fn new(config: StictionConfig) -> Result<Self, ConfigError> {
        Self::with_units(config, Units::SI)
    }
}

impl<T: Scalar> StictionAdaptation<T> {
    /// Validates the settings for a model with `units`
    /// ([`Model::units`](crate::Model::units)); θ_c = θ_s = 1.
    pub fn with_units(config: StictionConfig, units: Units) -> Result<Self, ConfigError> {
        let step = ScaleStep::new(
            config.rate,
            config.period,
            config.min_scale,
            config.max_scale,
            config.min_speed,
            units,
        )?;
        let period = config.period;
        let gain = positive(config.reversal_gain, Setting::ReversalGain)?;
        if gain > 1.0 {
            return Err(ConfigError(Setting::ReversalGain));
        }
        let bandwidth = positive(config.bandwidth, Setting::Bandwidth)?;
        let alpha = -libm::expm1f(-bandwidth * period);
        if !(alpha > 0.0 && alpha <= 1.0) {
            return Err(ConfigError(Setting::Bandwidth));
        }
        let max_stiction_scale = positive(config.max_stiction_scale, Setting::MaxStictionScale)?;
        if max_stiction_scale < 1.0 {
            return Err(ConfigError(Setting::MaxStictionScale));
        }
        Ok(Self {
            step,
            gain: setting_in(gain, 1.0, Setting::ReversalGain)?,
            alpha: setting_in(alpha, 1.0, Setting::Bandwidth)?,
            max_stiction_scale: setting_in(max_stiction_scale, 1.0, Setting::MaxStictionScale)?,
            coulomb: T::ONE,
            stiction: T::ONE,
            filtered: [T::ZERO; 2],
            direction: 0,
            window: None,
        })
    }

    /// Feeds one sample: the observer's `residual` r [N] of the period just
    /// ended, the `feedforward` whose force was applied in that period (not
    /// yet updated for the new one: its H_c, H − H_c, direction and sliding
    /// state are the regressors), and the reference `velocity` [m/s] (model
    /// units for fixed point). Returns (θ_c, θ_s) [-] for
    /// [`Feedforward::set_level_scales`]. A non-finite input is rejected and
    /// leaves the state unchanged. On a feedforward without
    /// [split levels](Feedforward::with_split_levels) H − H_c is 0: no window
    /// is conditioned, θ_s stays put and θ_c is a single scale on all of H.
    pub fn update<P: Position<T>, const N: usize>(
        &mut self,
        residual: T,
        feedforward: &Feedforward<P, T, N>,
        velocity: T,
    ) -> Result<(T, T), SampleError> {
        let regressors = [feedforward.coulomb_dry(), feedforward.stiction_dry()];
        if !(residual.is_finite() && regressors.iter().all(|h| h.is_finite())) {
            return Err(SampleError::Force);
        }
        if !velocity.is_finite() {
            return Err(SampleError::Velocity);
        }
        for (q, h) in self.filtered.iter_mut().zip(regressors) {
            *q = *q + self.alpha * (h - *q);
        }
        let [coulomb, stiction] = self.filtered;
        let fast = feedforward.is_sliding() && velocity.abs() >= self.step.min_speed;
        if fast && coulomb != T::ZERO {
            self.coulomb = self.step.next(self.coulomb, residual, coulomb);
        }
        let direction = feedforward.presliding().direction();
        if direction != self.direction && self.direction != 0 {
            self.window = Some([T::ZERO; 2]);
        }
        self.direction = direction;
        if let Some(mut sums) = self.window {
            let terms = [stiction * stiction, residual * stiction];
            for (sum, term) in sums.iter_mut().zip(terms) {
                *sum = (*sum + term.saturate()).saturate();
            }
            if fast {
                self.window = None;
                self.close_window(sums);
            } else {
                self.window = Some(sums);
            }
        }
        Ok((self.coulomb, self.stiction))
    }

    /// The least-squares stiction error of a closed window's `sums`,
    /// applied with gain κ.
    fn close_window(&mut self, sums: [T; 2]) {
        let [ss, rs] = sums;
        // Skip a window without excitation; a saturated sum in Q16 makes the
        // fit meaningless too.
        let finite = sums.iter().all(|s| s.is_finite() && s.abs() < T::MAX);
        if !(ss > T::ZERO && finite) {
            return;
        }
        let error = rs / ss;
        let next = self.stiction + self.gain * error.saturate();
        self.stiction = clamp(next, T::ZERO, self.max_stiction_scale);
    }

    /// The Coulomb scale θ_c [-].
    pub fn coulomb_scale(&self) -> T {
        self.coulomb
    }

    /// The stiction scale θ_s [-] (on Fs − Fc).
    pub fn stiction_scale(&self) -> T {
        self.stiction
    }

    /// Returns θ_c and θ_s to 1 and forgets the window and the filters.
    pub fn reset(&mut self) {
        self.coulomb = T::ONE;
        self.stiction = T::ONE;
        self.filtered = [T::ZERO; 2];
        self.direction = 0;
        self.window = None;
    }
}
