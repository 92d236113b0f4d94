//! Online break-away detection ([model](crate::model_overview#break-away-predictor)).
//!
//! While the axis is at rest (|v| ≤ rest_speed, presliding creep included)
//! under a force command whose magnitude rises, the detector fits the force
//! rate k by least squares to |u|(t) since the start of the rise (O(1) per
//! sample, see below). Break-away is the first sample at which |v| exceeds
//! break_away_speed: travel has left presliding and the velocity rises
//! sharply. The measured pair (k, F_ba = |u| there) is stored with the
//! predictor's F_ba and t_ba for that k, in a fixed-capacity buffer (the
//! oldest is dropped when full) from which the predictor's parameters can be
//! refitted on the host (`breakaway-lab`'s fit).
//!
//! The detector re-arms once |v| falls back to rest_speed. A rise starts
//! afresh at every sample at rest where |u| does not grow or u changes sign.
//! The measured F_ba is late by the time the velocity takes from v_b to
//! break_away_speed; choose break_away_speed near the predicted v_b
//! ([`BreakAway::v_b`]), above the velocity noise.
//!
//! # The regression
//!
//! The rise's samples i = 0 … n − 1 (one per rising sample, period T [s])
//! enter relative to its first one, d_i = |u_i| − |u_0| [N]. Two running
//! sums, S = Σ d_i [N] and P = Σ_{m<n−1} S_m [N] (the sum of the partial
//! sums S_m = Σ_{i≤m} d_i), need one addition each per sample and give the
//! least-squares slope
//!
//! ```text
//! Σ (2i − (n − 1))·d_i = (n − 1)·S − 2·P
//! k = 6·((n − 1)·S − 2·P) / (n·(n² − 1)·T)      [N/s]
//! ```
//!
//! with no sum of t² or t·u that would outgrow a fixed-point type. The sums
//! are kept in the number type's [`Accumulate::Sum`]: `f32` for `f32`; for
//! [`Q16`] the raw values in `i64`, exact, so that k carries only the
//! rounding of the one final division. In `f32` the sums round: a rise
//! longer than 10⁵ samples (10 s at 10 kHz) gives no measurement
//! ([`Accumulate::MAX_TICKS`]; after 10⁶ samples k was 9.7e-4 off).
//!
//! # Q16
//!
//! With a `Model<Q16>` the signals are in the model's units (force in Fs,
//! velocity in V, time in seconds). Admitted, besides the ranges of the
//! type (forces within ±32768·Fs):
//!
//! - a sample rate 1/T below 32768 Hz (T > 30.5 µs): an error
//!   ([`Setting::Period`]) otherwise;
//! - rises of up to 52 000 samples, n·(n² − 1)·2¹⁶ < 2⁶³ (52 s at 1 kHz,
//!   5.2 s at 10 kHz), k below 32768·Fs/s and t below 32768 s: beyond, the
//!   sums or the result do not fit and the break-away gives **no
//!   measurement** (never a saturated one);
//! - a rise k·T of at least two resolution steps of the command per
//!   sample, 2·2⁻¹⁶·Fs: min_rate ≥ 2⁻¹⁵·Fs/T [N/s] (0.031·Fs/s at 1 kHz,
//!   0.31·Fs/s at 10 kHz: 0.46 N/s for Fs = 1.5 N), or an error
//!   ([`Setting::MinRate`]) at construction; the detector then measures
//!   no slower rise ("Command resolution" below).
//!
//! Resolution: F_ba and t are rounded to 2⁻¹⁶ (Fs, s); k to 2⁻¹⁶·Fs/s, plus
//! the slope of the command's own quantization, at most 3·2⁻¹⁷·Fs/t (2.3e-5
//! relative for k = 1·Fs/s over t = 1 s). A predicted break-away whose
//! fixed-point evaluation saturated is reported as `None`.
//!
//! # Command resolution
//!
//! A command rounded to the resolution r of the number type
//! ([`Accumulate::RESOLUTION`], 2⁻¹⁶·Fs for [`Q16`]) rises by a whole
//! number of steps per sample. At a ramp of x = k·T/r steps per sample,
//! rounded once (|error| ≤ r/2), the increments are ⌊x⌋ or ⌈x⌉ steps: for
//! x < 1 the command repeats values. At rest each repeat restarts the rise,
//! and once the axis creeps above rest_speed the repeats are skipped like
//! any sample that does not rise, so that k comes out at exactly one step
//! per sample, r/T: measured on the reference dynamics (FIG5, T = 0.1 …
//! 1 ms) 1 % too high at x = 0.99, 15 % at x = 0.87 (0.2 N/s at 10 kHz),
//! 100 % at x = 0.5, and unbiased from x = 1 on. A command rounded once
//! more before (computed in another Q16 unit, say N, then converted:
//! |error| ≤ r) has increments within x ± 2 steps and can repeat values for
//! any x < 2: measured 25 % too high at x = 1.2, 0.9 % at 1.65, unbiased
//! from 1.7 on, and every biased k below 1.7·r/T.
//!
//! Admitted are therefore rises of at least two steps per sample,
//! k·T ≥ 2·r, enforced through min_rate (k < min_rate gives no
//! measurement): [`BreakAwayDetector::new`] rejects a min_rate below
//! 2·r/T. A command within ±r of a ramp of more than two steps per sample
//! never repeats a value, and k has the resolution stated above. (A command further off the ramp,
//! noise above r, falls back at any rate and biases k in either number
//! type: the detector takes a command that rises monotonically up to its
//! rounding.) `f32` has no absolute resolution (r = 0: no bound on
//! min_rate); its spacing, at most 2⁻²³·|u|, would need a rise of more than
//! 2²² samples to matter.

