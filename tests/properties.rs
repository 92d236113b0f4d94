//! Properties of the f32 library that the model (`breakaway::model_overview`)
//! states directly: parameter rules, the shape g, the state machine's idle
//! start, deadband and turning points, minor-loop closing and its overflow,
//! rejected samples, and the shape of F_ba(k).

use breakaway::{
    shape_f32, BreakAwayPredictor, Model, Param, ParamError, Params, PredictError, Presliding,
    SampleError, Variant,
};

mod support;
use support::{worse, FIG5};

fn model(p: Params) -> Model<f32> {
    Model::new(p).expect("valid parameters")
}

type Breaker = fn(&mut Params);

#[test]
fn every_invalid_parameter_has_its_own_error() {
    let cases: [(Breaker, ParamError); 15] = [
        (|p| p.fc = 0.0, ParamError::CoulombNotPositive),
        (|p| p.fc = -1.0, ParamError::CoulombNotPositive),
        (|p| p.fs = 0.99, ParamError::StictionBelowCoulomb),
        (
            |p| p.v_stribeck = 0.0,
            ParamError::StribeckVelocityNotPositive,
        ),
        (|p| p.delta = -2.0, ParamError::ShapeExponentNotPositive),
        (|p| p.sigma = -1e-9, ParamError::ViscousNegative),
        (|p| p.z_max = 0.0, ParamError::PreslidingDistanceNotPositive),
        (|p| p.epsilon = -1e-9, ParamError::DeadbandNegative),
        (|p| p.fc = f32::NAN, ParamError::NotFinite(Param::Fc)),
        (|p| p.fs = f32::INFINITY, ParamError::NotFinite(Param::Fs)),
        (
            |p| p.v_stribeck = f32::NAN,
            ParamError::NotFinite(Param::VStribeck),
        ),
        (
            |p| p.delta = f32::NEG_INFINITY,
            ParamError::NotFinite(Param::Delta),
        ),
        (|p| p.sigma = f32::NAN, ParamError::NotFinite(Param::Sigma)),
        (
            |p| p.z_max = f32::INFINITY,
            ParamError::NotFinite(Param::ZMax),
        ),
        (
            |p| p.epsilon = f32::NAN,
            ParamError::NotFinite(Param::Epsilon),
        ),
    ];
    for (break_it, expected) in cases {
        let mut p = FIG5;
        break_it(&mut p);
        let err = Model::<f32>::new(p).expect_err("must be rejected");
        assert_eq!(err, expected);
        // The message names the model-file key of the parameter at fault.
        let text = err.to_string();
        assert!(text.contains(err.param().key()), "{text}");
    }
    // Valid by the model, not representable: 1/V and 1/z_max overflow f32.
    let mut p = FIG5;
    p.v_stribeck = 1e-40;
    assert_eq!(
        Model::<f32>::new(p).unwrap_err(),
        ParamError::OutOfRange(Param::VStribeck)
    );
    let mut p = FIG5;
    p.z_max = 1e-40;
    assert_eq!(
        Model::<f32>::new(p).unwrap_err(),
        ParamError::OutOfRange(Param::ZMax)
    );
    // Boundary values that the contract allows.
    let mut p = FIG5;
    p.fs = p.fc;
    p.sigma = 0.0;
    p.epsilon = 0.0;
    assert!(Model::<f32>::new(p).is_ok());
}

#[test]
fn shape_ends_and_monotone() {
    assert_eq!(shape_f32(0.0), 0.0);
    assert_eq!(shape_f32(1.0), 1.0);
    assert_eq!(shape_f32(-3.0), 0.0);
    assert_eq!(shape_f32(7.0), 1.0);
    // g(0.15) = 0.43 as quoted in the model overview (turning points); g(0.5) = 0.5·(1 + ln 2).
    assert!((shape_f32(0.15) - 0.434_568).abs() < 1e-6);
    assert!((shape_f32(0.5) - 0.846_573_6).abs() < 1e-6);
    let mut last = 0.0;
    for i in 1..=100_000 {
        let g = shape_f32(i as f32 / 100_000.0);
        assert!(g >= last && g <= 1.0, "g not monotone at {i}");
        last = g;
    }
    // Every f32 in [0.5, 1] and a dense sweep below: within 2 ulp of g
    // (1.3e-7 measured); monotone to the last bit above 0.9, where g flattens.
    let mut worst = 0.0f64;
    let mut w = 1e-30f32;
    while w < 0.5 {
        let exact = w as f64 * (1.0 - (w as f64).ln());
        worst = worse(worst, (shape_f32(w) as f64 - exact).abs());
        w *= 1.000_37;
    }
    let (mut w, mut last) = (0.5f32, shape_f32(0.5));
    while w < 1.0 {
        w = f32::from_bits(w.to_bits() + 1);
        let g = shape_f32(w);
        assert!(g >= last || w <= 0.9, "g not monotone at w = {w}");
        let exact = w as f64 * (1.0 - (w as f64).ln());
        worst = worse(worst, (g as f64 - exact).abs());
        last = g;
    }
    println!("shape: worst |g_f32 − g| = {worst:.3e}");
    assert!(worst < 1.5e-7, "{worst}");
}

