//! `exp` and `ln` in `f32`, without the special-case branches of a general
//! `expf`/`logf`.
//!
//! `libm`'s `expf` and `logf` are general: they branch on special values and on
//! the size of the argument before they reach their polynomial. The model knows
//! more: the Stribeck curve needs e^(−p) for p ≥ 0 only. The kernels here take
//! those domains without the checks, with errors of about two units in the
//! last place (measured against `f64` in the tests: `MAX_EXP_ERROR`,
//! `MAX_LN_ERROR`), far inside the model's 1e-5·Fs budget. The per-sample
//! path no longer calls them ([`curves`](crate::curves) evaluates S from a
//! per-model table and g from a table in flash): they build the Stribeck
//! table at construction, and evaluate S below the table for δ < 0.82.
//! `libm` remains in use for the phase curve.
//!
//! Measured errors: e^(−p) 3.7e-6 relative at p = 87 (growing with p), below
//! 4e-8 absolute for any p; ln 1.3e-7.
//!
//! - e^x: x = n·ln 2 + r with |r| ≤ ln 2 / 2 (Cody–Waite split of ln 2),
//!   e^r by a degree-5 polynomial fitted for the least maximum relative
//!   error on that interval (7.5e-8 before rounding), 2ⁿ by building the
//!   exponent bits.
//! - ln x: x = m·2ᵉ with m in [√½, √2), ln m = 2·atanh(s), s = (m − 1)/(m + 1),
//!   |s| ≤ 0.172, by its odd series to s⁷ (truncation < 3e-8).

/// ln 2 split for exact products n·LN2_HI with |n| < 2¹²: high part.
const LN2_HI: f32 = 0.693_145_75;
/// ln 2 − LN2_HI.
const LN2_LO: f32 = 1.428_606_8e-6;
const LOG2_E: f32 = core::f32::consts::LOG2_E;

/// Coefficients of e^r ≈ Σ Cₖ·rᵏ on |r| ≤ ln 2 / 2 (least maximum
/// relative error, 7.5e-8).
const C0: f32 = 1.000_000_1;
const C1: f32 = 0.999_999_7;
const C2: f32 = 0.499_988_95;
const C3: f32 = 0.166_675_75;
const C4: f32 = 0.041_915_383;
const C5: f32 = 0.008_297_654;

/// e^r for |r| ≤ ln 2 / 2.
#[inline(always)]
fn exp_reduced(r: f32) -> f32 {
    C0 + r * (C1 + r * (C2 + r * (C3 + r * (C4 + r * C5))))
}

/// Coefficients of 2^(−f) ≈ Σ Dₖ·fᵏ on 0 ≤ f < 1 (least maximum relative
/// error, 7.5e-8).
const D0: f32 = 0.999_999_9;
const D1: f32 = -0.693_142_25;
const D2: f32 = 0.240_172_19;
const D3: f32 = -0.055_279_72;
const D4: f32 = 0.009_188_612;
const D5: f32 = -0.000_938_788_3;

/// e^(−p) for p ≥ 0 or p = +∞; 0 beyond p = 87 (true value < 1.7e-38).
///
/// e^(−p) = 2^(−y), y = p·log2 e = n + f: 2^(−n) from the exponent bits,
/// 2^(−f) by polynomial. The rounding of y costs a relative error of about
/// p·4e-8 (3.7e-6 at p = 87), an absolute error below 4e-8 for any p: the
/// model only uses e^(−p) in sums with terms of order 1.
#[inline(always)]
pub fn exp_neg(p: f32) -> f32 {
    if p > 87.0 {
        return 0.0;
    }
    let y = p * LOG2_E;
    let n = y as i32; // ⌊y⌋ in [0, 125]
    let f = y - n as f32;
    let two_f = D0 + f * (D1 + f * (D2 + f * (D3 + f * (D4 + f * D5))));
    // n ≤ 125: the exponent field 127 − n is in [2, 127].
    two_f * f32::from_bits((127i32.wrapping_sub(n) as u32) << 23)
}

/// e^x for any `x`: 0 below −87.33 (true value < 1.2e-38), +∞ above 88.72,
/// NaN for NaN. Relative error 2.2e-7 over the whole range (Cody–Waite
/// reduction).
#[inline]
pub fn exp(x: f32) -> f32 {
    if x.is_nan() {
        return x;
    }
    if x < -87.33 {
        return 0.0;
    }
    if x > 88.72 {
        return f32::INFINITY;
    }
    // n = round(x·log2 e) in [−126, 128].
    let t = x * LOG2_E;
    let n = if t < 0.0 {
        (t - 0.5) as i32
    } else {
        (t + 0.5) as i32
    };
    let nf = n as f32;
    let r = (x - nf * LN2_HI) - nf * LN2_LO;
    // 2ⁿ in two factors: 2¹²⁸ is not a float.
    // n in [−126, 128]: both exponent fields lie in [64, 191].
    let half_n = n.wrapping_div(2);
    let half = f32::from_bits((half_n.wrapping_add(127) as u32) << 23);
    let rest = f32::from_bits((n.wrapping_sub(half_n).wrapping_add(127) as u32) << 23);
    exp_reduced(r) * half * rest
}

