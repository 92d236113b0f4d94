//! The generator's friction against the MODEL.md formulas at hand-picked
//! points (values worked out by hand, not by the code under test).

use breakaway_gen::friction::{
    g, stribeck, Asymmetry, Drift, DwellStiction, Effect, Effects, FrictionalLag, Model,
    ModelFriction, NonlinearViscous, Offset, PositionRipple,
};

fn paper() -> Model {
    Model::paper()
}

#[test]
fn stribeck_curve_points() {
    // S(0) = Fs.
    assert_eq!(stribeck(0.0, 1.0, 1.5, 1e-3, 2.0), 1.5);
    // S(V) = Fc + (Fs − Fc)/e = 1.18393972058572.
    assert!((stribeck(1e-3, 1.0, 1.5, 1e-3, 2.0) - 1.183_939_720_585_72).abs() < 1e-12);
    // S(2V) with δ = 2: 1 + 0.5·e^−4 = 1.00915781944437.
    assert!((stribeck(2e-3, 1.0, 1.5, 1e-3, 2.0) - 1.009_157_819_444_37).abs() < 1e-12);
    // S(∞) → Fc.
    assert!((stribeck(1.0, 1.0, 1.5, 1e-3, 2.0) - 1.0).abs() < 1e-15);
    assert!((stribeck(10.0, 2.0, 3.0, 1e-3, 0.6) - 2.0).abs() < 1e-6);
    // δ = 0.5 at |v| = 4V: 1 + 0.5·e^−2 = 1.06766764161831.
    assert!((stribeck(-4e-3, 1.0, 1.5, 1e-3, 0.5) - 1.067_667_641_618_31).abs() < 1e-12);
}

#[test]
fn presliding_shape_points() {
    assert_eq!(g(0.0), 0.0);
    assert_eq!(g(1.0), 1.0);
    // g(0.1) = 0.1·(1 + ln 10) = 0.330258509299405.
    assert!((g(0.1) - 0.330_258_509_299_405).abs() < 1e-14);
    // g(0.95) = 0.998728… (the paper's z_0.95 boundary).
    assert!((g(0.95) - 0.998_728_629_668_17).abs() < 1e-12);
    // g'(1) = 0: g(1 − 1e-4) ≈ 1 − 5e-9.
    assert!((1.0 - g(1.0 - 1e-4)) < 1e-8);
}

#[test]
fn presliding_branch_computed_by_hand() {
    let mut f = ModelFriction::new(paper(), &[], 0.0);
    // Idle: no motion, no force.
    assert_eq!(f.eval(0.0, 0.0, 0.0, None).h, 0.0);
    // Forward 3 µm at v = 0: H = Fs·g(0.3) = 1.5·0.3·(1 − ln 0.3) = 0.991787…
    let e = f.eval(3e-6, 0.0, 0.0, None);
    assert!((e.h - 0.991_787_761_946_67).abs() < 1e-12, "{}", e.h);
    // Forward to 8 µm while sliding at V: H = S(V)·g(0.8).
    let e = f.eval(8e-6, 1e-3, 0.0, None);
    let want = 1.183_939_720_585_72 * 0.8 * (1.0 - 0.8f64.ln());
    assert!((e.h - want).abs() < 1e-12);
    // Reverse by 2 µm at rest: H_r = that H, branch towards −Fs with w = 0.2.
    let hr = want;
    let e = f.eval(6e-6, 0.0, 0.0, None);
    let want = hr + (-1.5 - hr) * 0.2 * (1.0 - 0.2f64.ln());
    assert!((e.h - want).abs() < 1e-12);
    assert_eq!(e.d, -1.0);
    // Beyond z_max from the turning point: gross sliding, H = −S(v).
    let e = f.eval(-5e-6, -2e-3, 0.0, None);
    assert!((e.h + 1.009_157_819_444_37).abs() < 1e-12);
    assert_eq!(e.w, 1.0);
}

