//! The break-away predictor, after Ruderman's eqs. 12–13
//! ([model](crate::model_overview#break-away-predictor)).
//!
//! Under a force ramp u = k·t from idle, and neglecting inertia in
//! presliding, the velocity at normalised travel w is
//!
//! ```text
//! v(w) = −k·z_max / (F̂·ln w)
//! ```
//!
//! Break-away is placed where w reaches w_b (default 0.95):
//!
//! ```text
//! v_b  = −k·z_max / (F̂·ln w_b)
//! F_ba = S(v_b) + σ·v_b
//! t_ba = (S(v_b)·g(w_b) + σ·v_b) / k
//! ```
//!
//! with F̂ one of four [`Variant`]s. `Consistent` takes F̂ = S(v_b), the
//! smallest positive root of v·S(v) = c = −k·z_max/ln w_b, solved by the
//! model's curves ([`Curves::consistent_root`]):
//!
//! - where v·S(v) is monotone — d(v·S)/dv = Fc + (Fs − Fc)·e^(−x)·(1 − δ·x),
//!   x = (v/V)^δ, is least at x = 1 + 1/δ, so (Fs − Fc)·δ ≤ Fc·e^(1 + 1/δ),
//!   every model with Fs ≤ 8.3·Fc at δ = 1 and with Fs ≤ 3.2·Fc at δ = 2
//!   — the root is the only one, and Newton's iteration finds it from
//!   c/S_mean with the slope of the model's Stribeck table: two or three
//!   evaluations of S (`f32`: the segment polynomial and its derivative;
//!   [`Q16`](crate::Q16): the table's cell, the steps from a reciprocal
//!   table, no division instruction);
//! - elsewhere, and as the fallback of the Newton solve, the fixed-point
//!   iteration: the map v ↦ c/S(v) is non-decreasing (S falls with |v|),
//!   so the iteration from c/Fs climbs monotonically to the smallest root;
//!   it stops when the Aitken estimate of the remaining error falls below a
//!   few ulp.
//!
//! The quasi-static result holds while inertia is negligible in presliding,
//! roughly m·k²·z_max / (F̂³·w_b·|ln w_b|³) ≪ 1
//! ([validity](crate::model_overview#break-away-predictor), [known
//! limits](crate::model_overview#known-limits)); beyond that, the full dynamics
//! of the reference simulator are the judge.
//!
//! ```
//! use breakaway::{BreakAwayPredictor, Model, Params, Variant};
//! let model = Model::<f32>::new(Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3,
//!     delta: 1.0, sigma: 0.0, z_max: 1e-5, epsilon: 0.0 })?;
//! // Break-away force under the force ramp u = k·t, k = 2 N/s.
//! let predictor = BreakAwayPredictor::new(&model, 0.95).unwrap();
//! let ba = predictor.predict(&model, Variant::Consistent, 2.0).unwrap();
//! assert!(ba.f_ba > model.params().fc && ba.f_ba < model.params().fs);
//! println!("F_ba = {} N at t = {} s (v_b = {} m/s)", ba.f_ba, ba.t_ba, ba.v_b);
//! # Ok::<(), breakaway::ParamError>(())
//! ```

// Arithmetic here is on the generic number type `T`, whose operators are
// total by the `Scalar` contract (IEEE `f32`; saturating `Q16`): no panic, no
// wrap. Integer arithmetic is written with explicit wrapping or checks.
#![allow(clippy::arithmetic_side_effects)]

use crate::curves::Curves;
use crate::model::Model;
use crate::scalar::Scalar;

/// Which steady-state level F̂ enters v(w) ([break-away
/// predictor](crate::model_overview#break-away-predictor)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Variant {
    /// F̂ = Fc.
    Coulomb,
    /// F̂ = Fs.
    Stiction,
    /// F̂ = (Fc + Fs)/2, the paper's F̂_ss.
    Mean,
    /// F̂ = S(v_b), solved self-consistently (beyond the paper).
    Consistent,
}

impl Variant {
    /// The four variants, in the order of the [model
    /// overview](crate::model_overview#break-away-predictor).
    pub const ALL: [Variant; 4] = [
        Variant::Coulomb,
        Variant::Stiction,
        Variant::Mean,
        Variant::Consistent,
    ];

    /// The variant's name as written in reports and on the command line.
    ///
    /// ```
    /// use breakaway::Variant;
    /// let names = Variant::ALL.map(Variant::name);
    /// assert_eq!(names, ["coulomb", "stiction", "mean", "consistent"]);
    /// ```
    pub const fn name(self) -> &'static str {
        match self {
            Variant::Coulomb => "coulomb",
            Variant::Stiction => "stiction",
            Variant::Mean => "mean",
            Variant::Consistent => "consistent",
        }
    }
}

/// A predicted break-away.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BreakAway<T> {
    /// Velocity at break-away v_b [m/s].
    pub v_b: T,
    /// Break-away force F_ba [N].
    pub f_ba: T,
    /// Time of break-away t_ba [s] after the start of the ramp.
    pub t_ba: T,
}

/// Why a prediction could not be made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum PredictError {
    /// The force rate k is not finite and > 0.
    InvalidRate,
    /// The break-away boundary w_b is not in (0, 1).
    InvalidBoundary,
    /// The normalised travel w of a phase-curve point is not in (0, 1).
    InvalidTravel,
    /// The self-consistent root did not converge (S falls so steeply that
    /// v·S(v) touches the target level tangentially).
    NoConvergence,
}

impl core::fmt::Display for PredictError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            PredictError::InvalidRate => "force rate k must be finite and > 0",
            PredictError::InvalidBoundary => "break-away boundary w_b must be in (0, 1)",
            PredictError::InvalidTravel => "normalised travel w must be in (0, 1)",
            PredictError::NoConvergence => "self-consistent break-away velocity did not converge",
        })
    }
}