#[test]
fn stribeck_ends() {
    let m = model(FIG5);
    assert_eq!(m.stribeck(0.0), 1.5);
    assert!((m.stribeck(1e-3) - (1.0 + 0.5 * (-1.0f32).exp())).abs() < 1e-6);
    assert_eq!(m.stribeck(-1.0), 1.0);
    assert_eq!(m.stribeck(f32::MAX), 1.0);
    assert_eq!(m.steady_state(0.0), 0.0);
    assert_eq!(m.steady_state(-1.0), -1.0);
    for delta in [0.5, 1.0, 2.0, 1.3] {
        let m = model(Params { delta, ..FIG5 });
        let s = m.stribeck(2e-3);
        let expected = 1.0 + 0.5 * (-(2.0f64).powf(delta as f64)).exp();
        assert!(
            (s as f64 - expected).abs() < 1e-6,
            "delta {delta}: {s} vs {expected}"
        );
    }
}

#[test]
fn idle_first_motion_and_reversal() {
    let m = model(FIG5);
    let mut axis = Presliding::at(0.0);
    assert_eq!(axis.update(&m, 0.0, 0.0), Ok(0.0));
    assert_eq!(axis.direction(), 0);
    // First motion: H = S(v)·g(w), w = 4 µm / 10 µm; the deadband does not apply.
    let f = axis.update(&m, 4e-6, 0.0).unwrap();
    assert_eq!(axis.direction(), 1);
    let expected = 1.5 * (0.4 * (1.0 - 0.4f64.ln()));
    assert!((f as f64 - expected).abs() < 1e-6, "{f} vs {expected}");
    // Reversal at 4 µm back to 1 µm: H = H_r + (−S − H_r)·g(0.3).
    let f = axis.update(&m, 1e-6, 0.0).unwrap();
    assert_eq!(axis.direction(), -1);
    let g = 0.3 * (1.0 - 0.3f64.ln());
    let back = expected + (-1.5 - expected) * g;
    assert!((f as f64 - back).abs() < 1e-6, "{f} vs {back}");
    assert_eq!(axis.turning_point().position, 4e-6);
    // Beyond z_max from the turning point: gross sliding at −S(v).
    let f = axis.update(&m, -7e-6, -1e-3).unwrap();
    assert!((f - -(1.0 + 0.5 * (-1.0f32).exp())).abs() < 1e-6);
    assert!(axis.is_sliding());
}

#[test]
fn deadband_holds_then_confirms() {
    let m = model(Params {
        epsilon: 1e-6,
        ..FIG5
    });
    let mut axis = Presliding::<i64>::new(0, 1e-8).unwrap(); // 10 nm counts
    let held = axis.update(&m, 500, 0.0).unwrap(); // 5 µm
                                                   // 0.9 µm back: pending, H held at its value at the extremum.
    assert_eq!(axis.update(&m, 410, 0.0), Ok(held));
    assert_eq!(axis.direction(), 1);
    // Forward again past the extremum: the same branch continues.
    let on = axis.update(&m, 520, 0.0).unwrap();
    let g = |w: f64| w * (1.0 - w.ln());
    assert!((on as f64 - 1.5 * g(0.52)).abs() < 1e-6);
    // 1.1 µm back from 5.2 µm: confirmed, already w = 0.11 on the new branch.
    let f = axis.update(&m, 410, 0.0).unwrap();
    assert_eq!(axis.direction(), -1);
    let expected = on as f64 + (-1.5 - on as f64) * g(0.11);
    assert!((f as f64 - expected).abs() < 1e-6, "{f} vs {expected}");
}

#[test]
fn rejected_samples_leave_the_state_unchanged() {
    let m = model(Params { sigma: 2.0, ..FIG5 });
    let mut axis = Presliding::at(0.0);
    axis.update(&m, 3e-6, 1e-4).unwrap();
    let before = axis.clone();
    assert_eq!(axis.update(&m, f32::NAN, 0.0), Err(SampleError::Position));
    assert_eq!(
        axis.update(&m, f32::INFINITY, 0.0),
        Err(SampleError::Position)
    );
    assert_eq!(axis.update(&m, 1e-6, f32::NAN), Err(SampleError::Velocity));
    assert_eq!(
        axis.update(&m, 1e-6, f32::NEG_INFINITY),
        Err(SampleError::Velocity)
    );
    assert_eq!(axis, before);
    // Extreme finite input gives finite output.
    for (x, v) in [(f32::MAX, f32::MAX), (-f32::MAX, -f32::MAX), (1e-45, 1e-45)] {
        let f = axis.update(&m, x, v).unwrap();
        assert!(f.is_finite(), "{x} {v} -> {f}");
        assert!(axis.dry().abs() <= 1.5);
    }
}

