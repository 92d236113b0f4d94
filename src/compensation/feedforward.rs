//! Friction feedforward through the presliding model (MODEL.md §3).
//!
//! The reference trajectory (x_ref, v_ref) drives a [`Presliding`] state, and
//! the compensation force is
//!
//! ```text
//! u_ff = clamp(gain·(θ·H + σ·v), ±limit),   H = H_r + (d·S(v) − H_r)·g(w)
//! ```
//!
//! with θ the level scale of [`LevelAdaptation`](super::LevelAdaptation)
//! (1 when not adapted; H is linear in Fc and Fs, so scaling both by θ
//! scales H by θ). At a reversal of the reference the force leaves the
//! turning point along g(w) and needs the travel z_max to reach the new
//! steady state, as the real friction does; a sgn(v_ref) feedforward
//! instead steps by 2·Fc at the instant v_ref changes sign while the axis
//! is still stuck in presliding, and kicks it (the quadrant glitch).

use crate::model::Model;
use crate::position::Position;
use crate::presliding::{Presliding, SampleError};
use crate::scalar::Scalar;

use super::{clamp_symmetric, non_negative, positive, ConfigError, Setting};

/// Settings of a [`Feedforward`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct FeedforwardConfig {
    /// Gain on the model force [-], finite and ≥ 0 (1 compensates the
    /// model fully; below 1 leaves a margin for an over-estimated model).
    pub gain: f32,
    /// Velocity deadband [m/s], ≥ 0: a reference velocity with
    /// |v_ref| ≤ deadband enters the model as 0 (S(0) = Fs, no σ·v), so a
    /// noisy or dithering v_ref around a stop cannot chatter the Stribeck
    /// and viscous parts. The direction still comes from the positions.
    pub deadband: f32,
    /// Force limit [N], > 0: |u_ff| never exceeds it.
    pub limit: f32,
}

impl Default for FeedforwardConfig {
    /// Gain 1, no deadband, no limit (`f32::MAX`).
    fn default() -> Self {
        Self {
            gain: 1.0,
            deadband: 0.0,
            limit: f32::MAX,
        }
    }
}

/// Presliding friction feedforward for one axis.
///
/// `P` is the position type of [`Presliding`] (`f32` metres, or `i32`/`i64`
/// counts), `N` its turning-point memory (0: the reference rule of
/// MODEL.md §3; N > 0 closes minor loops).
#[derive(Clone, Debug, PartialEq)]
pub struct Feedforward<P: Position<f32, Scale = f32> = f32, const N: usize = 0> {
    config: FeedforwardConfig,
    state: Presliding<P, f32, N>,
    scale: f32,
    force: f32,
}

impl<P: Position<f32, Scale = f32>, const N: usize> Feedforward<P, N> {
    /// A feedforward idle at the reference position `start`, positions in
    /// units of `metres_per_unit` metres.
    ///
    /// ```
    /// use breakaway::compensation::{Feedforward, FeedforwardConfig};
    /// use breakaway::{Model, Params};
    /// let model = Model::<f32>::new(Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3,
    ///     delta: 1.0, sigma: 0.0, z_max: 1e-5, epsilon: 0.0 })?;
    /// let mut ff = Feedforward::<f32>::new(FeedforwardConfig::default(), 0.0, 1.0).unwrap();
    /// let u = ff.update(&model, 2e-6, 1e-4).unwrap(); // 0.2 z_max into presliding
    /// assert!(u > 0.0 && u < 1.0);
    /// # Ok::<(), breakaway::ParamError>(())
    /// ```
    pub fn new(
        config: FeedforwardConfig,
        start: P,
        metres_per_unit: f32,
    ) -> Result<Self, ConfigError> {
        non_negative(config.gain, Setting::Gain)?;
        non_negative(config.deadband, Setting::Deadband)?;
        positive(config.limit, Setting::Limit)?;
        let state = Presliding::new(start, metres_per_unit)
            .map_err(|_| ConfigError(Setting::MetresPerUnit))?;
        Ok(Self {
            config,
            state,
            scale: 1.0,
            force: 0.0,
        })
    }

    /// Feeds the reference sample (`x_ref` in position units, `v_ref`
    /// [m/s]) and returns the compensation force u_ff [N]. A non-finite
    /// sample is rejected and leaves the state unchanged.
    pub fn update(&mut self, model: &Model<f32>, x_ref: P, v_ref: f32) -> Result<f32, SampleError> {
        let v = if libm::fabsf(v_ref) <= self.config.deadband {
            0.0
        } else {
            v_ref
        };
        let f = self.state.update(model, x_ref, v)?;
        let dry = self.state.dry();
        // f − dry = σ·v (saturated): only the dry part scales with θ. Each
        // product is saturated before the sum, so extreme settings give
        // ±∞ at worst (clamped below), never NaN (no 0·∞, no ∞ − ∞).
        let level = (self.config.gain * (self.scale * dry).saturate()).saturate();
        let viscous = (self.config.gain * (f - dry).saturate()).saturate();
        let u = level + viscous;
        self.force = clamp_symmetric(u, self.config.limit);
        Ok(self.force)
    }

    /// Sets the level scale θ on Fc and Fs (from
    /// [`LevelAdaptation`](super::LevelAdaptation)); a non-finite or
    /// non-positive value is ignored. Takes effect from the next sample.
    pub fn set_level_scale(&mut self, scale: f32) {
        if scale.is_finite() && scale > 0.0 {
            self.scale = scale;
        }
    }

    /// The level scale θ [-] in use.
    pub fn level_scale(&self) -> f32 {
        self.scale
    }

    /// The compensation force u_ff [N] of the last accepted sample.
    pub fn force(&self) -> f32 {
        self.force
    }

    /// The model's dry friction H [N] at unit level scale after the last
    /// accepted sample: the regressor of [`LevelAdaptation`](super::LevelAdaptation).
    pub fn dry(&self) -> f32 {
        self.state.dry()
    }

    /// `true` once the reference has left presliding (w = 1 on the current
    /// branch): gross sliding, where the friction level is observable.
    pub fn is_sliding(&self) -> bool {
        self.state.is_sliding()
    }

    /// The presliding state driven by the reference.
    pub fn presliding(&self) -> &Presliding<P, f32, N> {
        &self.state
    }

    /// The settings.
    pub fn config(&self) -> &FeedforwardConfig {
        &self.config
    }

    /// Returns to idle at `start` (the level scale is kept).
    pub fn reset(&mut self, start: P) {
        self.state.reset(start);
        self.force = 0.0;
    }
}
