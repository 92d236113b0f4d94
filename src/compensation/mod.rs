//! Friction compensation for a position or velocity loop: what a motion
//! controller links in on top of the friction model.
//!
//! - [`Feedforward`]: the compensation force from the reference trajectory
//!   (x_ref, v_ref) through the [presliding](crate::model_overview#presliding)
//!   model, so that the force ramps through a reversal along the hysteresis
//!   branch H = H_r + (d·S(v) − H_r)·g(w) instead of switching sign as
//!   Fc·sgn(v) does (the cause of quadrant glitches).
//! - [`DisturbanceObserver`]: the nominal-plant inverse m_n·a of the
//!   [plant](crate::model_overview#plant) with a first-order low-pass filter,
//!   estimating the force that the feedforward does not explain (in the
//!   style of Iwasaki, Shibata and Matsui, "Disturbance-observer-based
//!   nonlinear friction compensation in table drive system", IEEE/ASME
//!   Trans. Mechatronics 4(1), 1999, cited by the seed paper).
//! - [`LevelAdaptation`]: a bounded, slow estimator of a common scale on Fc
//!   and Fs (temperature, wear: the `drift` of the
//!   [effects](crate::model_overview#effects)), driven by the observer's
//!   residual while sliding and frozen in presliding and at rest.
//! - [`StictionAdaptation`]: the Coulomb level from sliding and the
//!   stiction excess Fs − Fc from the window after each reversal (the
//!   presliding swing and the break-away), on a feedforward
//!   [with split levels](Feedforward::with_split_levels).
//! - [`VelocityEstimator`]: the velocity from encoder counts, by a
//!   critically damped α–β tracking filter (at low speed a difference of
//!   counts is 0 or one count per period, which the derivative term and the
//!   observer amplify).
//! - [`BreakAwayDetector`]: online break-away detection under a rising force
//!   command; keeps measured (k, F_ba) pairs
//!   ([break-away predictor](crate::model_overview#break-away-predictor)) in
//!   a fixed-capacity buffer for a refit of the predictor on the host.
//!
//! | block | what it computes | model |
//! |---|---|---|
//! | [`Feedforward`] | u_ff = clamp(gain·(θ·H + σ·v), ±limit) from (x_ref, v_ref) through the presliding state machine: at a reversal the force swings along g(w) over z_max of travel instead of stepping by 2·Fc | [presliding](crate::model_overview#presliding) |
//! | [`DisturbanceObserver`] | r = Q(u − m_n·Δv/T − u_ff), Q a first-order low pass of bandwidth g: the force the feedforward does not explain | [plant](crate::model_overview#plant) |
//! | [`LevelAdaptation`] | θ ← clamp(θ + γ·T·r/H, θ_min, θ_max): one scale on Fc and Fs, frozen in presliding and below `min_speed` | [Stribeck curve](crate::model_overview#stribeck-curve), `drift` |
//! | [`StictionAdaptation`] | θ_c as θ above on H_c (the model with S ≡ Fc); θ_s ← clamp(θ_s + κ·Δθ_s, 0, θ_s,max) once per reversal, Δθ_s the least-squares fit of r on the filtered (H_c, H − H_c) from the turning point to sliding at `min_speed` | [Stribeck curve](crate::model_overview#stribeck-curve), [presliding](crate::model_overview#presliding), `drift` |
//! | [`VelocityEstimator`] | v̂ from the position samples (counts): x̂⁻ = x̂ + T·v̂, e = x_m − x̂⁻, x̂ = x̂⁻ + (1 − p²)·e, v̂ += (1 − p)²·e/T, p = exp(−ω_e·T) | [plant](crate::model_overview#plant) (measurement) |
//! | [`BreakAwayDetector<N>`](BreakAwayDetector) | least-squares k of a rising \|u\| at rest, break-away when \|v\| > `break_away_speed`, (k, F_ba, t_ba, predicted) in a `heapless::Deque` of N | [break-away predictor](crate::model_overview#break-away-predictor) |
//! | `hal::PwmForce` (feature `hal`) | force → `embedded_hal::pwm::SetDutyCycle`, `Centered` (50 % = 0 N) or `Magnitude` (+ direction), saturating at ±F_full | – |
//!
//! The blocks of this module need no feature; only the PWM output
//! `hal::PwmForce` needs the feature `hal` (it depends on `embedded-hal`).
//! The closed-loop benchmarks, on the host and on the Cortex-M0 in Q16
//! (ideal runs within 0.3 % of the host's f64 run; the whole Q16 loop in
//! 12.6 KB of flash and 1.4 KB of RAM, `cargo xtask qemu
//! compensation_fixed`), are in the repository's
//! [docs/compensation.md](https://github.com/breakaway-rs/breakaway/blob/main/docs/compensation.md)
//! and [docs/cycle-budget.md](https://github.com/breakaway-rs/breakaway/blob/main/docs/cycle-budget.md).
//!
//! All of it is allocation-free and panic-free; settings are validated
//! once at construction ([`ConfigError`] names the setting) and a non-finite
//! sample is rejected without changing any state.
//!
//! [`Feedforward`], [`DisturbanceObserver`], [`LevelAdaptation`],
//! [`VelocityEstimator`], [`BreakAwayDetector`] (and `hal::PwmForce`) are generic over the number
//! type: the same code runs in `f32` and in [`Q16`](crate::Q16) on an MCU
//! without an FPU. The settings stay in SI units; `with_units(…,
//! model.units())` (for the detector, `new` from the model) converts them
//! once, and the signals are then in the model's units (force in Fs,
//! velocity in V):
//!
//! ```
//! use breakaway::compensation::{DisturbanceObserver, Feedforward, FeedforwardConfig,
//!     ObserverConfig};
//! use breakaway::{Model, Params, Scalar, Q16};
//! let mut model = Model::<Q16>::UNIT_COULOMB;
//! model.set_params(Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3, delta: 1.0,
//!                           sigma: 0.0, z_max: 1e-5, epsilon: 0.0 })?;
//! let units = model.units();
//! let scale = model.position_scale::<i32>(1e-8).unwrap(); // 10 nm counts
//! let mut ff = Feedforward::<i32, Q16>::with_units(
//!     FeedforwardConfig::default(), units, 0, scale).unwrap();
//! let config = ObserverConfig { mass: 1.0, bandwidth: 100.0, period: 1e-3 };
//! let mut dob = DisturbanceObserver::<Q16>::with_units(config, units).unwrap();
//! // Each period: the command of the period just ended, the measured
//! // velocity and the feedforward applied in it go to the observer; the
//! // new command adds the feedforward and the observer's residual r.
//! let (mut command, mut u_ff) = (Q16::ZERO, Q16::ZERO);
//! for count in [0, 20, 60, 120] {
//!     let v = model.velocity(2e-4).unwrap(); // from the counts, in practice
//!     let r = dob.update(command, v, u_ff).unwrap();
//!     u_ff = ff.update(&model, count, v).unwrap();
//!     command = u_ff + r; // plus the controller's own output
//! }
//! assert!(u_ff.to_f32() * units.force > 0.5); // N
//! # Ok::<(), breakaway::ParamError>(())
//! ```
//!
//! ## The velocity loop in Q16.16, for a core without an FPU
//!
//! The README's velocity-loop recipe with every per-sample signal in Q16:
//! the model built in place (no 1.4 KB `f32` model on the stack), the
//! velocity estimated from the counts in the model's units, and the PI
//! gains converted once from SI to model units (force in Fs, velocity in
//! V): kp [N·s/m] times V/Fs; ki [N/m] times V·T/Fs, for an integral kept as
//! the sum of the velocity errors. The loop then runs on integer arithmetic
//! only. Conversions that can leave the Q16 range return `None`;
//! [`Error::Range`](crate::Error::Range) names them, so that one `?` serves
//! the whole function. `cargo xtask qemu velocity_loop_fixed` builds this
//! function, as it stands here, into a Cortex-M0 firmware and measures it:
//! 13.4 KB of flash and 1.5 KB of stack with the release profile of the
//! repository (`lto = true`, `codegen-units = 1`, `opt-level = 3`); with
//! `opt-level = "s"` 14.3 KB and 1.6 KB, with `"z"` 16.9 KB, more than a
//! 16 KiB part holds (`CARGO_PROFILE_RELEASE_OPT_LEVEL=z cargo xtask qemu
//! velocity_loop_fixed`).
//!
// The recipe's code is one text for three uses: shown and run here (its
// doctest), and measured on the Cortex-M0 by the `velocity_loop_fixed`
// firmware (`cargo xtask qemu velocity_loop_fixed`). The file is not a
// module of the crate.
#![doc = concat!(
    "```\n",
    "# #[cfg(feature = \"hal\")]\n",
    "# mod recipe {\n",
    include_str!("velocity_loop_q16.rs"),
    "# }\n",
    "# #[cfg(feature = \"hal\")]\n",
    "# fn main() -> Result<(), breakaway::Error> {\n",
    "#     use breakaway::hal::SetDutyCycle;\n",
    "#     struct Timer(u16); // a PWM channel that keeps the last duty\n",
    "#     impl embedded_hal::pwm::ErrorType for Timer {\n",
    "#         type Error = core::convert::Infallible;\n",
    "#     }\n",
    "#     impl SetDutyCycle for Timer {\n",
    "#         fn max_duty_cycle(&self) -> u16 { 4095 }\n",
    "#         fn set_duty_cycle(&mut self, duty: u16) -> Result<(), Self::Error> {\n",
    "#             self.0 = duty;\n",
    "#             Ok(())\n",
    "#         }\n",
    "#     }\n",
    "#     let mut timer = Timer(0);\n",
    "#     let encoder = [0, 0, 40, 160, 400, 800, 1300, 1800, 2300, 2800, 3300];\n",
    "#     let newtons = recipe::velocity_loop(&mut timer, encoder)?;\n",
    "#     assert!(newtons > 1.0 && newtons < 1.5); // sliding now: F = S(v), between Fc and Fs\n",
    "#     assert!(timer.0 > 2048); // a forward force on the timer\n",
    "#     Ok(())\n",
    "# }\n",
    "# #[cfg(not(feature = \"hal\"))]\n",
    "# fn main() {}\n",
    "```\n",
)]
// Arithmetic here is on the generic number type `T`, whose operators are
// total by the `Scalar` contract (IEEE `f32`; saturating `Q16`): no panic, no
// wrap.
#![allow(clippy::arithmetic_side_effects)]

