//! `exp` and `ln` in `f32` for the per-sample path.
//!
//! `libm`'s `expf` and `logf` evaluate in `f64` internally; on a Cortex-M4F
//! (single-precision FPU) that is software floating point, several hundred
//! cycles per call. These kernels stay in `f32`, with errors of a few units
//! in the last place over their whole domain (measured against `f64` in the
//! tests: `MAX_EXP_ERROR`, `MAX_LN_ERROR`), well inside the model's 1e-5·Fs
//! budget. `libm` remains in use where time does not matter (construction,
//! the phase curve).
//!
//! - `exp(x)`: x = n·ln 2 + r with |r| ≤ ln 2 / 2 (Cody–Waite split of
//!   ln 2), e^r by its Taylor polynomial of degree 7 (truncation < 8e-9
//!   relative), 2ⁿ by building the exponent bits.
//! - `ln(x)`: x = m·2ᵉ with m in [√½, √2), ln m = 2·atanh(s), s = (m − 1)/(m + 1),
//!   |s| ≤ 0.172, by its odd series to s⁹ (truncation < 7e-10).

/// ln 2 split for exact products n·LN2_HI with |n| < 2¹²: high part.
const LN2_HI: f32 = 0.693_145_75;
/// ln 2 − LN2_HI.
const LN2_LO: f32 = 1.428_606_8e-6;
const LOG2_E: f32 = core::f32::consts::LOG2_E;

/// e^x for any `x`: 0 below −87.3 (true value < 1.2e-38), +∞ above 88.7,
/// NaN for NaN.
#[inline]
pub fn exp(x: f32) -> f32 {
    if x < -87.33 {
        return 0.0;
    }
    if x > 88.72 {
        return f32::INFINITY;
    }
    if x.is_nan() {
        return x;
    }
    // n = round(x·log2 e), |n| ≤ 126.
    let t = x * LOG2_E;
    let n = if t < 0.0 {
        (t - 0.5) as i32
    } else {
        (t + 0.5) as i32
    };
    let nf = n as f32;
    let r = (x - nf * LN2_HI) - nf * LN2_LO;
    let p = 1.0
        + r * (1.0
            + r * (0.5
                + r * (1.0 / 6.0
                    + r * (1.0 / 24.0
                        + r * (1.0 / 120.0 + r * (1.0 / 720.0 + r * (1.0 / 5040.0)))))));
    // 2ⁿ with n in [−126, 128): a normal float; 2¹²⁸ is split in two.
    if n > 127 {
        return p * 2.0 * f32::from_bits(((n - 1 + 127) as u32) << 23);
    }
    p * f32::from_bits(((n + 127) as u32) << 23)
}

/// ln x for finite `x > 0`; −∞ for 0 and values below the smallest normal
/// float (callers treat them as 0 travel), NaN for negative `x`, +∞ for +∞.
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
    let bits = x.to_bits();
    let mut e = ((bits >> 23) & 0xff) as i32 - 127;
    let mut m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000);
    if m > core::f32::consts::SQRT_2 {
        m *= 0.5;
        e += 1;
    }
    let s = (m - 1.0) / (m + 1.0);
    let s2 = s * s;
    let series = 1.0 + s2 * (1.0 / 3.0 + s2 * (1.0 / 5.0 + s2 * (1.0 / 7.0 + s2 * (1.0 / 9.0))));
    let ef = e as f32;
    ef * LN2_HI + (2.0 * s * series + ef * LN2_LO)
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::println;

    /// Largest relative error of `exp` over its domain (measured 9.5e-8).
    const MAX_EXP_ERROR: f64 = 1.2e-7;
    /// Largest error of `ln`, absolute below |ln x| = 1, relative above (measured 1.2e-7).
    const MAX_LN_ERROR: f64 = 1.3e-7;

    #[test]
    fn exp_against_f64() {
        let mut worst = 0.0f64;
        let mut x = -87.3f32;
        while x < 88.7 {
            let got = exp(x) as f64;
            let want = (x as f64).exp();
            worst = worst.max(((got - want) / want).abs());
            x += 0.000_731;
        }
        println!("exp: worst relative error {worst:.3e}");
        assert!(worst < MAX_EXP_ERROR, "{worst}");
        assert_eq!(exp(0.0), 1.0);
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
        assert_eq!(ln(1.0), 0.0);
        assert_eq!(ln(0.0), f32::NEG_INFINITY);
        assert_eq!(ln(1e-40), f32::NEG_INFINITY);
        assert!(ln(-1.0).is_nan());
        assert_eq!(ln(f32::INFINITY), f32::INFINITY);
    }
}
