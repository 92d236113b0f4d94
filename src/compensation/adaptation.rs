//! Online adaptation of the friction levels: a bounded scale θ on Fc and Fs
//! ([Stribeck curve](crate::model_overview#stribeck-curve); the `drift` of the
//! [effects](crate::model_overview#effects): temperature, lubricant, wear).
//!
//! While the axis slides, the dry friction is d·θ*·S(v) with the unknown
//! true scale θ*, and a feedforward at scale θ leaves the residual
//! r ≈ (θ* − θ)·H, H the model's dry friction at unit scale (the regressor,
//! [`Feedforward::dry`](super::Feedforward::dry)). The normalised gradient
//! step
//!
//! ```text
//! θ ← clamp(θ + γ·T·r/H, θ_min, θ_max)
//! ```
//!
//! makes θ follow θ* as a first-order lag of rate γ [1/s].
//!
//! # Limits
//!
//! - **Frozen** in presliding (the level is not observable there: H is set
//!   by the turning point and the travel, and a model error in z_max would
//!   be read as a level error) and at rest or slow motion (|v| < min_speed,
//!   where the Stribeck part and the observer noise dominate).
//! - **Bounded** to [θ_min, θ_max]: a residual that is not a level error (a
//!   mass error (m − m_n)·a, a viscous error, a position-dependent ripple, a
//!   load force) biases θ, never beyond the bounds. Symmetric strokes
//!   average the mass and ripple terms out.
//! - **Slow**: γ must stay well below the observer bandwidth, since r is the
//!   observer's low-pass estimate; γ·T ≤ 1 is required.
//! - One scale for Fc and Fs together (the shape of S is kept); an asymmetry
//!   between the directions averages into θ. A drift of Fc alone changes
//!   the shape: θ settles at the sliding level and θ·Fs over-compensates
//!   every break-away; [`StictionAdaptation`](super::StictionAdaptation)
//!   scales Fc and Fs − Fc separately.

// Arithmetic here is on the generic number type `T`, whose operators are
// total by the `Scalar` contract (IEEE `f32`; saturating `Q16`): no panic, no
// wrap.
#![allow(clippy::arithmetic_side_effects)]

use super::{clamp, non_negative, positive, setting_in, ConfigError, Setting};
use crate::scalar::{Scalar, Units};
use crate::SampleError;

/// Settings of a [`LevelAdaptation`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct AdaptationConfig {
    /// Adaptation rate γ [1/s], > 0, with γ·period ≤ 1.
    pub rate: f32,
    /// Lower bound θ_min [-] on the scale, > 0 and ≤ 1.
    pub min_scale: f32,
    /// Upper bound θ_max [-] on the scale, ≥ 1.
    pub max_scale: f32,
    /// Speed [m/s], ≥ 0, below which the estimate is frozen.
    pub min_speed: f32,
    /// Sample period T [s], > 0.
    pub period: f32,
}

/// The level-scale estimator; starts at θ = 1. In the number type `T`
/// (`f32`, or [`Q16`](crate::Q16) with forces in units of Fs and velocities
/// in units of V).
///
/// In Q16 the per-sample increment γ·T·r/H is rounded to 2⁻¹⁶: increments
/// below half of that (|r/H| < 2⁻¹⁷/(γ·T), 0.8 % for γ·T = 1e-3) are lost,
/// a deadband on the relative residual.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelAdaptation<T: Scalar = f32> {
    step: ScaleStep<T>,
    scale: T,
}

/// The bounded normalised step θ ← clamp(θ + γ·T·r/H, θ_min, θ_max) and
/// its settings, validated once: the level scale of [`LevelAdaptation`] and
/// the Coulomb scale of [`StictionAdaptation`](super::StictionAdaptation).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct ScaleStep<T: Scalar> {
    /// γ·T [-].
    step: T,
    min_scale: T,
    max_scale: T,
    /// The speed below which θ is frozen (model velocity units).
    pub(super) min_speed: T,
}

impl<T: Scalar> ScaleStep<T> {
    /// Validates γ [1/s], T [s], θ_min, θ_max [-] and the speed [m/s], as
    /// documented on [`AdaptationConfig`].
    pub(super) fn new(
        rate: f32,
        period: f32,
        min_scale: f32,
        max_scale: f32,
        min_speed: f32,
        units: Units,
    ) -> Result<Self, ConfigError> {
        let rate = positive(rate, Setting::Rate)?;
        let period = positive(period, Setting::Period)?;
        let step = rate * period;
        // γ·T can underflow to 0 from two positive settings; a zero step
        // would turn an infinite r/H into 0·∞ = NaN.
        if !(step.is_finite() && step > 0.0 && step <= 1.0) {
            return Err(ConfigError(Setting::Rate));
        }
        let min_scale = positive(min_scale, Setting::MinScale)?;
        if min_scale > 1.0 {
            return Err(ConfigError(Setting::MinScale));
        }
        let max_scale = positive(max_scale, Setting::MaxScale)?;
        if max_scale < 1.0 {
            return Err(ConfigError(Setting::MaxScale));
        }
        let min_speed = non_negative(min_speed, Setting::MinSpeed)?;
        Ok(Self {
            step: setting_in(step, 1.0, Setting::Rate)?,
            min_scale: setting_in(min_scale, 1.0, Setting::MinScale)?,
            max_scale: setting_in(max_scale, 1.0, Setting::MaxScale)?,
            min_speed: setting_in(min_speed, units.velocity, Setting::MinSpeed)?,
        })
    }

