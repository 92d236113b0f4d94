//! Velocity from encoder counts: a critically damped α–β tracking filter
//! (the measured velocity of the [plant](crate::model_overview#plant) that
//! the derivative term and the [`DisturbanceObserver`](super::DisturbanceObserver)
//! need).
//!
//! At low speed the plain difference of counts over one period is useless:
//! at 1 µm per count and T = 1 ms it is 0 or ±1 mm/s, and the observer
//! (which differentiates the velocity again, ×m_n/T) turns that into force
//! spikes of m_n·1 mm/s / 1 ms = 1 N per kg. The estimator tracks the counts
//! with a constant-velocity model, per period T:
//!
//! ```text
//! x̂⁻ = x̂ + T·v̂                          (prediction)
//! e  = x_m − x̂⁻                          (innovation, from the count x_m)
//! x̂  = x̂⁻ + l₁·e,   v̂ ← v̂ + (l₂/T)·e
//! l₁ = 1 − p²,      l₂ = (1 − p)²,      p = exp(−ω_e·T)
//! ```
//!
//! The error dynamics z² − 2p·z + p² have a double pole at p: a critically
//! damped second-order filter of bandwidth ω_e [rad/s] from the counts to
//! v̂, with no steady lag at constant velocity (type 2). ω_e trades delay
//! against quantisation noise on v̂: the noise grows with ω_e, up to the
//! plain difference of counts (±q/T for a count q) as ω_e·T → ∞ (p → 0).
//!
//! Only differences of positions are used, through
//! [`Position::travel_from`] (wrapping for integer counts), so a 32-bit
//! hardware counter that wraps is fine and the estimate is exact at any
//! distance from the origin. The state is x̂ − x_m (the estimate relative
//! to the last count, in model length units) and T·v̂; both stay small.
//!
//! # Limits
//!
//! - Under a constant acceleration a [m/s²] v̂ lags by about 2·a/ω_e [m/s]
//!   for ω_e·T ≪ 1 (the constant-velocity model), less as ω_e·T grows.
//! - In fixed point (`Q16`) the travel of one period must fit in the model's
//!   length range (128·z_max; above that it saturates) and v̂ saturates at
//!   32768·V.

// Arithmetic here is on the generic number type `T`, whose operators are
// total by the `Scalar` contract (IEEE `f32`; saturating `Q16`): no panic, no
// wrap.
#![allow(clippy::arithmetic_side_effects)]

use super::{positive, setting_in, ConfigError, Setting};
use crate::position::Position;
use crate::scalar::{Scalar, Units};
use crate::SampleError;

/// Settings of a [`VelocityEstimator`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct VelocityConfig {
    /// Bandwidth ω_e [rad/s], > 0: higher follows faster, lower smooths
    /// the count quantisation more (the repository's closed-loop benchmark
    /// uses ω_e·T = 3 at T = 1 ms and 1 µm counts; at ω_e·T = 0.3 its loop
    /// with the observer diverged).
    pub bandwidth: f32,
    /// Sample period T [s], > 0.
    pub period: f32,
}

/// Velocity (and a smoothed position) of one axis from its position samples.
///
/// `P` is the position type (`f32` metres, or `i32`/`i64` encoder counts),
/// `T` the number type (`f32`, or [`Q16`](crate::Q16): lengths in the
/// model's length unit, velocities in units of V).
#[derive(Clone, Debug, PartialEq)]
pub struct VelocityEstimator<P: Position<T> = f32, T: Scalar = f32> {
    scale: P::Scale,
    /// l₁ [-] and l₂ [-].
    l1: T,
    l2: T,
    /// Model velocity units per (model length unit per period).
    rate: T,
    /// The last sample; `None` before the first.
    last: Option<P>,
    /// x̂ − last sample [model length units].
    offset: T,
    /// T·v̂ [model length units per period].
    travel: T,
}

impl<P: Position<f32, Scale = f32>> VelocityEstimator<P, f32> {
    /// An estimator at rest, positions in units of `metres_per_unit` metres
    /// (the metres per count of the encoder, or 1 for positions in metres);
    /// the first sample sets the position.
    ///
    /// ```
    /// use breakaway::compensation::{VelocityConfig, VelocityEstimator};
    /// let config = VelocityConfig { bandwidth: 300.0, period: 1e-3 };
    /// let mut estimator = VelocityEstimator::<i32>::new(config, 1e-6).unwrap(); // 1 µm counts
    /// // 2.5 mm/s: 2.5 counts per period, read as whole counts.
    /// let mut v = 0.0;
    /// for n in 0..400 {
    ///     v = estimator.update(n * 5 / 2).unwrap();
    /// }
    /// assert!((v - 2.5e-3).abs() < 0.1e-3); // m/s
    /// ```
    pub fn new(config: VelocityConfig, metres_per_unit: f32) -> Result<Self, ConfigError> {
        Self::with_units(config, Units::SI, metres_per_unit)
    }
}

