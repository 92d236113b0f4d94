//! The Q16.16 fixed-point model against the independent f64 reference, over
//! randomized parameter sets and trajectories across the documented range
//! (`breakaway::fixed_point`), and its saturation at the extremes.
//!
//! Bounds (fixed-point issue): friction within 1e-3·Fs (max abs), F_ba
//! within 1e-3 relative. The fixed-point model is judged at the inputs it
//! receives: the reference gets the same quantized velocity and force rate.
//! Worst cases are printed (`-- --nocapture`).

use breakaway::{
    BreakAwayPredictor, Model, Param, ParamError, Params, Presliding, Scalar, Variant, Q16,
};
use breakaway_reference as reference;
use proptest::prelude::*;

mod common;
use common::{
    boundary, check, params, reference_break_away, reference_model, samples, trajectory, worse,
    Segment, Worst, FIG5,
};

/// Worst |F − F_ref|/Fs over the samples of `segments` (in steps of
/// z_max/1000) read by an encoder of `per_z_max` counts per z_max.
fn friction_error(p: &Params, segments: &[Segment], per_z_max: f64) -> f64 {
    let model = Model::<Q16>::new(*p).expect("parameters within the documented range");
    let judge_model = reference_model(p);
    let count = (p.z_max as f64 / per_z_max) as f32;
    let scale = model.position_scale::<i64>(count).expect("scale in range");
    let mut lib = Presliding::<i64, Q16>::new(0, scale).unwrap();
    let mut judge = reference::Presliding::new(0.0);
    let mut worst = 0.0f64;
    for (at, v) in samples(segments) {
        let at = (at as f64 * per_z_max / 1000.0).round() as i64;
        let v_q = model.velocity(v * p.v_stribeck).expect("velocity in range");
        // The reference sees the velocity the fixed-point model received.
        let v_si = v_q.to_f32() as f64 * p.v_stribeck as f64;
        let f = lib.update(&model, at, v_q).unwrap().to_f32() as f64 * p.fs as f64;
        let f_ref = judge.update(&judge_model, at as f64 * count as f64, v_si);
        worst = worse(worst, (f - f_ref).abs() / p.fs as f64);
    }
    worst
}

/// From 10 to 10⁷ counts per z_max (a 20-bit encoder on a 5 mm screw is
/// 2 000 counts per z_max = 10 µm): the travel never saturates before it is
/// scaled, and the scale keeps its precision.
#[test]
fn fixed_friction_within_1e_3_fs_at_every_encoder_resolution() {
    for decade in 1..=7 {
        let per_z_max = 10f64.powi(decade);
        let worst = std::cell::Cell::new(0.0f64);
        check(
            40,
            &(params(0.5..2.0), trajectory(64.0)),
            |(p, segments)| {
                let error = friction_error(&p, &segments, per_z_max);
                worst.set(worse(worst.get(), error));
                prop_assert!(
                    error <= 1e-3,
                    "|ΔF| = {error:e}·Fs at {per_z_max:e} counts per z_max for {p:?}"
                );
                Ok(())
            },
        );
        println!(
            "{per_z_max:.0e} counts per z_max: worst |ΔF| = {:.3e}·Fs",
            worst.get()
        );
    }
}

#[test]
fn fixed_friction_matches_reference_within_1e_3_fs() {
    let worst = Worst::new();
    check(
        300,
        &(params(0.5..2.0), trajectory(64.0)),
        |(p, segments)| {
            worst.within(friction_error(&p, &segments, 1000.0), 1e-3, || {
                format!("{p:?}")
            })
        },
    );
    worst.print("fixed point: worst |F_q16 − F_f64|", "·Fs");
}

#[test]
fn fixed_break_away_matches_reference_within_1e_3() {
    let worst = Worst::new();
    // k from 0.01 to 30 Fs/s (raised where v_b would fall below 1e-3·V).
    let cases = (params(0.5..2.0), -2.0f32..1.5, boundary());
    check(300, &cases, |(p, log_k, w_b)| {
        let model = Model::<Q16>::new(p).unwrap();
        let judge_model = reference_model(&p);
        let predictor = BreakAwayPredictor::new(&model, w_b).unwrap();
        // Documented range: v_b ≥ 1e-3·V, where the Q16.16 velocity
        // resolution (1.5e-5·V) moves S(v_b) by less than 3e-4·(Fs − Fc)
        // even for δ = 0.5 (infinite slope of S at v = 0).
        let travel_per_rate = p.z_max / ((w_b as f64).ln().abs() as f32 * p.v_stribeck);
        let k_min = 1e-3 / travel_per_rate;
        let k_q = Q16::from_f32(10f32.powf(log_k).max(k_min)).unwrap();
        let k = k_q.to_f32() as f64 * p.fs as f64;
        for variant in Variant::ALL {
            let want = reference_break_away(&judge_model, variant, k, w_b as f64);
            let got = predictor.predict(&model, variant, k_q).unwrap();
            let f_ba = got.f_ba.to_f32() as f64 * p.fs as f64;
            let error = ((f_ba - want.f_ba) / want.f_ba).abs();
            worst.within(error, 1e-3, || format!("{variant:?} k={k} w_b={w_b} {p:?}"))?;
        }
        Ok(())
    });
    worst.print("fixed point: worst F_ba relative error", "");
}