/// Drives an axis through `path` (positions in 1 nm counts, in steps of
/// 1 count) at a fixed small velocity magnitude; returns H at every sample.
fn drive<const N: usize>(m: &Model<f32>, path: &[i64]) -> Vec<(i64, f32)> {
    let mut axis = Presliding::<i64, f32, N>::new(0, 1e-9).unwrap();
    let mut out = Vec::new();
    let mut x = 0i64;
    for &target in path {
        while x != target {
            let step = (target - x).signum();
            x += step;
            axis.update(m, x, step as f32 * 1e-9).unwrap();
            out.push((x, axis.dry()));
        }
    }
    out
}

fn h_at(trace: &[(i64, f32)], index: usize) -> f32 {
    trace[index].1
}

#[test]
fn h_continuous_across_turning_points() {
    let m = model(FIG5);
    // 1 nm steps against z_max = 10 µm: g(1e-4) = 1.0e-3, so no step of H
    // may exceed 2·Fs·g(1e-4) = 3.1e-3 N, at reversals included.
    let trace = drive::<0>(&m, &[6000, 2000, 9000, -12000, 0]);
    let bound = f64::from(2.0 * 1.5 * shape_f32(1e-4) + 1e-6);
    let worst = trace
        .windows(2)
        .map(|w| f64::from((w[1].1 - w[0].1).abs()))
        .fold(0.0, worse);
    assert!(worst <= bound, "largest step of H {worst} > {bound}");
    // Halving the step halves the largest jump (to first order, with the log).
    assert!(worst > 0.5 * bound);
}

#[test]
fn minor_loops_close_with_memory_and_not_without() {
    let m = model(FIG5);
    // Virgin to 6 µm, back to 2 µm, forward to 8 µm: the minor loop 6→2→6
    // closes at 6 µm with memory, and the branch to 8 µm is the virgin one.
    let path = [6000, 2000, 8000];
    let closing = drive::<4>(&m, &path);
    let reference = drive::<0>(&m, &path);
    let virgin = drive::<0>(&m, &[8000]);
    let first_at_6 = h_at(&closing, 5999);
    let back_at_6 = h_at(&closing, 5999 + 4000 + 4000);
    assert_eq!(closing[5999 + 8000].0, 6000);
    assert!(
        (first_at_6 - back_at_6).abs() < 2e-6,
        "{first_at_6} vs {back_at_6}"
    );
    let end_closing = closing.last().unwrap().1;
    let end_virgin = virgin.last().unwrap().1;
    let end_reference = reference.last().unwrap().1;
    assert!(
        (end_closing - end_virgin).abs() < 2e-6,
        "{end_closing} vs {end_virgin}"
    );
    // The single-turning-point rule does not return to the virgin curve.
    assert!(
        (end_reference - end_virgin).abs() > 1e-2,
        "{end_reference} vs {end_virgin}"
    );
    // Gross sliding wipes the memory.
    let mut axis = Presliding::<i64, f32, 4>::new(0, 1e-9).unwrap();
    for x in [3000, 1000, 2500, 1500] {
        axis.update(&m, x, 0.0).unwrap();
    }
    assert_eq!(axis.memory_len(), 3);
    axis.update(&m, 40_000, 0.0).unwrap();
    assert_eq!(axis.memory_len(), 0);
    assert!(axis.is_sliding());
}