impl<P: Position<T>, T: Scalar> VelocityEstimator<P, T> {
    /// An estimator in the number type `T` of a model with `units`
    /// ([`Model::units`](crate::Model::units)); `scale` from
    /// [`Model::position_scale`](crate::Model::position_scale). The settings
    /// stay in SI units and are converted here once.
    ///
    /// ```
    /// use breakaway::compensation::{VelocityConfig, VelocityEstimator};
    /// use breakaway::{Model, Params, Scalar, Q16};
    /// let model = Model::<Q16>::new(Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3,
    ///     delta: 1.0, sigma: 0.0, z_max: 1e-5, epsilon: 0.0 })?;
    /// let scale = model.position_scale::<i32>(1e-6).unwrap(); // 1 µm counts
    /// let config = VelocityConfig { bandwidth: 300.0, period: 1e-3 };
    /// let mut estimator =
    ///     VelocityEstimator::<i32, Q16>::with_units(config, model.units(), scale).unwrap();
    /// let mut v = Q16::ZERO;
    /// for n in 0..400 {
    ///     v = estimator.update(n * 5 / 2).unwrap(); // 2.5 mm/s
    /// }
    /// let metres_per_second = v.to_f32() * model.units().velocity;
    /// assert!((metres_per_second - 2.5e-3).abs() < 0.1e-3);
    /// # Ok::<(), breakaway::ParamError>(())
    /// ```
    pub fn with_units(
        config: VelocityConfig,
        units: Units,
        scale: P::Scale,
    ) -> Result<Self, ConfigError> {
        let bandwidth = positive(config.bandwidth, Setting::Bandwidth)?;
        let period = positive(config.period, Setting::Period)?;
        if !P::is_valid_scale(scale) {
            return Err(ConfigError(Setting::MetresPerUnit));
        }
        // 1 − p and p² from expm1 keep their precision at small ω_e·T.
        let one_minus_p = -libm::expm1f(-bandwidth * period);
        if !(one_minus_p > 0.0 && one_minus_p <= 1.0) {
            return Err(ConfigError(Setting::Bandwidth));
        }
        let p = 1.0 - one_minus_p;
        let l1 = 1.0 - p * p;
        let l2 = one_minus_p * one_minus_p;
        // l₂ can underflow (ω_e·T below about 1e-19): no velocity at all.
        if !(l1 > 0.0 && l2 > 0.0) {
            return Err(ConfigError(Setting::Bandwidth));
        }
        let rate = positive(units.length / (period * units.velocity), Setting::Period)?;
        Ok(Self {
            scale,
            l1: setting_in(l1, 1.0, Setting::Bandwidth)?,
            l2: setting_in(l2, 1.0, Setting::Bandwidth)?,
            rate: setting_in(rate, 1.0, Setting::Period)?,
            last: None,
            offset: T::ZERO,
            travel: T::ZERO,
        })
    }

    /// Feeds the position sample of this period (a count, or metres) and
    /// returns v̂ [m/s] (model velocity units for fixed point). The first
    /// sample only sets the position (v̂ = 0). A non-finite sample is
    /// rejected with [`SampleError::Position`] and leaves the state
    /// unchanged.
    pub fn update(&mut self, position: P) -> Result<T, SampleError> {
        if !position.is_valid() {
            return Err(SampleError::Position);
        }
        if let Some(last) = self.last {
            let moved = position.travel_from(last, self.scale);
            // e = x_m − x̂⁻ with x̂⁻ = last + offset + travel.
            let innovation = moved - self.offset - self.travel;
            // x̂ − x_m = x̂⁻ + l₁·e − x_m = −(1 − l₁)·e.
            let offset = self.l1 * innovation - innovation;
            let travel = self.travel + self.l2 * innovation;
            // Overflow of an `f32` travel: keep the state finite.
            if offset.is_finite() && travel.is_finite() {
                self.offset = offset;
                self.travel = travel;
            }
        }
        self.last = Some(position);
        Ok(self.velocity())
    }

    /// v̂ [m/s] (model velocity units) after the last accepted sample.
    pub fn velocity(&self) -> T {
        (self.travel * self.rate).saturate()
    }

    /// x̂ − x_m [m] (model length units): the smoothed position relative to
    /// the last sample, within about a count while tracking.
    pub fn offset(&self) -> T {
        self.offset
    }

    /// Forgets the state; the next sample sets the position again (v̂ = 0).
    pub fn reset(&mut self) {
        self.last = None;
        self.offset = T::ZERO;
        self.travel = T::ZERO;
    }
}
