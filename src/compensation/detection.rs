//! Online break-away detection ([model](crate::model_overview#break-away-predictor)).
//!
//! While the axis is at rest (|v| ≤ rest_speed, presliding creep included)
//! under a force command whose magnitude rises, the detector fits the force
//! rate k by least squares to |u|(t) since the start of the rise (a running
//! Welford-type regression, O(1) per sample). Break-away is the first sample
//! at which |v| exceeds break_away_speed: travel has left presliding and the
//! velocity rises sharply. The measured pair (k, F_ba = |u| there) is stored
//! with the predictor's F_ba and t_ba for that k, in a fixed-capacity buffer
//! (the oldest is dropped when full) from which the predictor's parameters
//! can be refitted on the host (`breakaway-lab`'s fit).
//!
//! The detector re-arms once |v| falls back to rest_speed. A rise starts
//! afresh at every sample at rest where |u| does not grow or u changes sign.
//! The measured F_ba is late by the time the velocity takes from v_b to
//! break_away_speed; choose break_away_speed near the predicted v_b
//! ([`BreakAway::v_b`]), above the velocity noise.

use heapless::Deque;

use crate::model::Model;
use crate::predictor::{BreakAway, BreakAwayPredictor, Variant};

use super::{non_negative, positive, ConfigError, Setting, SignalError};

/// Settings of a [`BreakAwayDetector`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DetectorConfig {
    /// Sample period T [s], > 0.
    pub period: f32,
    /// Speed [m/s], ≥ 0, up to which the axis counts as at rest.
    pub rest_speed: f32,
    /// Speed [m/s], > rest_speed, above which the axis has broken away.
    pub break_away_speed: f32,
    /// Smallest force rate k [N/s], > 0, recorded as a ramp.
    pub min_rate: f32,
}

/// One measured break-away.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Measurement {
    /// Estimated force rate k [N/s] of the rise.
    pub rate: f32,
    /// Measured break-away force |u| [N].
    pub force: f32,
    /// Time [s] from the start of the rise to the break-away.
    pub time: f32,
    /// The predictor's break-away for this k (`None` if it failed).
    pub predicted: Option<BreakAway<f32>>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Regression {
    n: u32,
    mean_t: f32,
    mean_u: f32,
    c_tt: f32,
    c_tu: f32,
}

impl Regression {
    const EMPTY: Self = Self {
        n: 0,
        mean_t: 0.0,
        mean_u: 0.0,
        c_tt: 0.0,
        c_tu: 0.0,
    };

    fn add(&mut self, t: f32, u: f32) {
        self.n = self.n.saturating_add(1);
        let n = self.n as f32;
        let dt = t - self.mean_t;
        self.mean_t += dt / n;
        let du = u - self.mean_u;
        self.mean_u += du / n;
        self.c_tt += dt * (t - self.mean_t);
        self.c_tu += dt * (u - self.mean_u);
    }

    fn slope(&self) -> Option<f32> {
        let k = self.c_tu / self.c_tt;
        (self.n >= 3 && k.is_finite()).then_some(k)
    }
}

/// Online break-away detector keeping the last `N` measurements.
#[derive(Clone, Debug)]
pub struct BreakAwayDetector<const N: usize> {
    config: DetectorConfig,
    predictor: BreakAwayPredictor<f32>,
    variant: Variant,
    armed: bool,
    /// Samples since the start of the rise.
    ticks: u32,
    fit: Regression,
    last_command: f32,
    measurements: Deque<Measurement, N>,
}

impl<const N: usize> BreakAwayDetector<N> {
    /// A detector predicting with `variant` at the boundary `w_b` for
    /// `model`.
    pub fn new(
        config: DetectorConfig,
        model: &Model<f32>,
        variant: Variant,
        w_b: f32,
    ) -> Result<Self, ConfigError> {
        positive(config.period, Setting::Period)?;
        let rest = non_negative(config.rest_speed, Setting::RestSpeed)?;
        let fast = positive(config.break_away_speed, Setting::BreakAwaySpeed)?;
        if fast <= rest {
            return Err(ConfigError(Setting::BreakAwaySpeed));
        }
        positive(config.min_rate, Setting::MinRate)?;
        let predictor =
            BreakAwayPredictor::new(model, w_b).map_err(|_| ConfigError(Setting::Boundary))?;
        Ok(Self {
            config,
            predictor,
            variant,
            armed: false,
            ticks: 0,
            fit: Regression::EMPTY,
            last_command: 0.0,
            measurements: Deque::new(),
        })
    }

    /// Feeds one sample: the force `command` u [N] applied now and the
    /// measured `velocity` [m/s]. Returns the measurement when this sample
    /// is a break-away. A non-finite input is rejected and leaves the state
    /// unchanged.
    pub fn update(
        &mut self,
        model: &Model<f32>,
        command: f32,
        velocity: f32,
    ) -> Result<Option<Measurement>, SignalError> {
        if !command.is_finite() {
            return Err(SignalError::Command);
        }
        if !velocity.is_finite() {
            return Err(SignalError::Velocity);
        }
        let speed = libm::fabsf(velocity);
        let magnitude = libm::fabsf(command);
        let last = self.last_command;
        self.last_command = command;
        if !self.armed {
            if speed <= self.config.rest_speed {
                self.armed = true;
                self.restart(magnitude);
            }
            return Ok(None);
        }
        if speed > self.config.break_away_speed {
            self.armed = false;
            let Some(rate) = self.fit.slope() else {
                return Ok(None);
            };
            if rate < self.config.min_rate {
                return Ok(None);
            }
            let measurement = Measurement {
                rate,
                force: magnitude,
                time: self.ticks as f32 * self.config.period,
                predicted: self.predictor.predict(model, self.variant, rate).ok(),
            };
            if self.measurements.is_full() {
                self.measurements.pop_front();
            }
            // Cannot fail: a slot is free.
            let _ = self.measurements.push_back(measurement);
            return Ok(Some(measurement));
        }
        let rising = magnitude > libm::fabsf(last) && (command >= 0.0) == (last >= 0.0);
        if rising {
            self.ticks = self.ticks.saturating_add(1);
            self.fit
                .add(self.ticks as f32 * self.config.period, magnitude);
        } else if speed <= self.config.rest_speed {
            self.restart(magnitude);
        }
        Ok(None)
    }

    fn restart(&mut self, magnitude: f32) {
        self.ticks = 0;
        self.fit = Regression::EMPTY;
        self.fit.add(0.0, magnitude);
    }

    /// The stored measurements, oldest first.
    pub fn measurements(&self) -> impl Iterator<Item = &Measurement> {
        self.measurements.iter()
    }

    /// The stored (k [N/s], F_ba [N]) pairs, oldest first.
    pub fn pairs(&self) -> impl Iterator<Item = (f32, f32)> + '_ {
        self.measurements.iter().map(|m| (m.rate, m.force))
    }

    /// Number of stored measurements.
    pub fn len(&self) -> usize {
        self.measurements.len()
    }

    /// `true` when no measurement is stored.
    pub fn is_empty(&self) -> bool {
        self.measurements.is_empty()
    }

    /// Forgets the stored measurements.
    pub fn clear(&mut self) {
        self.measurements.clear();
    }
}
