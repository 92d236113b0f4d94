//! Disturbance observer: nominal-plant inverse with a low-pass filter
//! (MODEL.md §1), in the style of Iwasaki, Shibata and Matsui (1999).
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

use super::{positive, ConfigError, Setting, SignalError};

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

/// A first-order disturbance observer on one axis.
#[derive(Clone, Debug, PartialEq)]
pub struct DisturbanceObserver {
    /// m_n/T [kg/s].
    mass_rate: f32,
    alpha: f32,
    last_velocity: Option<f32>,
    estimate: f32,
}

impl DisturbanceObserver {
    /// An observer with zero estimate; the first sample only stores the
    /// velocity.
    pub fn new(config: ObserverConfig) -> Result<Self, ConfigError> {
        let mass = positive(config.mass, Setting::Mass)?;
        let bandwidth = positive(config.bandwidth, Setting::Bandwidth)?;
        let period = positive(config.period, Setting::Period)?;
        let mass_rate = positive(mass / period, Setting::Period)?;
        let alpha = -libm::expm1f(-bandwidth * period);
        if !(alpha > 0.0 && alpha <= 1.0) {
            return Err(ConfigError(Setting::Bandwidth));
        }
        Ok(Self {
            mass_rate,
            alpha,
            last_velocity: None,
            estimate: 0.0,
        })
    }

    /// Feeds one sample: `command` u [N] applied during the period that ends
    /// now, the measured `velocity` [m/s] now, and the `explained` force e
    /// [N] (the part of the friction already compensated in that period).
    /// Returns the estimate r [N] of the force not explained. A non-finite
    /// input is rejected and leaves the state unchanged.
    pub fn update(
        &mut self,
        command: f32,
        velocity: f32,
        explained: f32,
    ) -> Result<f32, SignalError> {
        if !command.is_finite() {
            return Err(SignalError::Command);
        }
        if !velocity.is_finite() {
            return Err(SignalError::Velocity);
        }
        if !explained.is_finite() {
            return Err(SignalError::Force);
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

    /// The estimate r [N] after the last accepted sample.
    pub fn estimate(&self) -> f32 {
        self.estimate
    }

    /// Clears the estimate and the stored velocity.
    pub fn reset(&mut self) {
        self.estimate = 0.0;
        self.last_velocity = None;
    }
}