// Arithmetic here is on the generic number type `T`, whose operators are
// total by the `Scalar` contract (IEEE `f32`; saturating `Q16`): no panic, no
// wrap. Integer arithmetic is written with explicit checks.
#![allow(clippy::arithmetic_side_effects)]

use heapless::Deque;

use crate::curves::Curves;
use crate::fixed_point::Q16;
use crate::model::Model;
use crate::predictor::{BreakAway, BreakAwayPredictor, Variant};
use crate::scalar::Scalar;

use super::{non_negative, positive, setting_in, ConfigError, Setting};
use crate::SampleError;

/// Settings of a [`BreakAwayDetector`], in SI units whatever the number
/// type of the model (converted once with [`Model::units`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DetectorConfig {
    /// Sample period T [s], > 0 (for [`Q16`]: > 1/32768 s).
    pub period: f32,
    /// Speed [m/s], ≥ 0, up to which the axis counts as at rest.
    pub rest_speed: f32,
    /// Speed [m/s], > rest_speed, above which the axis has broken away.
    pub break_away_speed: f32,
    /// Smallest force rate k [N/s], > 0, recorded as a ramp; for [`Q16`]
    /// at least two command steps per sample, 2⁻¹⁵·Fs/T (module
    /// documentation, "Command resolution").
    pub min_rate: f32,
}

/// One measured break-away, in the model's units (SI for `f32`; force in
/// Fs and velocity in V for [`Q16`]; time in seconds for both).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Measurement<T = f32> {
    /// Estimated force rate k [N/s] of the rise.
    pub rate: T,
    /// Measured break-away force |u| [N].
    pub force: T,
    /// Time [s] from the start of the rise to its last rising sample before
    /// the break-away.
    pub time: T,
    /// The predictor's break-away for this k (`None` if it failed or
    /// saturated).
    pub predicted: Option<BreakAway<T>>,
}

/// The running sums of a [`BreakAwayDetector`]'s regression in a number
/// type: a wider or exact sum type and the few operations on it. Every
/// operation reports what does not fit as `None` (a non-finite `f32`, an
/// `i64` overflow), never a saturated value.
pub trait Accumulate: Scalar {
    /// The absolute resolution of a value (a force command), the same at
    /// every magnitude: 2⁻¹⁶ for [`Q16`]; 0 for `f32`, whose spacing is
    /// relative.
    const RESOLUTION: Self;
    /// The longest rise [samples] whose sums keep the slope within 2e-4
    /// relative: 10⁵ for `f32`, whose running sums round (k was 9.7e-4
    /// off after 10⁶ samples of a ramp to 100 N, 2.7 % after 4·10⁶ of one
    /// to 1.2 N; within 2e-4 at 10⁵, tested); no limit for [`Q16`] (exact
    /// sums, whose overflow ends a rise at about 52 000 samples). A longer
    /// rise gives no measurement.
    const MAX_TICKS: u32;
    /// A sum of many samples: `f32` for `f32`; for [`Q16`] the raw value
    /// (value·2¹⁶) in `i64`, exact.
    type Sum: Copy + core::fmt::Debug + PartialEq;
    /// The sum 0.
    const SUM_ZERO: Self::Sum;
    /// A number as a sum (exact).
    fn widen(self) -> Self::Sum;
    /// The integer `n` as a sum; `None` when it does not fit.
    fn count(n: u64) -> Option<Self::Sum>;
    /// a + b; `None` when it does not fit.
    fn sum_add(a: Self::Sum, b: Self::Sum) -> Option<Self::Sum>;
    /// a − b; `None` when it does not fit.
    fn sum_sub(a: Self::Sum, b: Self::Sum) -> Option<Self::Sum>;
    /// a·m; `None` when it does not fit.
    fn sum_mul(a: Self::Sum, m: u64) -> Option<Self::Sum>;
    /// num/den·scale in the number type, rounded; `None` when den ≤ 0 or
    /// the result does not fit.
    fn ratio(num: Self::Sum, den: Self::Sum, scale: Self) -> Option<Self>;
}