mod adaptation;
mod detection;
mod feedforward;
mod observer;
mod stiction;
mod velocity;

pub use adaptation::{AdaptationConfig, LevelAdaptation};
pub use detection::{Accumulate, BreakAwayDetector, DetectorConfig, Measurement};
pub use feedforward::{Feedforward, FeedforwardConfig};
pub use observer::{DisturbanceObserver, ObserverConfig};
pub use stiction::{StictionAdaptation, StictionConfig};
pub use velocity::{VelocityConfig, VelocityEstimator};

use core::fmt;

use crate::scalar::Scalar;

/// Names a setting of a compensation block.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Setting {
    /// [`FeedforwardConfig::gain`].
    Gain,
    /// [`FeedforwardConfig::deadband`].
    Deadband,
    /// [`FeedforwardConfig::limit`].
    Limit,
    /// [`ObserverConfig::mass`].
    Mass,
    /// [`ObserverConfig::bandwidth`].
    Bandwidth,
    /// The sample period of a block.
    Period,
    /// [`AdaptationConfig::rate`].
    Rate,
    /// [`AdaptationConfig::min_scale`].
    MinScale,
    /// [`AdaptationConfig::max_scale`].
    MaxScale,
    /// [`AdaptationConfig::min_speed`], [`StictionConfig::min_speed`].
    MinSpeed,
    /// [`StictionConfig::reversal_gain`].
    ReversalGain,
    /// [`StictionConfig::max_stiction_scale`].
    MaxStictionScale,
    /// [`DetectorConfig::rest_speed`].
    RestSpeed,
    /// [`DetectorConfig::break_away_speed`].
    BreakAwaySpeed,
    /// [`DetectorConfig::min_rate`].
    MinRate,
    /// The break-away boundary w_b of [`BreakAwayDetector::new`].
    Boundary,
    /// The position scale (metres per position unit).
    MetresPerUnit,
    /// The force at full scale of the `hal` adapter.
    FullScale,
}