#[test]
fn memory_overflow_forgets_the_oldest_loop_only() {
    let m = model(FIG5);
    // Three nested loops: 9→1→8→2→7→3 µm, then out to 9.5 µm.
    let path = [9000, 1000, 8000, 2000, 7000, 3000, 9500];
    let deep = drive::<8>(&m, &path);
    let shallow = drive::<2>(&m, &path);
    // A loop branch spans |x_T − x_R| ≥ 4 µm here instead of z_max, so its
    // first 1 nm step may reach 2·Fs·g(1 nm / 4 µm); no larger jump anywhere.
    let bound = 2.0 * 1.5 * shape_f32(1.0 / 4000.0) + 1e-6;
    for trace in [&deep, &shallow] {
        let (i, worst) = trace
            .windows(2)
            .map(|w| (w[1].1 - w[0].1).abs())
            .enumerate()
            .fold(
                (0, 0.0f32),
                |a, b| {
                    if a.1.is_nan() || b.1 <= a.1 {
                        a
                    } else {
                        b
                    }
                },
            );
        assert!(
            worst <= bound,
            "jump {worst} at sample {i}, x = {}",
            trace[i].0
        );
    }
    // Index of the sample where the final ascent passes position p µm.
    let ascent_start = deep.len() - 6500;
    let at = |trace: &[(i64, f32)], p: i64| {
        let i = ascent_start + (p - 3000) as usize - 1;
        assert_eq!(trace[i].0, p);
        trace[i].1
    };
    // Innermost loop (7 µm) closes in both: H equals its value at the turning point.
    let h7 = deep[9000 + 8000 + 7000 + 6000 + 5000 - 1].1;
    assert!((at(&deep, 7000) - h7).abs() < 2e-6);
    assert!((at(&shallow, 7000) - h7).abs() < 2e-6);
    // With capacity 8 the outer loops close too; with capacity 2 the
    // outermost point (9 µm) was forgotten, so the shallow trace differs there.
    let h9 = deep[9000 - 1].1;
    assert!((at(&deep, 9000) - h9).abs() < 2e-6);
    assert!((at(&shallow, 9000) - h9).abs() > 1e-3);
}

#[test]
fn break_away_falls_from_stiction_to_coulomb() {
    let m = model(FIG5);
    let predictor = BreakAwayPredictor::new(&m, 0.95).unwrap();
    for variant in Variant::ALL {
        let mut last = f32::INFINITY;
        let mut ks = vec![0.01f32];
        ks.extend((0..=15).map(|i| 1.0 + 2.0 * i as f32));
        ks.push(1e4);
        for &k in &ks {
            let ba = predictor.predict(&m, variant, k).unwrap();
            assert!(ba.f_ba <= last, "{variant:?}: F_ba rises at k = {k}");
            last = ba.f_ba;
        }
        let small = predictor.predict(&m, variant, 0.01).unwrap().f_ba;
        let large = predictor.predict(&m, variant, 1e4).unwrap().f_ba;
        assert!(small > 1.49, "{variant:?}: {small}");
        assert!(large < 1.0 + 1e-6, "{variant:?}: {large}");
    }
    // The closed forms by hand at k = 1: v_b = k·z_max/(F̂·|ln 0.95|).
    let ln = (0.95f64).ln().abs();
    let ba = predictor.predict(&m, Variant::Mean, 1.0).unwrap();
    let v_b = 1e-5 / (1.25 * ln);
    assert!((ba.v_b as f64 / v_b - 1.0).abs() < 1e-6);
    let s = 1.0 + 0.5 * (-v_b / 1e-3).exp();
    assert!((ba.f_ba as f64 / s - 1.0).abs() < 1e-6);
    let g = 0.95 * (1.0 - 0.95f64.ln());
    assert!((ba.t_ba as f64 / (s * g) - 1.0).abs() < 1e-6);
    // consistent: v_b·S(v_b) = k·z_max/|ln w_b|.
    let ba = predictor.predict(&m, Variant::Consistent, 3.0).unwrap();
    let residual = ba.v_b as f64 * m.stribeck(ba.v_b) as f64 / (3e-5 / ln) - 1.0;
    assert!(residual.abs() < 1e-6, "{residual}");
}

#[test]
fn predictor_rejects_bad_arguments() {
    let m = model(FIG5);
    for w_b in [0.0, 1.0, -0.5, f32::NAN] {
        assert_eq!(
            BreakAwayPredictor::new(&m, w_b).unwrap_err(),
            PredictError::InvalidBoundary
        );
    }
    let p = BreakAwayPredictor::new(&m, 0.95).unwrap();
    for k in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        assert_eq!(
            p.predict(&m, Variant::Mean, k).unwrap_err(),
            PredictError::InvalidRate
        );
    }
    assert_eq!(
        BreakAwayPredictor::phase_velocity(&m, Variant::Mean, 1.0, 1.0).unwrap_err(),
        PredictError::InvalidTravel
    );
}

#[test]
fn phase_curve_matches_paper_eq_12() {
    let m = model(FIG5);
    let ln = |w: f64| w.ln();
    for w in [0.1, 0.5, 0.9, 0.99] {
        let v = BreakAwayPredictor::phase_velocity(&m, Variant::Stiction, 2.0, w).unwrap();
        let expected = -2.0 * 1e-5 / (1.5 * ln(w as f64));
        assert!((v as f64 / expected - 1.0).abs() < 1e-6);
    }
    // The velocity rises without bound as w → 1 (the break-away).
    let near = BreakAwayPredictor::phase_velocity(&m, Variant::Mean, 2.0, 0.9999).unwrap();
    let far = BreakAwayPredictor::phase_velocity(&m, Variant::Mean, 2.0, 0.5).unwrap();
    assert!(near > 1000.0 * far);
}
