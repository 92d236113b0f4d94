//! The Stribeck curve S(v) and the presliding shape g(w) = w·(1 − ln w) in
//! `f32` ([Stribeck curve](crate::model_overview#stribeck-curve),
//! [presliding](crate::model_overview#presliding)).
//!
//! The exponential and logarithm come from [`fastmath`]: single-precision
//! kernels for exactly the domains the model needs (e^(−p) with p ≥ 0, ln w
//! with w in (0, 0.9]), without the special-case branches of a general
//! `expf`/`logf`;
//! [`cargo xtask profile`](https://github.com/breakaway-rs/breakaway/blob/main/docs/cycle-budget.md)
//! shows the cost against `libm` (`naive_libm_update`).

use crate::fastmath;
use crate::params::{Param, ParamError, Params};
use crate::scalar::Curves;

/// The shape exponent δ, with the common values special-cased so that the
/// per-sample path avoids `powf`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
enum Exponent {
    Half,
    One,
    Two,
    General(f32),
}

/// S(v) and g(w) of one validated parameter set, in `f32`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CurvesF32 {
    fc: f32,
    /// Fs − Fc [N].
    rise: f32,
    /// 1/V [s/m].
    inv_v: f32,
    delta: Exponent,
}

impl Curves<f32> for CurvesF32 {
    fn check(p: &Params) -> Result<(), ParamError> {
        if !(1.0 / p.v_stribeck).is_finite() {
            return Err(ParamError::OutOfRange(Param::VStribeck));
        }
        if p.fs > f32::MAX / 4.0 {
            return Err(ParamError::OutOfRange(Param::Fs));
        }
        Ok(())
    }

    fn build(p: &Params) -> Self {
        let delta = if p.delta == 0.5 {
            Exponent::Half
        } else if p.delta == 1.0 {
            Exponent::One
        } else if p.delta == 2.0 {
            Exponent::Two
        } else {
            Exponent::General(p.delta)
        };
        Self {
            fc: p.fc,
            rise: p.fs - p.fc,
            inv_v: 1.0 / p.v_stribeck,
            delta,
        }
    }

    #[inline(always)]
    fn stribeck(&self, v: f32) -> f32 {
        let r = libm::fabsf(v) * self.inv_v;
        let p = match self.delta {
            Exponent::Half => libm::sqrtf(r),
            Exponent::One => r,
            Exponent::Two => r * r,
            // r^δ = e^(δ·ln r); below the smallest normal float r^δ is
            // negligible against 1 for any δ the model meets.
            Exponent::General(d) if (f32::MIN_POSITIVE..f32::INFINITY).contains(&r) => {
                fastmath::exp(d * fastmath::ln_normal(r))
            }
            Exponent::General(_) if r >= f32::MIN_POSITIVE => f32::INFINITY,
            Exponent::General(_) => 0.0,
        };
        // r is never NaN for finite v (inv_v is finite), so p ≥ 0 or +∞ and
        // exp(−p) is in [0, 1]: S stays in [Fc, Fs].
        self.fc + self.rise * fastmath::exp_neg(p)
    }

    #[inline]
    fn shape(&self, w: f32) -> f32 {
        shape_f32(w)
    }
}

/// g(w) = w·(1 − ln w), clamped to g(w ≤ 0) = 0 and g(w ≥ 1) = 1
/// ([presliding](crate::model_overview#presliding)).
///
/// The result never exceeds 1, so a branch H_r + (d·S − H_r)·g(w) stays
/// between its two ends.
#[inline]
pub fn shape_f32(w: f32) -> f32 {
    if w < 1e-30 {
        // g(1e-30) = 7e-29: zero to f32 precision (also for w ≤ 0).
        0.0
    } else if w >= 1.0 {
        1.0
    } else if w > 0.9 {
        // Near w = 1, g is flat (g′ = −ln w → 0) and w·(1 − ln w) would
        // round non-monotonically. With u = 1 − w (exact here),
        // 1 − g = Σₙ≥₂ uⁿ/(n(n − 1)); six terms leave < 2e-10 for u < 0.1,
        // and 1 − (a monotone polynomial with positive coefficients) rounds
        // monotonically.
        let u = 1.0 - w;
        let tail = 1.0 / 20.0 + u * (1.0 / 30.0 + u * (1.0 / 42.0));
        1.0 - u * u * (0.5 + u * (1.0 / 6.0 + u * (1.0 / 12.0 + u * tail)))
    } else {
        w * (1.0 - fastmath::ln_normal(w))
    }
}