impl core::error::Error for PredictError {}

/// Predicts break-away for one model and one boundary w_b.
///
/// The constants that involve logarithms are computed once here, so a
/// prediction costs one S(v) evaluation per closed-form variant (two or
/// three, with their slopes, for `Consistent`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BreakAwayPredictor<T> {
    /// The constant τ = z_max/(|ln w_b|·V_unit) [s] of c = v_b·F̂ = k·τ.
    rate: RateScale<T>,
    /// g(w_b).
    shape_at_boundary: T,
}

/// How c = k·τ is formed: by multiplying with τ, or, when τ < 1 s, by
/// dividing by 1/τ, so that a fixed-point τ keeps its relative precision
/// whatever its size.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
enum RateScale<T> {
    Times(T),
    Over(T),
}

/// The default break-away boundary w_b (the paper's z_0.95).
pub const DEFAULT_BOUNDARY: f32 = 0.95;

impl<T: Scalar> BreakAwayPredictor<T> {
    /// A predictor for `model` with the break-away boundary `w_b` in (0, 1).
    pub fn new<C: Curves<T>>(model: &Model<T, C>, w_b: f32) -> Result<Self, PredictError> {
        if !(w_b > 0.0 && w_b < 1.0) {
            return Err(PredictError::InvalidBoundary);
        }
        // v·F̂ = k·z_max/|ln w_b|, in model units (time in seconds).
        let tau = -model.params().z_max / (libm::logf(w_b) * model.units().velocity);
        let rate = if tau >= 1.0 {
            T::from_f32(tau).map(RateScale::Times)
        } else {
            T::from_f32(1.0 / tau).map(RateScale::Over)
        };
        match (rate, T::from_f32(crate::curves::shape_f32(w_b))) {
            (Some(rate), Some(shape_at_boundary)) if tau.is_finite() && tau > 0.0 => Ok(Self {
                rate,
                shape_at_boundary,
            }),
            _ => Err(PredictError::InvalidBoundary),
        }
    }

    /// The break-away under the force rate `k` (model force units per
    /// second: N/s for `f32`) with the level F̂ of `variant`; v_b and F_ba come
    /// in model units, t_ba in seconds.
    pub fn predict<C: Curves<T>>(
        &self,
        model: &Model<T, C>,
        variant: Variant,
        k: T,
    ) -> Result<BreakAway<T>, PredictError> {
        // Finite and positive (NaN fails both comparisons).
        if !(k > T::ZERO && k <= T::MAX) {
            return Err(PredictError::InvalidRate);
        }
        let c = match self.rate {
            RateScale::Times(tau) => k * tau,
            RateScale::Over(inv_tau) => k.div_approx(inv_tau),
        }
        .saturate();
        let (v_b, s) = match variant {
            // Saturated like the other variants' c/F̂ (a root beyond the
            // number range, found by the fuzzer: Fs = 1e-31 N, c = 6e7).
            Variant::Consistent => model
                .curves
                .consistent_root(c)
                .map(|(v, s)| (v.saturate(), s))
                .ok_or(PredictError::NoConvergence)?,
            _ => {
                let v_b = velocity_for(model, variant, c)?;
                (v_b, model.curves.stribeck(v_b))
            }
        };
        let viscous = (model.sigma * v_b).saturate();
        Ok(BreakAway {
            v_b,
            f_ba: (s + viscous).saturate(),
            t_ba: (s * self.shape_at_boundary + viscous)
                .div_approx(k)
                .saturate(),
        })
    }
}

/// The velocity v with v·F̂ = c [N·m/s] for the level F̂ of `variant`.
fn velocity_for<T: Scalar, C: Curves<T>>(
    model: &Model<T, C>,
    variant: Variant,
    c: T,
) -> Result<T, PredictError> {
    let two = T::ONE + T::ONE;
    let level = match variant {
        Variant::Coulomb => model.fc,
        Variant::Stiction => model.fs,
        Variant::Mean => model.fc + (model.fs - model.fc) / two,
        Variant::Consistent => {
            return match model.curves.consistent_root(c) {
                Some((v, _)) => Ok(v),
                None => Err(PredictError::NoConvergence),
            }
        }
    };
    Ok((c / level).saturate())
}

impl BreakAwayPredictor<f32> {
    /// The paper's phase curve: the presliding velocity v(w) [m/s] at
    /// normalised travel `w` in (0, 1) under the force rate `k` [N/s]
    /// (paper eq. 12 with z_max; `Consistent` solves F̂ = S(v(w))).
    ///
    /// ```
    /// use breakaway::{BreakAwayPredictor, Model, Params, PredictError, Variant};
    /// let p = Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3, delta: 1.0,
    ///                  sigma: 0.0, z_max: 1e-5, epsilon: 0.0 };
    /// let model = Model::<f32>::new(p).unwrap();
    /// let phase = |w| BreakAwayPredictor::phase_velocity(&model, Variant::Mean, 10.0, w);
    /// // The presliding velocity grows along the travel.
    /// assert!(phase(0.2).unwrap() < phase(0.8).unwrap());
    /// assert_eq!(phase(1.0), Err(PredictError::InvalidTravel));
    /// ```
    pub fn phase_velocity<C: Curves<f32>>(
        model: &Model<f32, C>,
        variant: Variant,
        k: f32,
        w: f32,
    ) -> Result<f32, PredictError> {
        if !(k.is_finite() && k > 0.0) {
            return Err(PredictError::InvalidRate);
        }
        if !(w > 0.0 && w < 1.0) {
            return Err(PredictError::InvalidTravel);
        }
        let c = (-k * model.params().z_max / libm::logf(w)).saturate();
        velocity_for(model, variant, c)
    }
}