/// `Some(x)` when `x` is finite.
fn finite(x: f32) -> Option<f32> {
    x.is_finite().then_some(x)
}

impl Accumulate for f32 {
    const RESOLUTION: f32 = 0.0;
    const MAX_TICKS: u32 = 100_000;
    type Sum = f32;
    const SUM_ZERO: f32 = 0.0;
    fn widen(self) -> f32 {
        self
    }
    fn count(n: u64) -> Option<f32> {
        Some(n as f32)
    }
    fn sum_add(a: f32, b: f32) -> Option<f32> {
        finite(a + b)
    }
    fn sum_sub(a: f32, b: f32) -> Option<f32> {
        finite(a - b)
    }
    fn sum_mul(a: f32, m: u64) -> Option<f32> {
        finite(a * m as f32)
    }
    fn ratio(num: f32, den: f32, scale: f32) -> Option<f32> {
        if den > 0.0 {
            finite(num / den * scale)
        } else {
            None
        }
    }
}

/// Sums of raw Q16.16 values in `i64`: exact additions, checked. The one
/// division, at a break-away, is done in `i128` (|num·scale| < 2⁹⁴) and
/// rounded to nearest.
impl Accumulate for Q16 {
    const RESOLUTION: Self = Self::from_bits(1);
    const MAX_TICKS: u32 = u32::MAX;
    type Sum = i64;
    const SUM_ZERO: i64 = 0;
    fn widen(self) -> i64 {
        i64::from(self.to_bits())
    }
    fn count(n: u64) -> Option<i64> {
        i64::try_from(n).ok()?.checked_mul(1 << 16)
    }
    fn sum_add(a: i64, b: i64) -> Option<i64> {
        a.checked_add(b)
    }
    fn sum_sub(a: i64, b: i64) -> Option<i64> {
        a.checked_sub(b)
    }
    fn sum_mul(a: i64, m: u64) -> Option<i64> {
        a.checked_mul(i64::try_from(m).ok()?)
    }
    fn ratio(num: i64, den: i64, scale: Self) -> Option<Self> {
        if den <= 0 {
            return None;
        }
        // Raw result num·scale_raw/den_raw: the 2¹⁶ of num and den cancel.
        let product = i128::from(num).checked_mul(i128::from(scale.to_bits()))?;
        let den = i128::from(den);
        let half = den / 2;
        let rounded = if product >= 0 {
            product.checked_add(half)?.checked_div(den)?
        } else {
            product.checked_sub(half)?.checked_div(den)?
        };
        i32::try_from(rounded).ok().map(Self::from_bits)
    }
}

/// The running least-squares fit of one rise (module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Regression<T: Accumulate> {
    /// |u_0| [N], the first sample of the rise.
    start: T,
    /// The index n − 1 of the last sample: rising samples since the start.
    ticks: u32,
    /// (S, P) [N]; `None` once a sum has overflowed.
    sums: Option<(T::Sum, T::Sum)>,
}

impl<T: Accumulate> Regression<T> {
    /// A rise starting at |u| = `magnitude` [N].
    fn start(magnitude: T) -> Self {
        Self {
            start: magnitude,
            ticks: 0,
            sums: Some((T::SUM_ZERO, T::SUM_ZERO)),
        }
    }

    /// The next rising sample |u| = `magnitude` [N].
    fn add(&mut self, magnitude: T) {
        let Some(ticks) = self.ticks.checked_add(1).filter(|&t| t <= T::MAX_TICKS) else {
            self.sums = None;
            return;
        };
        self.ticks = ticks;
        // Both in [0, MAX]: the difference fits.
        let d = (magnitude - self.start).widen();
        self.sums = self.sums.and_then(|(s, p)| {
            let p = T::sum_add(p, s)?;
            Some((T::sum_add(s, d)?, p))
        });
    }

