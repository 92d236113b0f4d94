//! Friction feedforward through the
//! [presliding](crate::model_overview#presliding) model.
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
//! scales H by θ).
//!
//! With [`with_split_levels`](Feedforward::with_split_levels) the
//! Coulomb level and the stiction excess Fs − Fc get scales of their own:
//! a second presliding state on the same reference with S ≡ Fc gives the
//! Coulomb part H_c of H (H is linear in Fc and Fs − Fc, turning points
//! included), and
//!
//! ```text
//! u_ff = clamp(gain·(θ_c·H_c + θ_s·(H − H_c) + σ·v), ±limit)
//! ```
//!
//! with θ_c and θ_s from [`StictionAdaptation`](super::StictionAdaptation). At a reversal of the reference the force leaves the
//! turning point along g(w) and needs the travel z_max to reach the new
//! steady state, as the real friction does; a sgn(v_ref) feedforward
//! instead steps by 2·Fc at the instant v_ref changes sign while the axis
//! is still stuck in presliding, and kicks it (the quadrant glitch).

// Arithmetic here is on the generic number type `T`, whose operators are
// total by the `Scalar` contract (IEEE `f32`; saturating `Q16`): no panic, no
// wrap.
#![allow(clippy::arithmetic_side_effects)]

use crate::curves::Curves;
use crate::model::Model;
use crate::position::Position;
use crate::presliding::{Presliding, SampleError};
use crate::scalar::{Scalar, Units};

use super::{clamp_symmetric, non_negative, positive, setting_in, ConfigError, Setting};

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
/// counts), `T` the number type (`f32`, or [`Q16`](crate::Q16) for an MCU
/// without an FPU: forces in units of Fs, velocities in units of V), `N` the
/// turning-point memory (0: the single-turning-point rule of the
/// [model](crate::model_overview#turning-points-and-deadband); N > 0 closes
/// minor loops).
#[derive(Clone, Debug, PartialEq)]
pub struct Feedforward<P: Position<T> = f32, T: Scalar = f32, const N: usize = 0> {
    config: FeedforwardConfig,
    /// Gain, deadband and limit in model units.
    gain: T,
    deadband: T,
    limit: T,
    state: Presliding<P, T, N>,
    /// The state with S ≡ Fc, when the levels are split.
    coulomb: Option<Presliding<P, T, N>>,
    /// θ_c (θ when not split) and θ_s.
    scale: T,
    stiction_scale: T,
    /// H_c of the last accepted sample (H when not split).
    coulomb_dry: T,
    force: T,
}

impl<P: Position<f32, Scale = f32>, const N: usize> Feedforward<P, f32, N> {
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
        Self::with_units(config, Units::SI, start, metres_per_unit)
    }
}

impl<P: Position<T>, T: Scalar, const N: usize> Feedforward<P, T, N> {
    /// A feedforward in the number type `T` of a model with `units`
    /// ([`Model::units`]), idle at `start`; `scale` from
    /// [`Model::position_scale`]. The settings stay in SI units in
    /// [`config`](Self::config) and are converted here once.
    ///
    /// ```
    /// use breakaway::compensation::{Feedforward, FeedforwardConfig};
    /// use breakaway::{Model, Params, Q16};
    /// let model = Model::<Q16>::new(Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3,
    ///     delta: 1.0, sigma: 0.0, z_max: 1e-5, epsilon: 0.0 })?;
    /// let scale = model.position_scale::<i32>(1e-8).unwrap(); // 10 nm counts
    /// let mut ff = Feedforward::<i32, Q16>::with_units(
    ///     FeedforwardConfig::default(), model.units(), 0, scale).unwrap();
    /// let v = model.velocity(1e-4).unwrap();
    /// let u = ff.update(&model, 200, v).unwrap(); // 2 µm = 0.2 z_max, in units of Fs
    /// let newtons = u.to_f32() * model.units().force;
    /// assert!(newtons > 0.0 && newtons < 1.0);
    /// # Ok::<(), breakaway::ParamError>(())
    /// ```
    pub fn with_units(
        config: FeedforwardConfig,
        units: Units,
        start: P,
        scale: P::Scale,
    ) -> Result<Self, ConfigError> {
        non_negative(config.gain, Setting::Gain)?;
        non_negative(config.deadband, Setting::Deadband)?;
        positive(config.limit, Setting::Limit)?;
        let state =
            Presliding::new(start, scale).map_err(|_| ConfigError(Setting::MetresPerUnit))?;
        Ok(Self {
            gain: setting_in(config.gain, 1.0, Setting::Gain)?,
            deadband: setting_in(config.deadband, units.velocity, Setting::Deadband)?,
            limit: setting_in(config.limit, units.force, Setting::Limit)?,
            config,
            state,
            coulomb: None,
            scale: T::ONE,
            stiction_scale: T::ONE,
            coulomb_dry: T::ZERO,
            force: T::ZERO,
        })
    }

    /// The same feedforward with the Coulomb level and the stiction excess
    /// Fs − Fc scaled separately ([`set_level_scales`](Self::set_level_scales));
    /// call it before the first sample. Each sample then also runs the
    /// presliding state machine with S ≡ Fc (no Stribeck evaluation).
    pub fn with_split_levels(mut self) -> Self {
        self.coulomb = Some(self.state.clone());
        self
    }

