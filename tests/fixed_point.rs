//! The Q16.16 fixed-point model against the independent f64 reference, over
//! randomized parameter sets and trajectories across the documented range
//! (`breakaway::fixed_point`), and its saturation at the extremes.
//!
//! Bounds (fixed-point issue): friction within 1e-3·Fs (max abs), F_ba
//! within 1e-3 relative. The fixed-point model is judged at the inputs it
//! receives: the reference gets the same quantized velocity and force rate.
//! Worst cases are printed (`-- --nocapture`).

use std::sync::Mutex;

use breakaway::{
    BreakAwayPredictor, Model, Param, ParamError, Params, Presliding, Scalar, Variant, Q16,
};
use breakaway_reference as reference;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

type Fx = Q16<16>;

fn params() -> impl Strategy<Value = Params> {
    (
        -1.0f32..2.0,                                                 // log10 Fc [N]
        0.0f32..2.0,                                                  // Fs/Fc − 1
        -4.0f32..-1.0,                                                // log10 V [m/s]
        prop_oneof![Just(0.5f32), Just(1.0), Just(2.0), 0.5f32..2.0], // δ
        prop_oneof![Just(0.0f32), 0.0f32..1.0],                       // σ·V/Fc
        -6.0f32..-3.0,                                                // log10 z_max [m]
        prop_oneof![Just(0u32), 0u32..40],                            // ε in counts (+½)
    )
        .prop_map(|(fc, rise, v, delta, sigma, z_max, eps)| {
            let fc = 10f32.powf(fc);
            let v_stribeck = 10f32.powf(v);
            let z_max = 10f32.powf(z_max);
            let count = z_max / 1000.0;
            Params {
                fc,
                fs: fc * (1.0 + rise),
                v_stribeck,
                delta,
                sigma: sigma * fc / v_stribeck,
                z_max,
                epsilon: if eps == 0 {
                    0.0
                } else {
                    (eps as f32 + 0.5) * count
                },
            }
        })
}

fn reference_model(p: &Params) -> reference::Model {
    reference::Model {
        mass: 1.0,
        fc: p.fc as f64,
        fs: p.fs as f64,
        v_stribeck: p.v_stribeck as f64,
        delta: p.delta as f64,
        sigma: p.sigma as f64,
        z_max: p.z_max as f64,
        epsilon: p.epsilon as f64,
        effects: reference::Effects::default(),
    }
}

/// Travel in counts (z_max = 1000 counts), counts per sample, velocity in V.
type Segment = (i32, i32, f32);

fn trajectory() -> impl Strategy<Value = Vec<Segment>> {
    let segment = (
        prop_oneof![1i32..300, 300i32..1500, 1500i32..6000],
        any::<bool>(),
        prop_oneof![Just(1i32), 1i32..8, 8i32..80],
        prop_oneof![Just(0.0f32), 0.0f32..0.3, 0.3f32..5.0, 5.0f32..64.0],
    )
        .prop_map(|(len, up, step, v)| (if up { len } else { -len }, step, v));
    prop::collection::vec(segment, 4..40)
}

/// A runner with a fixed seed: the same cases on every run and machine.
fn runner(cases: u32) -> TestRunner {
    TestRunner::new_with_rng(
        Config {
            cases,
            ..Config::default()
        },
        TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    )
}

static WORST: Mutex<[(f64, String); 2]> = Mutex::new([(0.0, String::new()), (0.0, String::new())]);

fn record(slot: usize, error: f64, case: impl FnOnce() -> String) {
    let mut worst = WORST.lock().unwrap();
    if error > worst[slot].0 {
        worst[slot] = (error, case());
    }
}

fn friction_error(p: &Params, segments: &[Segment]) -> f64 {
    let model = Model::<Fx>::new(*p).expect("parameters within the documented range");
    let judge_model = reference_model(p);
    let count = p.z_max / 1000.0;
    let scale = model.position_scale(count).expect("scale in range");
    let mut lib = Presliding::<i32, Fx>::new(0, scale).unwrap();
    let mut judge = reference::Presliding::new(0.0);
    let mut x = 0i32;
    let mut worst = 0.0f64;
    for &(travel, step, v) in segments {
        let target = x + travel;
        let dir = travel.signum();
        let v_q = model
            .velocity(dir as f32 * v * p.v_stribeck)
            .expect("velocity in range");
        // The reference sees the velocity the fixed-point model received.
        let v_si = v_q.to_f32() as f64 * p.v_stribeck as f64;
        let samples = std::iter::once(x).chain(std::iter::successors(Some(x), |&at| {
            (at != target).then(|| {
                if dir > 0 {
                    (at + step).min(target)
                } else {
                    (at - step).max(target)
                }
            })
        }));
        for at in samples {
            let f = lib.update(&model, at, v_q).unwrap().to_f32() as f64 * p.fs as f64;
            let f_ref = judge.update(&judge_model, at as f64 * count as f64, v_si);
            worst = worst.max((f - f_ref).abs() / p.fs as f64);
        }
        x = target;
    }
    worst
}

#[test]
fn fixed_friction_matches_reference_within_1e_3_fs() {
    let mut runner = runner(300);
    runner
        .run(&(params(), trajectory()), |(p, segments)| {
            let error = friction_error(&p, &segments);
            record(0, error, || format!("{p:?}"));
            prop_assert!(error <= 1e-3, "|ΔF| = {error:e}·Fs for {p:?}");
            Ok(())
        })
        .unwrap();
    let worst = WORST.lock().unwrap();
    println!(
        "fixed point: worst |F_q16 − F_f64| = {:.3e}·Fs ({})",
        worst[0].0, worst[0].1
    );
}