    /// The slope k [N/s] for the sample rate `rate` = 1/T [1/s]; `None`
    /// below 3 samples or when it does not fit.
    fn slope(&self, rate: T) -> Option<T> {
        let (s, p) = self.sums?;
        if self.ticks < 2 {
            return None;
        }
        let last = u64::from(self.ticks);
        let n = last.checked_add(1)?;
        let numerator = T::sum_sub(T::sum_mul(s, last)?, T::sum_add(p, p)?)?;
        let denominator = T::sum_mul(T::count(n.checked_mul(n)?.checked_sub(1)?)?, n)?;
        T::ratio(T::sum_mul(numerator, 6)?, denominator, rate)
    }

    /// The time [s] from the start to the last sample for the sample rate
    /// `rate` = 1/T [1/s].
    fn time(&self, rate: T) -> Option<T> {
        T::ratio(T::count(u64::from(self.ticks))?, rate.widen(), T::ONE)
    }
}

/// `true` unless `x` is NaN or at the largest magnitude (where `f32`
/// overflow and fixed-point saturation land).
fn within_range<T: Scalar>(x: T) -> bool {
    x < T::MAX && x > -T::MAX
}

/// Online break-away detector keeping the last `N` measurements, in the
/// number type `T` (`f32`, or [`Q16`] with forces in units of Fs and
/// velocities in units of V; the admitted range of `Q16` is in the module
/// documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct BreakAwayDetector<const N: usize, T: Accumulate = f32> {
    predictor: BreakAwayPredictor<T>,
    variant: Variant,
    /// 1/T [1/s].
    sample_rate: T,
    /// [m/s] (model units).
    rest_speed: T,
    /// [m/s] (model units).
    break_away_speed: T,
    /// [N/s] (model units).
    min_rate: T,
    armed: bool,
    fit: Regression<T>,
    /// The last command u [N] (model units).
    last_command: T,
    measurements: Deque<Measurement<T>, N>,
}

impl<const N: usize, T: Accumulate> BreakAwayDetector<N, T> {
    /// A detector predicting with `variant` at the boundary `w_b` for
    /// `model`. The settings stay in SI units and are converted here once
    /// to the model's [`Units`](crate::Units) (force in Fs and velocity in V
    /// for [`Q16`]; a setting beyond the type's range is taken as its
    /// largest value).
    ///
    /// The error names the first setting out of its range
    /// ([`DetectorConfig`]); for [`Q16`] that includes a min_rate below two
    /// command steps per sample, 2⁻¹⁵·Fs/T (0.046 N/s at 1 kHz for the
    /// Fs = 1.5 N below).
    ///
    /// ```
    /// use breakaway::compensation::{BreakAwayDetector, DetectorConfig};
    /// use breakaway::{Model, Params, Variant, Q16};
    /// let params = Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3, delta: 1.0,
    ///                       sigma: 0.0, z_max: 1e-5, epsilon: 0.0 };
    /// let model = Model::<Q16>::new(params)?;
    /// let config = DetectorConfig { period: 1e-3, rest_speed: 1e-5,
    ///                               break_away_speed: 1e-3, min_rate: 0.1 };
    /// let mut detector =
    ///     BreakAwayDetector::<4, Q16>::new(config, &model, Variant::Consistent, 0.95).unwrap();
    /// // A ramp of 2 N/s at rest, then the axis moves at 2 mm/s.
    /// let (rest, moving) = (model.velocity(0.0).unwrap(), model.velocity(2e-3).unwrap());
    /// for i in 0..=700 {
    ///     let u = Q16::from_f32(2.0 * i as f32 * 1e-3 / params.fs).unwrap(); // in Fs
    ///     detector.update(&model, u, rest).unwrap();
    /// }
    /// let u = Q16::from_f32(1.402 / params.fs).unwrap();
    /// let m = detector.update(&model, u, moving).unwrap().unwrap();
    /// assert!((m.rate.to_f32() * params.fs - 2.0).abs() < 1e-4); // N/s
    /// assert!((m.time.to_f32() - 0.7).abs() < 1e-4); // s
    /// # Ok::<(), breakaway::ParamError>(())
    /// ```
    pub fn new<C: Curves<T>>(
        config: DetectorConfig,
        model: &Model<T, C>,
        variant: Variant,
        w_b: f32,
    ) -> Result<Self, ConfigError> {
        let period = positive(config.period, Setting::Period)?;
        let rest = non_negative(config.rest_speed, Setting::RestSpeed)?;
        let fast = positive(config.break_away_speed, Setting::BreakAwaySpeed)?;
        if fast <= rest {
            return Err(ConfigError(Setting::BreakAwaySpeed));
        }
        let min_rate = positive(config.min_rate, Setting::MinRate)?;
        let predictor =
            BreakAwayPredictor::new(model, w_b).map_err(|_| ConfigError(Setting::Boundary))?;
        let units = model.units();
        // The sample rate scales every k: it must be represented, not
        // saturated.
        let sample_rate = T::from_f32(1.0 / period)
            .filter(|r| *r > T::ZERO && within_range(*r))
            .ok_or(ConfigError(Setting::Period))?;
        let rest_speed = setting_in(rest, units.velocity, Setting::RestSpeed)?;
        let break_away_speed = setting_in(fast, units.velocity, Setting::BreakAwaySpeed)?;
        if break_away_speed <= rest_speed {
            return Err(ConfigError(Setting::BreakAwaySpeed));
        }
        let min_rate = setting_in(min_rate, units.force, Setting::MinRate)?;
        // Two resolution steps of the command per sample (module
        // documentation): a slower rise is not resolved. For Q16 the bound
        // 2⁻¹⁵·(1/T) is below 1 and rounded to 2⁻¹⁶, for f32 it is 0.
        if min_rate < (T::RESOLUTION + T::RESOLUTION) * sample_rate {
            return Err(ConfigError(Setting::MinRate));
        }
        Ok(Self {
            predictor,
            variant,
            sample_rate,
            rest_speed,
            break_away_speed,
            min_rate,
            armed: false,
            fit: Regression::start(T::ZERO),
            last_command: T::ZERO,
            measurements: Deque::new(),
        })
    }

