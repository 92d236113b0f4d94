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

/// The per-model Stribeck table (`breakaway::curves`) over the whole
/// admitted range of δ: trajectories as above with δ log-uniform from 0.1
/// to 10, where the table splits each octave into 2ᵏ segments, k from 0
/// to 3, and, below δ = 0.82, the table does not reach down to S = Fs and
/// the kernels take over below it.
#[test]
fn friction_matches_reference_within_1e_5_fs_for_every_delta() {
    let mut runner = runner(300);
    let cases = (
        params(0.3..3.0),
        -1.0f32..1.0, // log10 δ
        trajectory(20.0),
    );
    let worst = Mutex::new((0.0f64, String::new()));
    runner
        .run(&cases, |(p, log_delta, segments)| {
            let p = Params {
                delta: 10f32.powf(log_delta),
                ..p
            };
            let error = friction_error(&p, &segments);
            record(&worst, error, || format!("{p:?}"));
            prop_assert!(error <= 1e-5, "|ΔF| = {error:e}·Fs for {p:?}");
            Ok(())
        })
        .unwrap();
    let worst = worst.lock().unwrap();
    println!(
        "friction, δ in [0.1, 10]: worst |F_f32 − F_f64| = {:.3e}·Fs ({})",
        worst.0, worst.1
    );
}

/// S(v) of the table against the reference at velocities log-uniform over
/// 40 decades (both sides of the table, inside and outside it), δ
/// log-uniform from 0.05 to 20: within 2e-6·Fs.
#[test]
fn stribeck_matches_reference_over_every_velocity_and_delta() {
    let mut runner = runner(2000);
    let cases = (params(0.3..3.0), -1.3f32..1.3, -30.0f32..10.0);
    let worst = Mutex::new((0.0f64, String::new()));
    runner
        .run(&cases, |(p, log_delta, log_u)| {
            let p = Params {
                delta: 10f32.powf(log_delta),
                ..p
            };
            let model = Model::<f32>::new(p).unwrap();
            let judge = reference_model(&p);
            for sign in [1.0f32, -1.0] {
                let v = sign * 10f32.powf(log_u) * p.v_stribeck;
                let error = (f64::from(model.stribeck(v))
                    - reference::curves::stribeck(&judge, f64::from(v)))
                .abs()
                    / f64::from(p.fs);
                record(&worst, error, || format!("v = {v:e}, {p:?}"));
                prop_assert!(error <= 2e-6, "|ΔS| = {error:e}·Fs at v = {v:e}, {p:?}");
            }
            Ok(())
        })
        .unwrap();
    let worst = worst.lock().unwrap();
    println!(
        "Stribeck, δ in [0.05, 20], |v| from 1e-30·V to 1e10·V: worst |S_f32 − S_f64| = {:.3e}·Fs ({})",
        worst.0, worst.1
    );
}