#[test]
fn fixed_break_away_matches_reference_within_1e_3() {
    let mut runner = runner(300);
    // k from 0.01 to 30 Fs/s (raised where v_b would fall below 1e-3·V).
    let cases = (
        params(),
        -2.0f32..1.5,
        prop_oneof![Just(0.95f32), 0.5f32..0.99],
    );
    runner
        .run(&cases, |(p, log_k, w_b)| {
            let model = Model::<Fx>::new(p).unwrap();
            let judge_model = reference_model(&p);
            let predictor = BreakAwayPredictor::new(&model, w_b).unwrap();
            // Documented range: v_b ≥ 1e-3·V, where the Q16.16 velocity
            // resolution (1.5e-5·V) moves S(v_b) by less than 3e-4·(Fs − Fc)
            // even for δ = 0.5 (infinite slope of S at v = 0).
            let travel_per_rate = p.z_max / ((w_b as f64).ln().abs() as f32 * p.v_stribeck);
            let k_min = 1e-3 / travel_per_rate;
            let k_q = Fx::from_f32(10f32.powf(log_k).max(k_min)).unwrap();
            let k = k_q.to_f32() as f64 * p.fs as f64;
            for variant in Variant::ALL {
                let judge_variant = reference::Variant::parse(variant.name()).unwrap();
                let want =
                    reference::predict_break_away(&judge_model, judge_variant, k, w_b as f64)
                        .unwrap();
                let got = predictor.predict(&model, variant, k_q).unwrap();
                let f_ba = got.f_ba.to_f32() as f64 * p.fs as f64;
                let error = ((f_ba - want.f_ba) / want.f_ba).abs();
                record(1, error, || format!("{variant:?} k={k} w_b={w_b} {p:?}"));
                prop_assert!(
                    error <= 1e-3,
                    "{variant:?}: F_ba rel. error {error:e} at k = {k}, {p:?}"
                );
            }
            Ok(())
        })
        .unwrap();
    let worst = WORST.lock().unwrap();
    println!(
        "fixed point: worst F_ba relative error = {:.3e} ({})",
        worst[1].0, worst[1].1
    );
}

fn paper() -> Params {
    Params {
        fc: 1.0,
        fs: 1.5,
        v_stribeck: 1e-3,
        delta: 1.0,
        sigma: 0.0,
        z_max: 1e-5,
        epsilon: 0.0,
    }
}

#[test]
fn construction_rejects_what_does_not_fit_naming_the_parameter() {
    // σ·V/Fs = 1e6 does not fit Q16.16.
    let p = Params {
        sigma: 1.5e9,
        ..paper()
    };
    assert_eq!(
        Model::<Fx>::new(p).unwrap_err(),
        ParamError::OutOfRange(Param::Sigma)
    );
    // ε = 200·z_max: ε/z_max·256 = 51200 does not fit.
    let p = Params {
        epsilon: 2e-3,
        ..paper()
    };
    assert_eq!(
        Model::<Fx>::new(p).unwrap_err(),
        ParamError::OutOfRange(Param::Epsilon)
    );
    // Fc/Fs = 1e-6 rounds to 0.
    let p = Params {
        fc: 1e-6,
        ..paper()
    };
    assert_eq!(
        Model::<Fx>::new(p).unwrap_err(),
        ParamError::OutOfRange(Param::Fc)
    );
    // Encoder counts coarser than 128·z_max or finer than z_max/2²⁴.
    let m = Model::<Fx>::new(paper()).unwrap();
    assert!(m.position_scale(1.0).is_none());
    assert!(m.position_scale(1e-13).is_none());
    assert!(m.position_scale(1e-8).is_some());
}

#[test]
fn extreme_samples_saturate_and_never_panic() {
    // σ·V/Fs = 2: the viscous term saturates above 16384·V.
    let p = Params {
        sigma: 3000.0,
        ..paper()
    };
    let model = Model::<Fx>::new(p).unwrap();
    let scale = model.position_scale(1e-8).unwrap();
    let mut axis = Presliding::<i32, Fx>::new(0, scale).unwrap();
    let extremes = [i32::MIN, i32::MAX, 0, -1, 1, i32::MAX, i32::MIN + 1];
    let speeds = [
        Fx::from_bits(i32::MIN),
        Fx::from_bits(i32::MAX),
        Fx::ZERO,
        Fx::from_bits(1),
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
    let mut axis = Presliding::<i32, Fx>::new(0, scale).unwrap();
    let f = axis.update(&model, 2000, Fx::from_bits(i32::MAX)).unwrap();
    assert_eq!(f, Fx::from_bits(i32::MAX));
    assert!((axis.dry().to_f32() - 1.0 / 1.5).abs() < 1e-4);
    // Predictor extremes: huge and tiny k give finite, saturated results.
    let predictor = BreakAwayPredictor::new(&model, 0.95).unwrap();
    for k in [Fx::from_bits(1), Fx::from_bits(i32::MAX)] {
        for variant in Variant::ALL {
            let ba = predictor.predict(&model, variant, k).unwrap();
            assert!(ba.f_ba.to_f32() >= 1.0 / 1.5 - 1e-3);
        }
    }
    assert!(predictor.predict(&model, Variant::Mean, Fx::ZERO).is_err());
    assert!(predictor.predict(&model, Variant::Mean, -Fx::ONE).is_err());
}
