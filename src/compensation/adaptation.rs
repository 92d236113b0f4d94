//! Online adaptation of the friction levels: a bounded scale θ on Fc and Fs
//! (MODEL.md §2, the `drift` effect of §5: temperature, lubricant, wear).
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
//!   between the directions averages into θ.

use super::{non_negative, positive, ConfigError, Setting, SignalError};

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

/// The level-scale estimator; starts at θ = 1.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelAdaptation {
    step: f32,
    min_scale: f32,
    max_scale: f32,
    min_speed: f32,
    scale: f32,
}

impl LevelAdaptation {
    /// Validates the settings; θ starts at 1.
    pub fn new(config: AdaptationConfig) -> Result<Self, ConfigError> {
        let rate = positive(config.rate, Setting::Rate)?;
        let period = positive(config.period, Setting::Period)?;
        let step = rate * period;
        if !(step.is_finite() && step <= 1.0) {
            return Err(ConfigError(Setting::Rate));
        }
        let min_scale = positive(config.min_scale, Setting::MinScale)?;
        if min_scale > 1.0 {
            return Err(ConfigError(Setting::MinScale));
        }
        let max_scale = positive(config.max_scale, Setting::MaxScale)?;
        if max_scale < 1.0 {
            return Err(ConfigError(Setting::MaxScale));
        }
        let min_speed = non_negative(config.min_speed, Setting::MinSpeed)?;
        Ok(Self {
            step,
            min_scale,
            max_scale,
            min_speed,
            scale: 1.0,
        })
    }

    /// Feeds one sample: the observer's `residual` r [N], the `regressor` H
    /// [N] (model dry friction at unit scale), the `velocity` [m/s] and
    /// whether the model is `sliding` (out of presliding). Returns θ [-].
    /// Frozen unless sliding with |velocity| ≥ min_speed and H ≠ 0; a
    /// non-finite input is rejected and leaves θ unchanged.
    pub fn update(
        &mut self,
        residual: f32,
        regressor: f32,
        velocity: f32,
        sliding: bool,
    ) -> Result<f32, SignalError> {
        if !(residual.is_finite() && regressor.is_finite()) {
            return Err(SignalError::Force);
        }
        if !velocity.is_finite() {
            return Err(SignalError::Velocity);
        }
        if sliding && libm::fabsf(velocity) >= self.min_speed && regressor != 0.0 {
            let next = self.scale + self.step * residual / regressor;
            // NaN cannot arise (finite / non-zero); ±∞ clamps to the bounds.
            self.scale = if next < self.min_scale {
                self.min_scale
            } else if next > self.max_scale {
                self.max_scale
            } else {
                next
            };
        }
        Ok(self.scale)
    }

    /// The scale θ [-].
    pub fn scale(&self) -> f32 {
        self.scale
    }

    /// Returns θ to 1.
    pub fn reset(&mut self) {
        self.scale = 1.0;
    }
}