    /// Feeds the reference sample (`x_ref` in position units, `v_ref`
    /// [m/s]; model units for fixed point) and returns the compensation
    /// force u_ff [N] (model units). A non-finite sample is rejected and
    /// leaves the state unchanged.
    pub fn update(
        &mut self,
        model: &Model<T, impl Curves<T>>,
        x_ref: P,
        v_ref: T,
    ) -> Result<T, SampleError> {
        let v = if v_ref.abs() <= self.deadband {
            T::ZERO
        } else {
            v_ref
        };
        let f = self.state.update(model, x_ref, v)?;
        let dry = self.state.dry();
        // f − dry = σ·v (saturated): only the dry part scales with θ. Each
        // product is saturated before the sum, so extreme settings give
        // ±∞ at worst (clamped below), never NaN (no 0·∞, no ∞ − ∞).
        let scaled = match self.coulomb.as_mut() {
            None => {
                self.coulomb_dry = dry;
                (self.scale * dry).saturate()
            }
            Some(coulomb) => {
                // The same samples were just accepted: cannot fail.
                coulomb.update_at(model, x_ref, v, true)?;
                self.coulomb_dry = coulomb.dry();
                // |H|, |H_c| ≤ Fs: the difference is in range.
                let excess = dry - self.coulomb_dry;
                ((self.scale * self.coulomb_dry).saturate()
                    + (self.stiction_scale * excess).saturate())
                .saturate()
            }
        };
        let level = (self.gain * scaled).saturate();
        let viscous = (self.gain * (f - dry).saturate()).saturate();
        let u = level + viscous;
        self.force = clamp_symmetric(u, self.limit);
        Ok(self.force)
    }

    /// Sets the level scale θ on Fc and Fs (from
    /// [`LevelAdaptation`](super::LevelAdaptation)); a non-finite or
    /// non-positive value is ignored. Takes effect from the next sample.
    pub fn set_level_scale(&mut self, scale: T) {
        if scale.is_finite() && scale > T::ZERO {
            self.scale = scale;
            self.stiction_scale = scale;
        }
    }

    /// Sets the scale θ_c [-] on the Coulomb part H_c and θ_s [-] on the
    /// stiction part H − H_c (from
    /// [`StictionAdaptation`](super::StictionAdaptation)): the feedforward of
    /// a model with θ_c·Fc and θ_c·Fc + θ_s·(Fs − Fc). Without
    /// [`with_split_levels`](Self::with_split_levels) θ_c scales all of H.
    /// A non-finite θ_c or θ_s, θ_c ≤ 0 or θ_s < 0 is ignored. Takes effect
    /// from the next sample.
    pub fn set_level_scales(&mut self, coulomb: T, stiction: T) {
        if coulomb.is_finite() && coulomb > T::ZERO && stiction.is_finite() && stiction >= T::ZERO {
            self.scale = coulomb;
            self.stiction_scale = stiction;
        }
    }

    /// The level scale θ [-] in use (θ_c when the levels are split).
    pub fn level_scale(&self) -> T {
        self.scale
    }

    /// The scale θ_s [-] on the stiction part H − H_c (θ when the levels
    /// are not split).
    pub fn stiction_scale(&self) -> T {
        self.stiction_scale
    }

    /// The compensation force u_ff [N] (model units) of the last accepted
    /// sample.
    pub fn force(&self) -> T {
        self.force
    }

    /// The model's dry friction H [N] (model units) at unit level scale
    /// after the last accepted sample: the regressor of
    /// [`LevelAdaptation`](super::LevelAdaptation).
    pub fn dry(&self) -> T {
        self.state.dry()
    }

    /// The Coulomb part H_c [N] (model units) of [`dry`](Self::dry) after
    /// the last accepted sample: H of the model with S ≡ Fc, the regressor
    /// of θ_c in [`StictionAdaptation`](super::StictionAdaptation). H itself
    /// without [`with_split_levels`](Self::with_split_levels).
    pub fn coulomb_dry(&self) -> T {
        self.coulomb_dry
    }

    /// The stiction part H − H_c [N] (model units) after the last accepted
    /// sample: the regressor of θ_s. 0 without
    /// [`with_split_levels`](Self::with_split_levels).
    pub fn stiction_dry(&self) -> T {
        (self.state.dry() - self.coulomb_dry).saturate()
    }

    /// `true` once the reference has left presliding (w = 1 on the current
    /// branch): gross sliding, where the friction level is observable.
    pub fn is_sliding(&self) -> bool {
        self.state.is_sliding()
    }

    /// The presliding state driven by the reference.
    pub fn presliding(&self) -> &Presliding<P, T, N> {
        &self.state
    }

    /// The settings.
    pub fn config(&self) -> &FeedforwardConfig {
        &self.config
    }

    /// Returns to idle at `start` (the level scale is kept).
    pub fn reset(&mut self, start: P) {
        self.state.reset(start);
        if let Some(coulomb) = self.coulomb.as_mut() {
            coulomb.reset(start);
        }
        self.coulomb_dry = T::ZERO;
        self.force = T::ZERO;
    }
}