impl Setting {
    /// The setting's field name.
    pub const fn key(self) -> &'static str {
        match self {
            Setting::Gain => "gain",
            Setting::Deadband => "deadband",
            Setting::Limit => "limit",
            Setting::Mass => "mass",
            Setting::Bandwidth => "bandwidth",
            Setting::Period => "period",
            Setting::Rate => "rate",
            Setting::MinScale => "min_scale",
            Setting::MaxScale => "max_scale",
            Setting::MinSpeed => "min_speed",
            Setting::ReversalGain => "reversal_gain",
            Setting::MaxStictionScale => "max_stiction_scale",
            Setting::RestSpeed => "rest_speed",
            Setting::BreakAwaySpeed => "break_away_speed",
            Setting::MinRate => "min_rate",
            Setting::Boundary => "w_b",
            Setting::MetresPerUnit => "metres_per_unit",
            Setting::FullScale => "full_scale",
        }
    }
}

/// A setting outside its documented range (NaN and ±∞ included).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ConfigError(pub Setting);

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "setting `{}` is out of range", self.0.key())
    }
}

impl core::error::Error for ConfigError {}

/// `Ok(x)` when `x` is finite and `> 0`, else the setting.
pub(crate) fn positive(x: f32, setting: Setting) -> Result<f32, ConfigError> {
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(ConfigError(setting))
    }
}

/// `Ok(x)` when `x` is finite and `≥ 0`, else the setting.
fn non_negative(x: f32, setting: Setting) -> Result<f32, ConfigError> {
    if x.is_finite() && x >= 0.0 {
        Ok(x)
    } else {
        Err(ConfigError(setting))
    }
}

/// A setting `x` (≥ 0, in SI units of `unit`) in the number type; beyond
/// the type's range it is taken as the largest value (a limit "none" stays
/// none), a positive value that rounds to 0 is out of range.
fn setting_in<T: Scalar>(x: f32, unit: f32, setting: Setting) -> Result<T, ConfigError> {
    let scaled = x / unit;
    match T::from_f32(scaled) {
        Some(t) if t > T::ZERO || scaled == 0.0 => Ok(t),
        None if scaled > 0.0 => Ok(T::MAX),
        _ => Err(ConfigError(setting)),
    }
}

/// Clamps `x` to [lo, hi] (±∞ to the bounds).
#[inline(always)]
fn clamp<T: Scalar>(x: T, lo: T, hi: T) -> T {
    if x < lo {
        lo
    } else if x > hi {
        hi
    } else {
        x
    }
}

/// Clamps `x` to [−limit, limit]; finite for finite `limit`.
#[inline(always)]
fn clamp_symmetric<T: Scalar>(x: T, limit: T) -> T {
    if x > limit {
        limit
    } else if x < -limit {
        -limit
    } else {
        x
    }
}
