//! The quasi-static break-away predictor under a force ramp `u = k·t`
//! (MODEL.md §4, paper eqs. 12–13 with `z_max`).
//!
//! With `c(w) = −k·z_max/ln w > 0` the presliding phase velocity is
//! `v(w) = c(w)/F̂`; break-away is placed at `w_b`:
//! `v_b = c(w_b)/F̂`, `F_ba = S(v_b) + σ·v_b`,
//! `t_ba = (S(v_b)·g(w_b) + σ·v_b)/k`.
//!
//! `F̂` per [`Variant`]: `coulomb` `Fc`, `stiction` `Fs`, `mean` `(Fc + Fs)/2`,
//! `consistent` `S(v_b)` where `v_b` is the smallest positive root of
//! `v·S(v) = c` ([`consistent_root`]).
//!
//! The consistent root is found robustly although `v·S(v)` need not be
//! monotone (e.g. `Fs = 5·Fc`, `δ = 2`): `G(v) = v·S(v)` has
//! `G'(v) = Fc + (Fs − Fc)·e^{−u}·(1 − δ·u)` with `u = (v/V)^δ`, and
//! `e^{−u}(1 − δu)` decreases on `[0, 1 + 1/δ]` and increases after, so `G`
//! has at most one local maximum `v₁` and one local minimum `v₂ > v₁`. The
//! root lies in `[c/Fs, c/Fc]`; if `G(v₁) >= c` it is on the increasing part
//! `[c/Fs, min(v₁, c/Fc)]`, otherwise on `[max(c/Fs, v₁), c/Fc]`, where `G − c`
//! is negative up to the root and non-negative after it. Bisection on that
//! bracket runs to adjacent floats (≈ 1e-16 relative).

use crate::curves::{shape, stribeck};
use crate::model::{ArgumentError, Model, ModelError};
use std::fmt;

/// The choice of `F̂` in the phase velocity (MODEL.md §4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// `F̂ = Fc`.
    Coulomb,
    /// `F̂ = Fs`.
    Stiction,
    /// `F̂ = (Fc + Fs)/2` (the paper's `F̂_ss`).
    Mean,
    /// `F̂ = S(v_b)`, `v_b` the smallest positive root of `v·S(v) = c`.
    Consistent,
}

/// The identifiers of the variants, in declaration order (indexed by the
/// variant).
const NAMES: [&str; 4] = ["coulomb", "stiction", "mean", "consistent"];

impl Variant {
    /// All variants, in the order of MODEL.md §4.
    pub const ALL: [Variant; 4] = [Self::Coulomb, Self::Stiction, Self::Mean, Self::Consistent];

    /// The identifier used in reports and files: `coulomb`, `stiction`,
    /// `mean`, `consistent`.
    pub fn name(self) -> &'static str {
        NAMES[self as usize]
    }

    /// Parses an identifier as written by [`Variant::name`] (exact match).
    pub fn parse(s: &str) -> Option<Variant> {
        Variant::ALL.into_iter().find(|v| v.name() == s)
    }
}

impl fmt::Display for Variant {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Quasi-static break-away prediction (MODEL.md §4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BreakAway {
    /// Velocity at break-away `v_b` [m/s].
    pub v_b: f64,
    /// Break-away force `F_ba = S(v_b) + σ·v_b` [N].
    pub f_ba: f64,
    /// Time of break-away `t_ba = (S(v_b)·g(w_b) + σ·v_b)/k` [s].
    pub t_ba: f64,
}

/// Invalid input to the predictor.
#[derive(Clone, Debug, PartialEq)]
pub enum PredictError {
    /// An argument (`k`, `w_b`, `w`) or the model's `z_max` is out of range.
    Argument(ArgumentError),
    /// The model fails [`Model::validate`].
    Model(ModelError),
}

impl fmt::Display for PredictError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PredictError::Argument(e) => e.fmt(f),
            PredictError::Model(e) => write!(f, "invalid model: {e}"),
        }
    }
}

impl std::error::Error for PredictError {}

impl From<ArgumentError> for PredictError {
    fn from(e: ArgumentError) -> Self {
        PredictError::Argument(e)
    }
}

