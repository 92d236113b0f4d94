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

mod common;
use common::{params, reference_model, runner, samples, trajectory, Segment};

static WORST_FRICTION: Mutex<(f64, String)> = Mutex::new((0.0, String::new()));
static WORST_BREAKAWAY: Mutex<(f64, String)> = Mutex::new((0.0, String::new()));

fn record(slot: &Mutex<(f64, String)>, error: f64, case: impl FnOnce() -> String) {
    let mut worst = slot.lock().unwrap();
    if error > worst.0 {
        *worst = (error, case());
    }
}

/// Drives the library (f32, counts of z_max/1000) and the reference along
/// the trajectory; returns the largest |ΔF|/Fs.
fn friction_error(p: &Params, segments: &[Segment]) -> f64 {
    let model = Model::<f32>::new(*p).unwrap();
    let judge_model = reference_model(p);
    let count = p.z_max / 1000.0;
    let mut lib = Presliding::<i64>::new(0, count).unwrap();
    let mut judge = reference::Presliding::new(0.0);
    let mut worst = 0.0f64;
    for (at, v) in samples(segments) {
        let v = v * p.v_stribeck;
        let f = lib.update(&model, at, v).unwrap();
        let f_ref = judge.update(&judge_model, at as f64 * count as f64, v as f64);
        worst = worst.max((f as f64 - f_ref).abs() / p.fs as f64);
    }
    worst
}

#[test]
fn friction_matches_reference_within_1e_5_fs() {
    let mut runner = runner(400);
    runner
        .run(&(params(0.3..3.0), trajectory(20.0)), |(p, segments)| {
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
        params(0.3..3.0),
        -3.0f32..3.0,
        prop_oneof![Just(0.95f32), 0.5f32..0.99],
    );
    runner
        .run(&cases, |(p, log_k, w_b)| {
            let model = Model::<f32>::new(p).unwrap();
            let judge_model = reference_model(&p);
            let k = 10f32.powf(log_k) * p.fc;
            let predictor = BreakAwayPredictor::new(&model, w_b).unwrap();
            for variant in Variant::ALL {
                let judge_variant = reference::Variant::parse(variant.name()).unwrap();
                let want = reference::predict_break_away(
                    &judge_model,
                    judge_variant,
                    k as f64,
                    w_b as f64,
                )
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