#[test]
fn effects_compose_as_section_5() {
    let mut m = paper();
    m.p.sigma = 3.0;
    m.e = Effects {
        offset: Some(Offset { f0: -0.1 }),
        asymmetry: Some(Asymmetry { a: 0.2 }),
        position_ripple: Some(PositionRipple {
            amplitude: 0.05,
            wavelength: 1e-3,
            phase: 0.5,
        }),
        dwell_stiction: Some(DwellStiction {
            delta_fs: 0.4,
            gamma: 1.0,
            v_rest: 1e-5,
        }),
        frictional_lag: None,
        drift: Some(Drift { beta: 0.01 }),
        nonlinear_viscous: Some(NonlinearViscous {
            sigma_n: 2.0,
            n: 0.5,
        }),
    };
    // Levels at d = +1, t = 10 s, t_d = 3 s:
    // sc = 1.2·1.1 = 1.32; Fc' = 1.32; Fs' = 1.98 + 0.4·3/4 = 2.28.
    let (fc, fs) = m.levels(1.0, 10.0, 3.0);
    assert!((fc - 1.32).abs() < 1e-12);
    assert!((fs - 2.28).abs() < 1e-12);
    // The velocity and position terms at v = 4e-4 m/s, x = 0.25 mm:
    // σ·v + σ_n·√v + F0 + A·sin(π/2 + 0.5) = 1.2e-3 + 0.04 − 0.1 + 0.05·cos 0.5.
    let f = m.viscous_terms(4e-4) + m.static_terms(2.5e-4);
    let want = 1.2e-3 + 0.04 - 0.1 + 0.05 * 0.5f64.cos();
    assert!((f - want).abs() < 1e-12);
    // Steady curve F_ss(−V) at t = 0: −S·(1 − a) − σV − σ_n√V + F0.
    let s = 0.8 + 0.4 / std::f64::consts::E;
    let want = -s - 3e-3 - 2.0 * 1e-3f64.sqrt() - 0.1;
    assert!((m.steady(-1e-3) - want).abs() < 1e-12);
}

#[test]
fn frictional_lag_uses_lagged_velocity() {
    let mut m = paper();
    m.e.frictional_lag = Some(FrictionalLag { tau_l: 0.01 });
    let mut f = ModelFriction::new(m, &[Effect::FrictionalLag], 0.0);
    let mut d = [0.0];
    // First sample: v_l = v, no difference.
    f.eval(0.0, 0.0, 0.0, Some(&mut d));
    assert_eq!(d[0], 0.0);
    // After 10 ms at v = 2V from rest: v_l = 2V·(1 − e^−1).
    for _ in 0..1000 {
        f.advance(2e-3, 1e-5);
    }
    let x = 1e-3; // far beyond z_max: gross sliding
    f.eval(x, 2e-3, 0.01, Some(&mut d));
    let vl = 2e-3 * (1.0 - (-1.0f64).exp());
    let want = stribeck(vl, 1.0, 1.5, 1e-3, 2.0) - stribeck(2e-3, 1.0, 1.5, 1e-3, 2.0);
    assert!((d[0] - want).abs() < 1e-9, "{} vs {want}", d[0]);
}

#[test]
fn dwell_clock_logs_every_change_of_its_rest_state() {
    let mut m = paper();
    m.e.dwell_stiction = Some(DwellStiction {
        delta_fs: 0.2,
        gamma: 0.5,
        v_rest: 1e-4,
    });
    let mut f = ModelFriction::new(m, &[Effect::DwellStiction], 0.0);
    // At rest until 0.1 s, out at 2e-4 m/s, a dip to 5e-5 m/s at 0.102 s
    // (a new rest: t_d starts again), out again at 0.103 s.
    let steps = [
        (0.0, 0.0),
        (0.1, 2e-4),
        (0.101, 2e-4),
        (0.102, 5e-5),
        (0.103, 2e-4),
    ];
    for (t, v) in steps {
        f.eval(v * t, v, t, None);
        f.advance(v, 1e-3);
    }
    assert_eq!(f.rest_log(), &[(0.1, false), (0.102, true), (0.103, false)]);
    // The dip restarted the clock: t_d is the 1 ms of the dip's rest.
    assert!((f.rest_length() - 1e-3).abs() < 1e-15);
    // Without dwell_stiction there is no clock to log, not even at v = 0
    // after a motion.
    let mut plain = ModelFriction::new(paper(), &[], 0.0);
    for (t, v) in steps.into_iter().chain([(0.2, 0.0)]) {
        plain.eval(v * t, v, t, None);
    }
    assert!(plain.rest_log().is_empty());
}
