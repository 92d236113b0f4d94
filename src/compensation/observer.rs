//! Disturbance observer: nominal-plant inverse with a low-pass filter
//! ([plant](crate::model_overview#plant)), in the style of Iwasaki, Shibata and Matsui (1999).
//!
//! For the plant m·ẍ = u − F the force the motion reveals over one sample
//! period T, with the command u held constant (zero-order hold), is
//!
//! ```text
//! d_k = u_{k−1} − m_n·(v_k − v_{k−1})/T          (exact mean of F over the period for m_n = m)
//! r_k = r_{k−1} + α·(d_k − e_{k−1} − r_{k−1}),    α = 1 − exp(−g·T)
//! ```
//!
//! a first-order low-pass Q(s) = g/(s + g) of bandwidth g [rad/s] on the
//! force that the *explained* force e (typically the feedforward applied in
//! the same period) does not account for. With e = 0 it is the plain
//! disturbance observer and r estimates the whole friction. Filtering d − e
//! rather than subtracting e from a filtered d gives both the same lag, so a
//! feedforward that switches quickly at a reversal does not appear as a
//! spurious residual.
//!
//! Limits: r lags the true residual by about 1/g; a mass error m − m_n adds
//! (m − m_n)·a to it; the bandwidth is bounded by the velocity noise, which
//! the differentiation amplifies by m_n/T before the filter.

// Arithmetic here is on the generic number type `T`, whose operators are
// total by the `Scalar` contract (IEEE `f32`; saturating `Q16`): no panic, no
// wrap.
#![allow(clippy::arithmetic_side_effects)]

use super::{positive, ConfigError, Setting};
use crate::scalar::{Scalar, Units};
use crate::SampleError;

/// Settings of a [`DisturbanceObserver`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ObserverConfig {
    /// Nominal moving mass m_n [kg] (rotary: kg·m²), > 0.
    pub mass: f32,
    /// Filter bandwidth g [rad/s], > 0.
    pub bandwidth: f32,
    /// Sample period T [s], > 0.
    pub period: f32,
}

/// A first-order disturbance observer on one axis, in the number type `T`
/// (`f32`, or [`Q16`](crate::Q16) with forces in units of Fs and velocities
/// in units of V).
#[derive(Clone, Debug, PartialEq)]
pub struct DisturbanceObserver<T: Scalar = f32> {
    /// m_n/T [kg/s] (model force units per model velocity unit).
    mass_rate: T,
    alpha: T,
    last_velocity: Option<T>,
    estimate: T,
}

impl DisturbanceObserver<f32> {
    /// An observer with zero estimate; the first sample only stores the
    /// velocity.
    ///
    /// ```
    /// use breakaway::compensation::{DisturbanceObserver, ObserverConfig};
    /// let config = ObserverConfig { mass: 2.0, bandwidth: 300.0, period: 1e-4 };
    /// let mut dob = DisturbanceObserver::new(config).unwrap();
    /// // A constant 1.2 N of friction against a 1.2 N command: no acceleration.
    /// for _ in 0..2000 {
    ///     dob.update(1.2, 0.01, 0.0).unwrap();
    /// }
    /// assert!((dob.estimate() - 1.2).abs() < 1e-3);
    /// ```
    pub fn new(config: ObserverConfig) -> Result<Self, ConfigError> {
        Self::with_units(config, Units::SI)
    }
}

impl<T: Scalar> DisturbanceObserver<T> {
    /// An observer in the number type of a model with `units`
    /// ([`Model::units`](crate::Model::units)); the settings stay in SI
    /// units and are converted here once.
    pub fn with_units(config: ObserverConfig, units: Units) -> Result<Self, ConfigError> {
        let mass = positive(config.mass, Setting::Mass)?;
        let bandwidth = positive(config.bandwidth, Setting::Bandwidth)?;
        let period = positive(config.period, Setting::Period)?;
        let mass_rate = positive(mass / period, Setting::Period)?;
        let alpha = -libm::expm1f(-bandwidth * period);
        if !(alpha > 0.0 && alpha <= 1.0) {
            return Err(ConfigError(Setting::Bandwidth));
        }
        let mass_rate = T::from_f32(mass_rate * units.velocity / units.force)
            .filter(|m| *m > T::ZERO)
            .ok_or(ConfigError(Setting::Mass))?;
        let alpha = T::from_f32(alpha)
            .filter(|a| *a > T::ZERO)
            .ok_or(ConfigError(Setting::Bandwidth))?;
        Ok(Self {
            mass_rate,
            alpha,
            last_velocity: None,
            estimate: T::ZERO,
        })
    }

    /// Feeds one sample: `command` u [N] applied during the period that ends
    /// now, the measured `velocity` [m/s] now, and the `explained` force e
    /// [N] (the part of the friction already compensated in that period);
    /// model units for fixed point. Returns the estimate r [N] of the force
    /// not explained. A non-finite input is rejected and leaves the state
    /// unchanged.
    pub fn update(&mut self, command: T, velocity: T, explained: T) -> Result<T, SampleError> {
        if !command.is_finite() {
            return Err(SampleError::Command);
        }
        if !velocity.is_finite() {
            return Err(SampleError::Velocity);
        }
        if !explained.is_finite() {
            return Err(SampleError::Force);
        }
        if let Some(last) = self.last_velocity {
            let revealed = command - self.mass_rate * (velocity - last);
            let next = self.estimate + self.alpha * (revealed - explained - self.estimate);
            // Overflow of extreme inputs: keep the state finite.
            if next.is_finite() {
                self.estimate = next;
            }
        }
        self.last_velocity = Some(velocity);
        Ok(self.estimate)
    }

    /// The estimate r [N] (model units) after the last accepted sample.
    pub fn estimate(&self) -> T {
        self.estimate
    }

    /// Clears the estimate and the stored velocity.
    pub fn reset(&mut self) {
        self.estimate = T::ZERO;
        self.last_velocity = None;
    }
}
