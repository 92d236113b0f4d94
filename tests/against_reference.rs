//! The f32 library against the independent f64 reference (`reference/`,
//! written from MODEL.md alone) on randomized parameter sets and
//! trajectories with many reversals, minor loops, rests and gross sliding.
//!
//! Bounds (MODEL.md contract, core issue): friction within 1e-5·Fs, F_ba
//! within 1e-4 relative. The worst cases seen are printed
//! (`cargo test --test against_reference -- --nocapture`).

use std::sync::Mutex;

use breakaway::{BreakAwayPredictor, Model, Params, Presliding, Variant};
use breakaway_reference as reference;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

/// A parameter set, drawn over the ranges a motion axis meets.
fn params() -> impl Strategy<Value = Params> {
    (
        -1.0f32..2.0,                                                 // log10 Fc [N]
        0.0f32..2.0,                                                  // Fs/Fc − 1
        -4.0f32..-1.0,                                                // log10 V [m/s]
        prop_oneof![Just(0.5f32), Just(1.0), Just(2.0), 0.3f32..3.0], // δ
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

/// One segment of motion: travel in counts (signed), counts per sample,
/// velocity estimate in units of V.
type Segment = (i64, i64, f32);

fn trajectory() -> impl Strategy<Value = Vec<Segment>> {
    let segment = (
        prop_oneof![1i64..300, 300i64..1500, 1500i64..6000], // within, near, beyond z_max (1000 counts)
        any::<bool>(),
        prop_oneof![Just(1i64), 1i64..8, 8i64..80],
        prop_oneof![Just(0.0f32), 0.0f32..0.3, 0.3f32..5.0],
    )
        .prop_map(|(len, up, step, v)| (if up { len } else { -len }, step, v));
    prop::collection::vec(segment, 4..40)
}

/// Largest friction error seen, in units of Fs, with its case.
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

static WORST_FRICTION: Mutex<(f64, String)> = Mutex::new((0.0, String::new()));
static WORST_BREAKAWAY: Mutex<(f64, String)> = Mutex::new((0.0, String::new()));

fn record(slot: &Mutex<(f64, String)>, error: f64, case: impl FnOnce() -> String) {
    let mut worst = slot.lock().unwrap();
    if error > worst.0 {
        *worst = (error, case());
    }
}

/// Drives both models along the trajectory with memory capacity `N` in the
/// library (0: the reference rule); returns the largest |ΔF|/Fs.
fn friction_error(p: &Params, segments: &[Segment]) -> f64 {
    let model = Model::<f32>::new(*p).unwrap();
    let reference = reference_model(p);
    let count = p.z_max / 1000.0;
    let mut lib = Presliding::<i64>::new(0, count).unwrap();
    let mut judge = reference::Presliding::new(0.0);
    let mut x = 0i64;
    let mut worst = 0.0f64;
    for &(travel, step, v) in segments {
        let target = x + travel;
        let dir = travel.signum();
        let v = dir as f32 * v * p.v_stribeck;
        // A rest before each segment: the same position sampled twice.
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
            let f = lib.update(&model, at, v).unwrap();
            let f_ref = judge.update(&reference, at as f64 * count as f64, v as f64);
            worst = worst.max((f as f64 - f_ref).abs() / p.fs as f64);
        }
        x = target;
    }
    worst
}

#[test]
fn friction_matches_reference_within_1e_5_fs() {
    let mut runner = runner(400);
    runner
        .run(&(params(), trajectory()), |(p, segments)| {
            let error = friction_error(&p, &segments);
            record(&WORST_FRICTION, error, || format!("{p:?}"));
            prop_assert!(error <= 1e-5, "|ΔF| = {error:e}·Fs for {p:?}");
            Ok(())
        })
        .unwrap();
    let worst = WORST_FRICTION.lock().unwrap();
    println!(
        "friction: worst |F_f32 − F_f64| = {:.3e}·Fs ({})",
        worst.0, worst.1
    );
}

#[test]
fn break_away_matches_reference_within_1e_4() {
    let mut runner = runner(400);
    let cases = (
        params(),
        -3.0f32..3.0,
        prop_oneof![Just(0.95f32), 0.5f32..0.99],
    );
    runner
        .run(&cases, |(p, log_k, w_b)| {
            let model = Model::<f32>::new(p).unwrap();
            let reference = reference_model(&p);
            let k = 10f32.powf(log_k) * p.fc;
            let predictor = BreakAwayPredictor::new(&model, w_b).unwrap();
            for variant in Variant::ALL {
                let judge_variant = reference::Variant::parse(variant.name()).unwrap();
                let want =
                    reference::predict_break_away(&reference, judge_variant, k as f64, w_b as f64)
                        .unwrap();
                let got = predictor.predict(&model, variant, k).unwrap();
                let rel = |a: f32, b: f64| ((a as f64 - b) / b).abs();
                let error = rel(got.f_ba, want.f_ba)
                    .max(rel(got.v_b, want.v_b))
                    .max(rel(got.t_ba, want.t_ba));
                record(&WORST_BREAKAWAY, error, || {
                    format!("{variant:?} k={k} w_b={w_b} {p:?}")
                });
                prop_assert!(
                    error <= 1e-4,
                    "{variant:?}: rel. error {error:e} at k = {k}, {p:?}"
                );
            }
            Ok(())
        })
        .unwrap();
    let worst = WORST_BREAKAWAY.lock().unwrap();
    println!(
        "break-away: worst relative error of v_b, F_ba, t_ba = {:.3e} ({})",
        worst.0, worst.1
    );
}
