//! The f32 library against the independent f64 reference (`reference/`,
//! written from MODEL.md alone) on randomized parameter sets and
//! trajectories with many reversals, minor loops, rests and gross sliding.
//!
//! Bounds (MODEL.md contract, core issue): friction within 1e-5·Fs, F_ba
//! within 1e-4 relative. The worst cases seen are printed
//! (`cargo test --test against_reference -- --nocapture`).

use breakaway::{BreakAwayPredictor, Model, Params, Presliding, Variant};
use breakaway_reference as reference;
use proptest::prelude::*;

mod common;
use common::{
    boundary, check, params, reference_break_away, reference_model, samples, trajectory, worse,
    Segment, Worst,
};

static WORST_FRICTION: Worst = Worst::new();
static WORST_BREAKAWAY: Worst = Worst::new();

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
        worst = worse(worst, (f as f64 - f_ref).abs() / p.fs as f64);
    }
    worst
}

#[test]
fn friction_matches_reference_within_1e_5_fs() {
    check(
        400,
        &(params(0.3..3.0), trajectory(20.0)),
        |(p, segments)| {
            WORST_FRICTION.within(friction_error(&p, &segments), 1e-5, || format!("{p:?}"))
        },
    );
    WORST_FRICTION.print("friction: worst |F_f32 − F_f64|", "·Fs");
}

#[test]
fn break_away_matches_reference_within_1e_4() {
    let cases = (params(0.3..3.0), -3.0f32..3.0, boundary());
    check(400, &cases, |(p, log_k, w_b)| {
        let model = Model::<f32>::new(p).unwrap();
        let judge_model = reference_model(&p);
        let k = 10f32.powf(log_k) * p.fc;
        let predictor = BreakAwayPredictor::new(&model, w_b).unwrap();
        for variant in Variant::ALL {
            let want = reference_break_away(&judge_model, variant, k as f64, w_b as f64);
            let got = predictor.predict(&model, variant, k).unwrap();
            let rel = |a: f32, b: f64| ((a as f64 - b) / b).abs();
            let error = worse(
                worse(rel(got.f_ba, want.f_ba), rel(got.v_b, want.v_b)),
                rel(got.t_ba, want.t_ba),
            );
            WORST_BREAKAWAY.within(error, 1e-4, || format!("{variant:?} k={k} w_b={w_b} {p:?}"))?;
        }
        Ok(())
    });
    WORST_BREAKAWAY.print("break-away: worst relative error of v_b, F_ba, t_ba", "");
}

/// The per-model Stribeck table (`breakaway::curves`) over the whole
/// admitted range of δ: trajectories as above with δ log-uniform from 0.1
/// to 10, where the table splits each octave into 2ᵏ segments, k from 0
/// to 3, and, below δ = 0.82, the table does not reach down to S = Fs and
/// the kernels take over below it.
#[test]
fn friction_matches_reference_within_1e_5_fs_for_every_delta() {
    let cases = (
        params(0.3..3.0),
        -1.0f32..1.0, // log10 δ
        trajectory(20.0),
    );
    let worst = Worst::new();
    check(300, &cases, |(p, log_delta, segments)| {
        let p = Params {
            delta: 10f32.powf(log_delta),
            ..p
        };
        worst.within(friction_error(&p, &segments), 1e-5, || format!("{p:?}"))
    });
    worst.print("friction, δ in [0.1, 10]: worst |F_f32 − F_f64|", "·Fs");
}

/// S(v) of the table against the reference at velocities log-uniform over
/// 40 decades (both sides of the table, inside and outside it), δ
/// log-uniform from 0.05 to 20: within 2e-6·Fs.
#[test]
fn stribeck_matches_reference_over_every_velocity_and_delta() {
    let cases = (params(0.3..3.0), -1.3f32..1.3, -30.0f32..10.0);
    let worst = Worst::new();
    check(2000, &cases, |(p, log_delta, log_u)| {
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
            worst.within(error, 2e-6, || format!("v = {v:e}, {p:?}"))?;
        }
        Ok(())
    });
    worst.print(
        "Stribeck, δ in [0.05, 20], |v| from 1e-30·V to 1e10·V: worst |S_f32 − S_f64|",
        "·Fs",
    );
}

/// The consistent break-away velocity (the root of v·S(v) = c that
/// `Curves::consistent_root` finds: Newton's iteration on the table where
/// v·S is monotone, the fixed-point iteration where it is not) against the
/// reference's bracketed bisection, over Fs/Fc from 1 to 10 (steep curves
/// whose v·S has a local maximum included), δ log-uniform from 0.1 to 10
/// and c/V log-uniform over 14 decades (roots below the table, where δ <
/// 0.82 leaves S to the kernels, inside it and above it). Where the root
/// is well conditioned (d(v·S)/dv ≥ S/10 there) v_b is within 1e-5 of the
/// reference; everywhere v_b·S_ref(v_b) is within 1e-5 of c and v_b is not
/// a later root than the reference's (within 1 %).
#[test]
fn consistent_root_matches_reference_for_steep_curves_and_every_delta() {
    let cases = (
        params(0.3..3.0),
        0.0f32..1.0,   // log10 Fs/Fc
        -1.0f32..1.0,  // log10 δ
        -10.0f32..4.0, // log10 c/(V·Fc)
    );
    let worst = Worst::new();
    check(3000, &cases, |(p, log_ratio, log_delta, log_c)| {
        let p = Params {
            fs: p.fc * 10f32.powf(log_ratio),
            delta: 10f32.powf(log_delta),
            sigma: 0.0,
            ..p
        };
        let model = Model::<f32>::new(p).unwrap();
        let judge = reference_model(&p);
        let predictor = BreakAwayPredictor::new(&model, 0.95).unwrap();
        // k with c = k·z_max/|ln w_b| = 10^log_c·V·Fc.
        let c = 10f64.powf(f64::from(log_c)) * f64::from(p.v_stribeck) * f64::from(p.fc);
        let k = (c * 0.95f64.ln().abs() / f64::from(p.z_max)) as f32;
        let c = f64::from(k) * f64::from(p.z_max) / 0.95f64.ln().abs();
        let got = predictor.predict(&model, Variant::Consistent, k).unwrap();
        let want = reference::consistent_root(&judge, c);
        let v = f64::from(got.v_b);
        let s = |v: f64| reference::curves::stribeck(&judge, v);
        let residual = (v * s(v) / c - 1.0).abs();
        // d(v·S)/dv relative to S at the reference root.
        let h = 1e-6 * want;
        let slope = ((want + h) * s(want + h) - (want - h) * s(want - h)) / (2.0 * h) / s(want);
        let error = (v / want - 1.0).abs();
        if slope >= 0.1 {
            worst.within(error, 1e-5, || format!("c = {c:e}, {p:?}"))?;
        }
        prop_assert!(
            residual <= 1e-5,
            "residual {residual:e} at c = {c:e}, {p:?}"
        );
        prop_assert!(
            v <= 1.01 * want,
            "v_b = {v:e}, root {want:e} at c = {c:e}, {p:?}"
        );
        Ok(())
    });
    worst.print(
        "consistent root, Fs/Fc in [1, 10], δ in [0.1, 10]: worst relative error of v_b",
        "",
    );
}
