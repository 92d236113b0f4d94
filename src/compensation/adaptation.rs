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
//!   between the directions averages into θ.

// Arithmetic here is on the generic number type `T`, whose operators are
// total by the `Scalar` contract (IEEE `f32`; saturating `Q16`): no panic, no
// wrap.
#![allow(clippy::arithmetic_side_effects)]

use super::{non_negative, positive, setting_in, ConfigError, Setting, SignalError};
use crate::model::Model;
use crate::params::Params;
use crate::scalar::{Scalar, Units};

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
    step: T,
    min_scale: T,
    max_scale: T,
    min_speed: T,
    scale: T,
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
        let rate = positive(config.rate, Setting::Rate)?;
        let period = positive(config.period, Setting::Period)?;
        let step = rate * period;
        // γ·T can underflow to 0 from two positive settings; a zero step
        // would turn an infinite r/H into 0·∞ = NaN.
        if !(step.is_finite() && step > 0.0 && step <= 1.0) {
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
            step: setting_in(step, 1.0, Setting::Rate)?,
            min_scale: setting_in(min_scale, 1.0, Setting::MinScale)?,
            max_scale: setting_in(max_scale, 1.0, Setting::MaxScale)?,
            min_speed: setting_in(min_speed, units.velocity, Setting::MinSpeed)?,
            scale: T::ONE,
        })
    }

    /// Feeds one sample: the observer's `residual` r [N], the `regressor` H
    /// [N] (model dry friction at unit scale), the `velocity` [m/s] (model
    /// units for fixed point) and whether the model is `sliding` (out of
    /// presliding). Returns θ [-]. Frozen unless sliding with |velocity| ≥
    /// min_speed and H ≠ 0; a non-finite input is rejected and leaves θ
    /// unchanged.
    pub fn update(
        &mut self,
        residual: T,
        regressor: T,
        velocity: T,
        sliding: bool,
    ) -> Result<T, SignalError> {
        if !(residual.is_finite() && regressor.is_finite()) {
            return Err(SignalError::Force);
        }
        if !velocity.is_finite() {
            return Err(SignalError::Velocity);
        }
        if sliding && velocity.abs() >= self.min_speed && regressor != T::ZERO {
            let next = self.scale + self.step * (residual / regressor);
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
    pub fn scale(&self) -> T {
        self.scale
    }

    /// Returns θ to 1.
    pub fn reset(&mut self) {
        self.scale = T::ONE;
    }
}

/// Regularisation ρ [-] of the information matrix of a
/// [`SplitLevelAdaptation`]: bounds the step in a direction the motion has
/// not excited to (1 + ρ)/ρ times the step of a fully excited one.
pub const SPLIT_REGULARISATION: f32 = 0.05;

/// Separate scales θc on Fc and θs on Fs, for a drift that changes the
/// shape Fs − Fc (a Coulomb level that drifts alone), estimated while
/// sliding from the observer's residual.
///
/// While the axis slides in direction d the dry friction of the model is
/// d·S(v) = d·(Fc + (Fs − Fc)·e(v)), e(v) = exp(−(|v|/V)^δ), linear in the
/// two levels, so the residual of a feedforward at scales (θc, θs) is
///
/// ```text
/// r ≈ (θc* − θc)·φc + (θs* − θs)·φs,   φc = d·Fc·(1 − e(v)),   φs = d·Fs·e(v)
/// ```
///
/// (e is read off the model's own curve, e = (S(v) − Fc)/(Fs − Fc); e = 0
/// when Fs = Fc). φ passes through the same first-order low pass of
/// bandwidth g [rad/s] as the observer's residual (at every sample, frozen
/// or not), so that regressor and residual carry the same lag. The estimate is a least-squares fit with forgetting in
/// information form, on the regressors normalised by |φ|² (so that a scalar
/// fit reduces to the step of [`LevelAdaptation`]):
///
/// ```text
/// R ← (1 − γ·T)·R + γ·T·φφᵀ/|φ|²                      (R starts at the identity)
/// θ ← θ + (1 + ρ)·(R + ρ·I)⁻¹·γ·T·φ·r/|φ|²
/// ```
///
/// then each scale is clamped to [θ_min, θ_max] and θs raised to θc·Fc/Fs
/// where it would fall below (the adapted levels keep Fs ≥ Fc). The
/// direction that the motion always excites (the Coulomb level at speed)
/// follows as a first-order lag of rate γ [1/s]; the stiction level, seen
/// only in the short passages through low speed, gets a step up to
/// (1 + ρ)/ρ times larger, in proportion to how rarely it is excited,
/// with ρ = [`SPLIT_REGULARISATION`].
///
/// The feedforward then runs on the adapted levels: build a model from
/// [`SplitLevelAdaptation::params`] (cheap: validation and a few f32
/// constants) at the adaptation rate and feed it to
/// [`Feedforward::update`](super::Feedforward::update).
///
/// # Limits
///
/// The limits of [`LevelAdaptation`] (frozen in presliding and below
/// `min_speed`, bounded, slow), and: θs is only as good as the model's
/// Stribeck curve. Above `min_speed` e(v) is small, and a plant whose
/// friction falls off faster (or slower) with speed than the model's e(v)
/// biases θs down (up), and a plant still in presliding when the reference
/// is already sliding (a longer z_max) reads as a low Fs. In the closed-loop
/// benchmark of `breakaway-lab` (reversals every 0.5 s) these biases made
/// the reversal error worse than the single scale of [`LevelAdaptation`]
/// on a plant with a 30 % V and z_max error, so the benchmark keeps the
/// single scale; use the split scales where the speed profile dwells in
/// the Stribeck range (e.g. 1…2·V) away from reversals.
#[derive(Clone, Debug, PartialEq)]
pub struct SplitLevelAdaptation {
    step: f32,
    min_scale: f32,
    max_scale: f32,
    min_speed: f32,
    coulomb: f32,
    stiction: f32,
    /// The information matrix R (symmetric): R_cc, R_cs, R_ss.
    info: (f32, f32, f32),
    /// α = 1 − exp(−g·T) of the regressor filter.
    alpha: f32,
    /// The regressor through the observer's low pass.
    filtered: (f32, f32),
}

impl SplitLevelAdaptation {
    /// Validates the settings (the same rules as [`LevelAdaptation::new`])
    /// and the `bandwidth` g [rad/s] > 0 of the regressor filter (the
    /// observer's); θc = θs = 1.
    pub fn new(config: AdaptationConfig, bandwidth: f32) -> Result<Self, ConfigError> {
        let one = LevelAdaptation::new(config)?;
        let bandwidth = positive(bandwidth, Setting::Bandwidth)?;
        let alpha = -libm::expm1f(-bandwidth * one.step / config.rate);
        if !(alpha > 0.0 && alpha <= 1.0) {
            return Err(ConfigError(Setting::Bandwidth));
        }
        Ok(Self {
            step: one.step,
            min_scale: one.min_scale,
            max_scale: one.max_scale,
            min_speed: one.min_speed,
            coulomb: 1.0,
            stiction: 1.0,
            info: (1.0, 0.0, 1.0),
            alpha,
            filtered: (0.0, 0.0),
        })
    }

    /// Feeds one sample: the nominal `model` (unit scales: the regressors
    /// are built from its Fc, Fs and curve), the observer's `residual` r
    /// [N] against the feedforward at the current scales, the `velocity`
    /// [m/s] the feedforward ran at, and whether it is `sliding` (out of
    /// presliding). Returns (θc, θs) [-]. Frozen unless sliding with
    /// |velocity| ≥ min_speed and |velocity| > 0; a non-finite input is
    /// rejected and leaves the state unchanged.
    pub fn update(
        &mut self,
        model: &Model<f32>,
        residual: f32,
        velocity: f32,
        sliding: bool,
    ) -> Result<(f32, f32), SignalError> {
        if !residual.is_finite() {
            return Err(SignalError::Force);
        }
        if !velocity.is_finite() {
            return Err(SignalError::Velocity);
        }
        let speed = libm::fabsf(velocity);
        let active = sliding && speed >= self.min_speed && speed > 0.0;
        self.step_with(model, residual, velocity, active);
        Ok(self.scales())
    }

    /// φ = (d·Fc·(1 − e(v)), d·Fs·e(v)) of the nominal model.
    fn regressor(model: &Model<f32>, velocity: f32) -> (f32, f32) {
        let (fc, fs) = (model.params().fc, model.params().fs);
        let rise = fs - fc;
        let e = if rise > 0.0 {
            clamp((model.stribeck(velocity) - fc) / rise, 0.0, 1.0)
        } else {
            0.0
        };
        let d = if velocity > 0.0 {
            1.0
        } else if velocity < 0.0 {
            -1.0
        } else {
            0.0
        };
        (d * fc * (1.0 - e), d * fs * e)
    }

    fn step_with(&mut self, model: &Model<f32>, residual: f32, velocity: f32, active: bool) {
        let (pc, ps) = Self::regressor(model, velocity);
        let (fc_, fs_) = self.filtered;
        let next = (fc_ + self.alpha * (pc - fc_), fs_ + self.alpha * (ps - fs_));
        if next.0.is_finite() && next.1.is_finite() {
            self.filtered = next;
        }
        if !active {
            return;
        }
        let (pc, ps) = self.filtered;
        let (fc, fs) = (model.params().fc, model.params().fs);
        let norm = pc * pc + ps * ps;
        if !(norm.is_finite() && norm > 0.0) {
            return;
        }
        let (cc, cs, ss) = self.info;
        let keep = 1.0 - self.step;
        let weight = self.step / norm;
        let info = (
            keep * cc + weight * pc * pc,
            keep * cs + weight * pc * ps,
            keep * ss + weight * ps * ps,
        );
        let (gc, gs) = (weight * pc * residual, weight * ps * residual);
        let rho = SPLIT_REGULARISATION;
        let (a, b, c) = (info.0 + rho, info.1, info.2 + rho);
        let det = a * c - b * b;
        let scale = (1.0 + rho) / det;
        let (dc, ds) = (scale * (c * gc - b * gs), scale * (a * gs - b * gc));
        if !(dc.is_finite() && ds.is_finite() && det > 0.0) {
            return;
        }
        self.info = info;
        let bound = |x: f32| clamp(x, self.min_scale, self.max_scale);
        self.coulomb = bound(self.coulomb + dc);
        let floor = self.coulomb * fc / fs;
        let stiction = bound(self.stiction + ds);
        self.stiction = if stiction < floor { floor } else { stiction };
    }

    /// The scales (θc, θs) [-].
    pub fn scales(&self) -> (f32, f32) {
        (self.coulomb, self.stiction)
    }

    /// `nominal` with the adapted levels: Fc·θc [N] and max(Fs·θs, Fc·θc)
    /// [N], the rest unchanged (valid whenever `nominal` is, up to overflow
    /// of the products, which [`Model::new`] reports).
    pub fn params(&self, nominal: &Params) -> Params {
        let fc = nominal.fc * self.coulomb;
        let fs = nominal.fs * self.stiction;
        Params {
            fc,
            fs: if fs < fc { fc } else { fs },
            ..*nominal
        }
    }

    /// Returns θc and θs to 1 and forgets the excitation.
    pub fn reset(&mut self) {
        self.coulomb = 1.0;
        self.stiction = 1.0;
        self.info = (1.0, 0.0, 1.0);
        self.filtered = (0.0, 0.0);
    }
}

/// `x` clamped to [lo, hi] (lo ≤ hi), without a panic path.
fn clamp(x: f32, lo: f32, hi: f32) -> f32 {
    if x < lo {
        lo
    } else if x > hi {
        hi
    } else {
        x
    }
}