/// Checks the model, `k` and `w` (named `w_name`) and returns
/// `c = −k·z_max/ln w` [m·N/s].
fn rate_constant(m: &Model, k: f64, w: f64, w_name: &'static str) -> Result<f64, PredictError> {
    m.validate().map_err(PredictError::Model)?;
    if m.z_max.is_nan() || m.z_max <= 0.0 {
        return Err(ArgumentError::new("z_max", m.z_max, "z_max > 0 (presliding)").into());
    }
    if !(k.is_finite() && k > 0.0) {
        return Err(ArgumentError::new("k", k, "finite k > 0").into());
    }
    if !(w > 0.0 && w < 1.0) {
        let requirement = if w_name == "w" {
            "0 < w < 1"
        } else {
            "0 < w_b < 1"
        };
        return Err(ArgumentError::new(w_name, w, requirement).into());
    }
    Ok(-k * m.z_max / w.ln())
}

/// Smallest positive root `v` [m/s] of `v·S(v) = c` for `c > 0` [N·m/s]
/// (the `consistent` variant, see the module doc). Returns 0 for `c <= 0`
/// and NaN for a NaN `c`. `S` is the §2 curve without effects.
pub fn consistent_root(m: &Model, c: f64) -> f64 {
    if c.is_nan() {
        return f64::NAN;
    }
    if c <= 0.0 {
        return 0.0;
    }
    let lo = c / m.fs;
    let hi = c / m.fc;
    let dfs = m.fs - m.fc;
    if dfs.is_nan() || dfs <= 0.0 || lo >= hi {
        return hi;
    }
    let f = |v: f64| v * stribeck(m, v) - c;
    let d = m.delta;
    let u_star = 1.0 + 1.0 / d;
    // G'(u) = Fc + dfs·e^{−u}(1 − δu); non-monotone iff its minimum is < 0.
    let gprime = |u: f64| m.fc + dfs * (-u).exp() * (1.0 - d * u);
    let (mut a, mut b) = (lo, hi);
    if gprime(u_star) < 0.0 {
        // Local maximum of G at u1 in (0, u_star): G' decreasing there.
        let (mut ua, mut ub) = (0.0_f64, u_star);
        for _ in 0..200 {
            let um = 0.5 * (ua + ub);
            if um <= ua || um >= ub {
                break;
            }
            if gprime(um) > 0.0 {
                ua = um;
            } else {
                ub = um;
            }
        }
        let v1 = m.v_stribeck * ua.powf(1.0 / d);
        if f(v1) >= 0.0 {
            b = b.min(v1);
        } else {
            a = a.max(v1);
        }
    }
    // Invariant: f < 0 on [a, root), f >= 0 on [root, b].
    for _ in 0..2000 {
        let mid = 0.5 * (a + b);
        if mid <= a || mid >= b {
            break;
        }
        if f(mid) < 0.0 {
            a = mid;
        } else {
            b = mid;
        }
    }
    if f(a).abs() < f(b).abs() {
        a
    } else {
        b
    }
}

/// `F̂` [N] of `variant` for the constant `c` (consistent: `S(root)`), and
/// the velocity `c/F̂` [m/s].
fn velocity(m: &Model, variant: Variant, c: f64) -> f64 {
    match variant {
        Variant::Coulomb => c / m.fc,
        Variant::Stiction => c / m.fs,
        Variant::Mean => c / (0.5 * (m.fc + m.fs)),
        Variant::Consistent => consistent_root(m, c),
    }
}

/// Quasi-static break-away under `u = k·t` from idle (MODEL.md §4):
/// force rate `k` [N/s] (finite, > 0), boundary `w_b` [-] (`0 < w_b < 1`,
/// default 0.95). Requires a valid model with `z_max > 0`.
pub fn predict_break_away(
    m: &Model,
    variant: Variant,
    k: f64,
    w_b: f64,
) -> Result<BreakAway, PredictError> {
    let c = rate_constant(m, k, w_b, "w_b")?;
    let v_b = velocity(m, variant, c);
    let s = stribeck(m, v_b);
    Ok(BreakAway {
        v_b,
        f_ba: s + m.sigma * v_b,
        t_ba: (s * shape(w_b) + m.sigma * v_b) / k,
    })
}

/// Presliding phase velocity `v(w) = −k·z_max/(F̂·ln w)` [m/s] (paper eq. 12
/// with `z_max`) at normalised travel `w` [-] (`0 < w < 1`) for force rate `k`
/// [N/s]; `consistent` solves `F̂ = S(v(w))` as in the module doc.
pub fn phase_velocity(m: &Model, variant: Variant, k: f64, w: f64) -> Result<f64, PredictError> {
    let c = rate_constant(m, k, w, "w")?;
    Ok(velocity(m, variant, c))
}