    /// Feeds one sample: the force `command` u [N] applied now and the
    /// measured `velocity` [m/s] (model units for fixed point). Returns the
    /// measurement when this sample is a break-away whose rate, force and
    /// time are within range. A non-finite input is rejected and leaves the
    /// state unchanged.
    pub fn update<C: Curves<T>>(
        &mut self,
        model: &Model<T, C>,
        command: T,
        velocity: T,
    ) -> Result<Option<Measurement<T>>, SampleError> {
        if !command.is_finite() {
            return Err(SampleError::Command);
        }
        if !velocity.is_finite() {
            return Err(SampleError::Velocity);
        }
        let speed = velocity.abs();
        let magnitude = command.abs();
        let last = self.last_command;
        self.last_command = command;
        if !self.armed {
            if speed <= self.rest_speed {
                self.armed = true;
                self.fit = Regression::start(magnitude);
            }
            return Ok(None);
        }
        if speed > self.break_away_speed {
            self.armed = false;
            return Ok(self.measure(model, magnitude));
        }
        let rising = magnitude > last.abs() && (command >= T::ZERO) == (last >= T::ZERO);
        if rising {
            self.fit.add(magnitude);
        } else if speed <= self.rest_speed {
            self.fit = Regression::start(magnitude);
        }
        Ok(None)
    }

    /// The measurement of a break-away at |u| = `force` [N], stored; `None`
    /// when the rise is too short, slower than min_rate or out of range.
    fn measure<C: Curves<T>>(&mut self, model: &Model<T, C>, force: T) -> Option<Measurement<T>> {
        let rate = self.fit.slope(self.sample_rate)?;
        if rate < self.min_rate {
            return None;
        }
        let time = self.fit.time(self.sample_rate)?;
        if !(within_range(rate) && within_range(force) && within_range(time)) {
            return None;
        }
        let predicted = self
            .predictor
            .predict(model, self.variant, rate)
            .ok()
            .filter(|p| within_range(p.v_b) && within_range(p.f_ba) && within_range(p.t_ba));
        let measurement = Measurement {
            rate,
            force,
            time,
            predicted,
        };
        if self.measurements.is_full() {
            self.measurements.pop_front();
        }
        // Cannot fail: a slot is free.
        let _ = self.measurements.push_back(measurement);
        Some(measurement)
    }

    /// The stored measurements, oldest first.
    pub fn measurements(&self) -> impl Iterator<Item = &Measurement<T>> {
        self.measurements.iter()
    }

    /// The stored (k [N/s], F_ba [N]) pairs (model units), oldest first.
    pub fn pairs(&self) -> impl Iterator<Item = (T, T)> + '_ {
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
