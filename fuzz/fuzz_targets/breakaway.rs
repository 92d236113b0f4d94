//! The break-away predictor with arbitrary parameters, boundaries and rates
//! (f32 and Q16.16). Invariants: valid input gives finite v_b, F_ba, t_ba
//! with Fc ≤ F_ba − σ·v_b ≤ Fs; invalid input is an error, never a panic.
#![no_main]

use breakaway::{BreakAwayPredictor, Model, PredictError, Scalar, Variant, Q16};
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    let mut words = common::Words(data);
    let (Some(params), Some(w_b)) = (words.params(), words.f32()) else { return };
    let Ok(model) = Model::<f32>::new(params) else { return };
    let fixed = Model::<Q16>::new(params).ok();
    let Ok(predictor) = BreakAwayPredictor::new(&model, w_b) else {
        // Rejected only for w_b outside (0, 1) or τ = z_max/|ln w_b| (or
        // 1/τ) beyond the f32 range.
        let tau = params.z_max / w_b.ln().abs();
        let representable = tau.is_finite() && tau > 0.0 && (1.0 / tau).is_finite();
        assert!(!(w_b > 0.0 && w_b < 1.0 && representable), "rejected w_b = {w_b}, {params:?}");
        return;
    };
    let fixed_predictor = fixed.as_ref().and_then(|m| BreakAwayPredictor::new(m, w_b).ok());
    while let Some(k) = words.f32() {
        for variant in Variant::ALL {
            match predictor.predict(&model, variant, k) {
                Ok(ba) => {
                    assert!(k > 0.0 && k.is_finite());
                    assert!(ba.v_b.is_finite() && ba.f_ba.is_finite() && ba.t_ba.is_finite(), "{ba:?}");
                    let dry = ba.f_ba - params.sigma * ba.v_b;
                    let slack = 1e-4 * params.fs;
                    if (params.sigma * ba.v_b).abs() < 1e30 {
                        assert!(dry >= params.fc - slack - 1e-6 * (params.sigma * ba.v_b).abs(), "{ba:?} {params:?}");
                        assert!(dry <= params.fs + slack + 1e-6 * (params.sigma * ba.v_b).abs(), "{ba:?} {params:?}");
                    }
                }
                // A valid rate is refused only where the self-consistent
                // root does not converge; anything else compared nothing.
                Err(PredictError::InvalidRate) => assert!(!(k > 0.0 && k.is_finite()), "valid k = {k} refused"),
                Err(PredictError::NoConvergence) => assert_eq!(variant, Variant::Consistent, "k = {k}"),
                Err(e) => panic!("{e:?} at k = {k}, {params:?}"),
            }
            if let (Some(m), Some(p)) = (fixed.as_ref(), fixed_predictor.as_ref()) {
                let k = Q16::from_bits(k.to_bits() as i32);
                if let Ok(ba) = p.predict(m, variant, k) {
                    assert!(k > Q16::ZERO);
                    assert!(ba.v_b >= Q16::ZERO && ba.t_ba >= Q16::ZERO, "{ba:?}");
                }
            }
        }
    }
});