    /// θ + γ·T·r/H clamped to [θ_min, θ_max], for a finite r and a finite
    /// H ≠ 0 (NaN cannot arise; ±∞ clamps to the bounds).
    pub(super) fn next(&self, scale: T, residual: T, regressor: T) -> T {
        let next = scale + self.step * (residual / regressor);
        clamp(next, self.min_scale, self.max_scale)
    }
}

impl LevelAdaptation<f32> {
    /// Validates the settings; θ starts at 1.
    pub fn new(config: AdaptationConfig) -> Result<Self, ConfigError> {
        Self::with_units(config, Units::SI)
    }
}

impl<T: Scalar> LevelAdaptation<T> {
    /// Validates the settings for a model with `units`
    /// ([`Model::units`](crate::Model::units)); θ starts at 1.
    pub fn with_units(config: AdaptationConfig, units: Units) -> Result<Self, ConfigError> {
        let AdaptationConfig {
            rate,
            min_scale,
            max_scale,
            min_speed,
            period,
        } = config;
        Ok(Self {
            step: ScaleStep::new(rate, period, min_scale, max_scale, min_speed, units)?,
            scale: T::ONE,
        })
    }

    /// Feeds one sample: the observer's `residual` r [N], the `regressor` H
    /// [N] (model dry friction at unit scale), the `velocity` [m/s] (model
    /// units for fixed point) and whether the model is `sliding` (out of
    /// presliding). Returns θ [-]. Frozen unless sliding with |velocity| ≥
    /// min_speed and H ≠ 0; a non-finite input is rejected and leaves θ
    /// unchanged.
    ///
    /// Wired to a [`Feedforward`](super::Feedforward): its H and sliding
    /// flag are the regressor and the gate, θ goes back to it. Here the
    /// plant's levels are 20 % above the model's, and r is what the
    /// observer would report, the friction the scaled feedforward misses:
    ///
    /// ```
    /// use breakaway::compensation::{AdaptationConfig, Feedforward, FeedforwardConfig,
    ///     LevelAdaptation};
    /// use breakaway::{Model, Params};
    /// let model = Model::<f32>::new(Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3,
    ///     delta: 1.0, sigma: 0.0, z_max: 1e-5, epsilon: 0.0 })?;
    /// let mut ff = Feedforward::<i64>::new(FeedforwardConfig::default(), 0, 1e-8).unwrap();
    /// let config = AdaptationConfig { rate: 5.0, min_scale: 0.5, max_scale: 2.0,
    ///     min_speed: 1e-4, period: 1e-3 };
    /// let mut level = LevelAdaptation::new(config).unwrap();
    /// let v = 5e-3; // m/s: 500 counts of 10 nm per 1 ms period
    /// for k in 0..2000i64 {
    ///     let u_ff = ff.update(&model, 500 * k, v).unwrap();
    ///     let r = 1.2 * ff.dry() - u_ff; // the plant's friction minus the feedforward
    ///     let theta = level.update(r, ff.dry(), v, ff.is_sliding()).unwrap();
    ///     ff.set_level_scale(theta);
    /// }
    /// assert!((level.scale() - 1.2).abs() < 1e-3);
    /// // Frozen in presliding, whatever r says.
    /// assert_eq!(level.update(0.5, ff.dry(), v, false).unwrap(), level.scale());
    /// # Ok::<(), breakaway::ParamError>(())
    /// ```
    pub fn update(
        &mut self,
        residual: T,
        regressor: T,
        velocity: T,
        sliding: bool,
    ) -> Result<T, SampleError> {
        if !(residual.is_finite() && regressor.is_finite()) {
            return Err(SampleError::Force);
        }
        if !velocity.is_finite() {
            return Err(SampleError::Velocity);
        }
        if sliding && velocity.abs() >= self.step.min_speed && regressor != T::ZERO {
            self.scale = self.step.next(self.scale, residual, regressor);
        }
        Ok(self.scale)
    }

    /// The scale θ [-].
    pub fn scale(&self) -> T {
        self.scale
    }

    /// Returns θ to 1.
    pub fn reset(&mut self) {
        self.scale = T::ONE;
    }
}
