//! The steady-state (Stribeck) curve and the presliding shape function
//! (MODEL.md §2 and §3), without effects.

use crate::model::Model;

/// The Stribeck decay `exp(−(|v|/V)^δ)` (§2) at velocity `v` [m/s] for
/// the Stribeck velocity `v_stribeck` [m/s] and shape exponent `delta`: 1
/// at rest, towards 0 in gross sliding.
pub fn stribeck_decay(v_stribeck: f64, delta: f64, v: f64) -> f64 {
    let r = v.abs() / v_stribeck;
    let p = if delta == 1.0 {
        r
    } else if delta == 2.0 {
        r * r
    } else {
        r.powf(delta)
    };
    decay_of_power(p)
}

/// `exp(−p)` for the power `p = (|v|/V)^δ` of [`stribeck_decay`], for a
/// caller that has the power already.
pub fn decay_of_power(p: f64) -> f64 {
    // exp(−p) is 0 to the last bit beyond p = 745.2 (the smallest
    // subnormal is e^−744.4); its underflow path is slow.
    if p > 746.0 {
        0.0
    } else {
        (-p).exp()
    }
}

/// Stribeck magnitude `Fc + (Fs − Fc)·decay` [N] from the decay of
/// [`stribeck_decay`]; without a dip (`Fs = Fc`) the decay multiplies zero
/// and is not needed (the same bits as the full form).
pub(crate) fn stribeck_from_decay(fc: f64, fs: f64, decay: impl FnOnce() -> f64) -> f64 {
    if fs == fc {
        return fc;
    }
    fc + (fs - fc) * decay()
}

/// Stribeck magnitude with explicit parameters:
/// `Fc + (Fs − Fc)·exp(−(|v|/V)^δ)` [N].
pub(crate) fn stribeck_raw(fc: f64, fs: f64, v_stribeck: f64, delta: f64, v: f64) -> f64 {
    stribeck_from_decay(fc, fs, || stribeck_decay(v_stribeck, delta, v))
}

/// `S(v) = Fc + (Fs − Fc)·exp(−(|v|/V)^δ)` [N] (§2), the magnitude of the
/// steady-state friction at velocity `v` [m/s]; `S(0) = Fs`, `S(±∞) = Fc`.
/// No effects are applied.
pub fn stribeck(m: &Model, v: f64) -> f64 {
    stribeck_raw(m.fc, m.fs, m.v_stribeck, m.delta, v)
}

/// `F_ss(v) = sgn(v)·S(v) + σ·v` [N] (§2) at velocity `v` [m/s]; `sgn(0) = 0`,
/// so `F_ss(0) = 0`.
pub fn steady_state(m: &Model, v: f64) -> f64 {
    let sgn = if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    };
    sgn * stribeck(m, v) + m.sigma * v
}

/// Presliding shape `g(w) = w·(1 − ln w)` [-] (§3) of the normalised travel
/// `w` [-]; `w` is clamped to `[0, 1]`, `g(0) = 0`, `g(1) = 1`, `g'(1) = 0`.
/// A NaN input gives NaN.
pub fn shape(w: f64) -> f64 {
    if w.is_nan() {
        w
    } else if w <= 0.0 {
        0.0
    } else if w >= 1.0 {
        1.0
    } else {
        w * (1.0 - w.ln())
    }
}