/// ln x for a positive normal `x` (no check).
#[inline(always)]
pub fn ln_normal(x: f32) -> f32 {
    let bits = x.to_bits();
    // The exponent field is at most 255: e in [−126, 128].
    let mut e = (((bits >> 23) & 0xff) as i32).wrapping_sub(127);
    let mut m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000);
    if m > core::f32::consts::SQRT_2 {
        m *= 0.5;
        e = e.wrapping_add(1);
    }
    let s = (m - 1.0) / (m + 1.0);
    let s2 = s * s;
    let series = 1.0 + s2 * (1.0 / 3.0 + s2 * (1.0 / 5.0 + s2 * (1.0 / 7.0)));
    let ef = e as f32;
    ef * LN2_HI + (2.0 * s * series + ef * LN2_LO)
}

/// ln x for any `x`: −∞ for 0 and values below the smallest normal float,
/// NaN for negative `x` and NaN, +∞ for +∞.
#[inline]
pub fn ln(x: f32) -> f32 {
    if x.is_nan() || x < 0.0 {
        return f32::NAN;
    }
    if x < f32::MIN_POSITIVE {
        return f32::NEG_INFINITY;
    }
    if x == f32::INFINITY {
        return x;
    }
    ln_normal(x)
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::println;

    /// Largest relative error of `exp_neg` (measured 3.7e-6, growing with p
    /// as its doc says; the absolute error stays below 4e-8).
    const MAX_EXP_NEG_ERROR: f64 = 5e-6;
    /// Largest relative error of `exp` over its domain (measured 2.2e-7).
    const MAX_EXP_ERROR: f64 = 2.5e-7;
    /// Largest error of `ln`, absolute below |ln x| = 1, relative above (measured 1.3e-7).
    const MAX_LN_ERROR: f64 = 1.5e-7;

    #[test]
    fn exp_against_f64() {
        let mut worst = 0.0f64;
        let mut x = -87.3f32;
        while x < 88.72 {
            let got = exp(x) as f64;
            let want = (x as f64).exp();
            worst = worst.max(((got - want) / want).abs());
            x += 0.000_731;
        }
        println!("exp: worst relative error {worst:.3e}");
        assert!(worst < MAX_EXP_ERROR, "{worst}");
        assert!((exp(0.0) - 1.0).abs() <= f32::EPSILON);
        assert!((exp(88.7) as f64 / (88.7f32 as f64).exp() - 1.0).abs() < MAX_EXP_ERROR);
        // e^(−p): absolute error against f64, relative to e^(−p) + 1e-30.
        let mut worst_neg = 0.0f64;
        let mut p = 0.0f32;
        while p < 90.0 {
            let want = (-(p as f64)).exp();
            worst_neg = worst_neg.max((exp_neg(p) as f64 - want).abs() / want.clamp(1e-30, 1.0));
            p += 0.000_173;
        }
        println!("exp_neg: worst relative error {worst_neg:.3e}");
        assert!(worst_neg < MAX_EXP_NEG_ERROR, "{worst_neg}");
        assert_eq!(exp_neg(f32::INFINITY), 0.0);
        assert_eq!(exp_neg(0.0), D0);
        assert_eq!(exp(-100.0), 0.0);
        assert_eq!(exp(f32::NEG_INFINITY), 0.0);
        assert_eq!(exp(100.0), f32::INFINITY);
        assert!(exp(f32::NAN).is_nan());
    }

    #[test]
    fn ln_against_f64() {
        let mut worst = 0.0f64;
        // Every 97th float from the smallest normal to 1e30.
        let mut bits = f32::MIN_POSITIVE.to_bits();
        while bits < 1e30f32.to_bits() {
            let x = f32::from_bits(bits);
            let got = ln(x) as f64;
            let want = (x as f64).ln();
            worst = worst.max((got - want).abs() / want.abs().max(1.0));
            bits += 97;
        }
        println!("ln: worst error {worst:.3e} (absolute, relative above |ln x| = 1)");
        assert!(worst < MAX_LN_ERROR, "{worst}");
        assert!(ln(1.0).abs() < 1e-7);
        assert_eq!(ln(0.0), f32::NEG_INFINITY);
        assert_eq!(ln(1e-40), f32::NEG_INFINITY);
        assert!(ln(-1.0).is_nan());
        assert_eq!(ln(f32::INFINITY), f32::INFINITY);
    }
}