#[test]
fn construction_rejects_what_does_not_fit_naming_the_parameter() {
    // σ·V/Fs = 1e6 does not fit Q16.16.
    let p = Params {
        sigma: 1.5e9,
        ..FIG5
    };
    assert_eq!(
        Model::<Q16>::new(p).unwrap_err(),
        ParamError::OutOfRange(Param::Sigma)
    );
    // ε = 200·z_max: ε/z_max·256 = 51200 does not fit.
    let p = Params {
        epsilon: 2e-3,
        ..FIG5
    };
    assert_eq!(
        Model::<Q16>::new(p).unwrap_err(),
        ParamError::OutOfRange(Param::Epsilon)
    );
    // Fc/Fs = 1e-6 rounds to 0.
    let p = Params { fc: 1e-6, ..FIG5 };
    assert_eq!(
        Model::<Q16>::new(p).unwrap_err(),
        ParamError::OutOfRange(Param::Fc)
    );
    // Encoder counts coarser than 128·z_max or finer than z_max/2³⁴.
    let m = Model::<Q16>::new(FIG5).unwrap();
    assert!(m.position_scale::<i32>(1.0).is_none());
    assert!(m.position_scale::<i32>(1e-16).is_none());
    assert!(m.position_scale::<i32>(1e-8).is_some());
}

/// In-place construction builds the same model as `new`, from the `const`
/// starting point, and leaves the model unchanged when it rejects a set.
#[test]
fn set_params_in_place_equals_new_and_rejects_without_change() {
    // Fc = Fs = V = z_max = 1 (δ = 1, σ = ε = 0): the unit Coulomb model.
    let unit = Params {
        fs: 1.0,
        v_stribeck: 1.0,
        z_max: 1.0,
        ..FIG5
    };
    assert_eq!(
        format!("{:?}", Model::<Q16>::UNIT_COULOMB),
        format!("{:?}", Model::<Q16>::new(unit).unwrap())
    );
    check(50, &params(0.5..2.0), |p| {
        let mut model = Model::<Q16>::UNIT_COULOMB;
        model.set_params(p).unwrap();
        prop_assert_eq!(
            format!("{model:?}"),
            format!("{:?}", Model::<Q16>::new(p).unwrap())
        );
        let before = format!("{model:?}");
        let bad = Params {
            fs: p.fc * 0.5,
            ..p
        };
        prop_assert_eq!(model.set_params(bad), Err(ParamError::StictionBelowCoulomb));
        prop_assert_eq!(format!("{model:?}"), before);
        Ok(())
    });
}

#[test]
fn extreme_samples_saturate_and_never_panic() {
    // σ·V/Fs = 2: the viscous term saturates above 16384·V.
    let model = Model::<Q16>::new(Params {
        sigma: 3000.0,
        ..FIG5
    })
    .unwrap();
    let scale = model.position_scale::<i32>(1e-8).unwrap();
    let mut axis = Presliding::<i32, Q16>::new(0, scale).unwrap();
    let extremes = [i32::MIN, i32::MAX, 0, -1, 1, i32::MAX, i32::MIN + 1];
    let speeds = [
        Q16::from_bits(i32::MIN),
        Q16::from_bits(i32::MAX),
        Q16::ZERO,
        Q16::from_bits(1),
    ];
    for &x in &extremes {
        for &v in &speeds {
            let f = axis.update(&model, x, v).unwrap();
            // |H| ≤ Fs; the output saturates at the Q16.16 range.
            assert!(
                axis.dry().to_f32().abs() <= 1.0 + 1e-4,
                "H = {:?}",
                axis.dry()
            );
            assert!(f.to_f32().is_finite());
        }
    }
    // Saturated velocity: S = Fc/Fs, viscous σ·v saturates at +32768·Fs.
    let mut axis = Presliding::<i32, Q16>::new(0, scale).unwrap();
    let f = axis.update(&model, 2000, Q16::from_bits(i32::MAX)).unwrap();
    assert_eq!(f, Q16::from_bits(i32::MAX));
    assert!((axis.dry().to_f32() - 1.0 / 1.5).abs() < 1e-4);
    // Predictor extremes: huge and tiny k give finite, saturated results.
    let predictor = BreakAwayPredictor::new(&model, 0.95).unwrap();
    for k in [Q16::from_bits(1), Q16::from_bits(i32::MAX)] {
        for variant in Variant::ALL {
            let ba = predictor.predict(&model, variant, k).unwrap();
            assert!(ba.f_ba.to_f32() >= 1.0 / 1.5 - 1e-3);
        }
    }
    assert!(predictor.predict(&model, Variant::Mean, Q16::ZERO).is_err());
    assert!(predictor.predict(&model, Variant::Mean, -Q16::ONE).is_err());
}
