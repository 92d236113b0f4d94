//! Curves (MODEL.md §2, §3), the presliding state machine (§3) and the
//! effect composition (§5), against hand-computed values.

use breakaway_reference::*;

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + b.abs())
}

macro_rules! assert_close {
    ($a:expr, $b:expr) => {
        assert_close!($a, $b, 1e-12)
    };
    ($a:expr, $b:expr, $tol:expr) => {{
        let (a, b) = ($a, $b);
        assert!(
            close(a, b, $tol),
            "{} = {a:?}, expected {b:?}",
            stringify!($a)
        );
    }};
}

fn model(fc: f64, fs: f64, v: f64, delta: f64, sigma: f64, z_max: f64, eps: f64) -> Model {
    Model {
        mass: 1.0,
        fc,
        fs,
        v_stribeck: v,
        delta,
        sigma,
        z_max,
        epsilon: eps,
        effects: Effects::default(),
    }
}

/// Fc = 1, Fs = 2, V = 1, δ = 1, σ = 0.5, z_max = 1: easy hand values.
fn hand(eps: f64) -> Model {
    model(1.0, 2.0, 1.0, 1.0, 0.5, 1.0, eps)
}

#[test]
fn shape_function() {
    // Clamped to g(w <= 0) = 0 and g(w >= 1) = 1.
    for (w, g) in [(0.0, 0.0), (1.0, 1.0), (-0.5, 0.0), (3.0, 1.0)] {
        assert_eq!(shape(w), g, "g({w})");
    }
    assert!(shape(f64::NAN).is_nan());
    assert_close!(shape(0.5), 0.846_573_590_279_972_6);
    assert_close!(shape(0.95), 0.998_728_629_668_173);
    // g(0.15) = 0.43 as quoted in §3.
    assert!((shape(0.15) - 0.43).abs() < 0.005);
    // Monotone on [0, 1], slope −ln w, g'(1) = 0.
    let mut prev = 0.0;
    for i in 1..=10_000 {
        let w = f64::from(i) / 10_000.0;
        let g = shape(w);
        assert!(g > prev, "not increasing at {w}");
        prev = g;
    }
    let h = 1e-6;
    assert!((shape(1.0) - shape(1.0 - h)) / h < 1e-5);
    assert_close!(
        (shape(0.3 + h) - shape(0.3 - h)) / (2.0 * h),
        -(0.3f64.ln()),
        1e-8
    );
    // Tiny w: g(w) ≈ w(1 − ln w) > 0.
    assert!(shape(1e-300) > 0.0);
}

#[test]
fn stribeck_curve() {
    let m = model(1.0, 1.5, 1e-3, 1.0, 0.2, 1e-5, 0.0);
    assert_eq!(stribeck(&m, 0.0), 1.5);
    assert_close!(stribeck(&m, 1e-3), 1.0 + 0.5 * (-1.0f64).exp());
    assert_eq!(stribeck(&m, -1e-3), stribeck(&m, 1e-3));
    assert_close!(stribeck(&m, 1.0), 1.0, 1e-15);
    assert_eq!(stribeck(&m, f64::INFINITY), 1.0);
    // δ = 2 and δ = 0.5.
    let m2 = model(1.0, 1.5, 1e-3, 2.0, 0.0, 1e-5, 0.0);
    assert_close!(stribeck(&m2, 2e-3), 1.0 + 0.5 * (-4.0f64).exp());
    let mh = model(1.0, 1.5, 1e-3, 0.5, 0.0, 1e-5, 0.0);
    assert_close!(stribeck(&mh, 4e-3), 1.0 + 0.5 * (-2.0f64).exp());
    // Decreasing in |v|.
    let mut prev = f64::INFINITY;
    for i in 0..1000 {
        let s = stribeck(&m, f64::from(i) * 1e-5);
        assert!(s <= prev);
        prev = s;
    }
    // F_ss is odd, with σ·v.
    assert_eq!(steady_state(&m, 0.0), 0.0);
    assert_close!(steady_state(&m, 1e-3), 1.0 + 0.5 * (-1.0f64).exp() + 0.2e-3);
    assert_eq!(steady_state(&m, -1e-3), -steady_state(&m, 1e-3));
}

/// [`hand`] with deadband `eps` [m] after the first motion of
/// [`idle_then_first_motion`]: from idle at 0 to x = 0.5 at v = 0.2 (d = +1,
/// w = 0.5).
fn after_first_motion(eps: f64) -> (Model, Presliding) {
    let m = hand(eps);
    let mut p = Presliding::new(0.0);
    p.update(&m, 0.5, 0.2);
    (m, p)
}

#[test]
fn idle_then_first_motion() {
    let m = hand(0.0);
    let mut p = Presliding::new(0.0);
    assert_eq!(p.direction(), 0);
    // Idle: H = 0, F = σ·v.
    assert_eq!(p.update(&m, 0.0, 0.0), 0.0);
    assert_eq!(p.update(&m, 0.0, 0.3), 0.15);
    assert_eq!(p.dry(), 0.0);
    assert_eq!(p.direction(), 0);
    // First motion: d = +1, w = 0.5, H = S(0.2)·g(0.5).
    let f = p.update(&m, 0.5, 0.2);
    assert_eq!(p.direction(), 1);
    assert_close!(p.dry(), 1.539_689_423_385_825_4);
    assert_close!(f, 1.639_689_423_385_825_5);
    // Gross sliding: w = 1, H = S(v).
    p.update(&m, 2.0, 0.7);
    assert_close!(p.dry(), 1.496_585_303_791_409_4);
}

#[test]
fn first_motion_negative_and_ignoring_the_deadband() {
    let m = hand(0.1);
    let mut p = Presliding::new(1.0);
    p.update(&m, 0.75, -0.2);
    assert_eq!(p.direction(), -1);
    assert_close!(p.dry(), -1.085_006_735_116_33);
    // A first motion far smaller than ε still starts the branch.
    let mut q = Presliding::new(0.0);
    q.update(&m, 1e-9, 0.0);
    assert_eq!(q.direction(), 1);
    assert!(q.dry() > 0.0);
}

#[test]
fn reversal_takes_h_at_the_extremum() {
    let (m, mut p) = after_first_motion(0.0);
    let h1 = p.dry();
    // Back to 0.3: reversal, x_r = 0.5, H_r = H(0.5), w = 0.2.
    let f = p.update(&m, 0.3, -0.1);
    assert_eq!(p.direction(), -1);
    assert_eq!(p.turning_point(), 0.5);
    assert_eq!(p.dry_at_turning_point(), h1);
    assert_close!(p.dry(), -0.257_966_362_694_752_37);
    assert_close!(f, -0.307_966_362_694_752_36);
    // A second reversal takes H at the new extremum 0.3.
    let h2 = p.dry();
    p.update(&m, 0.35, 0.05);
    assert_eq!(p.direction(), 1);
    assert_eq!(p.turning_point(), 0.3);
    assert_eq!(p.dry_at_turning_point(), h2);
}

#[test]
fn reversal_is_continuous_for_clean_data() {
    // ε = 0: H on the new branch starts at H_r (g(0) = 0).
    let m = model(1.0, 1.5, 1e-3, 1.0, 0.0, 1e-5, 0.0);
    let mut p = Presliding::new(0.0);
    p.update(&m, 6e-6, 1e-4);
    let h_r = p.dry();
    p.update(&m, 6e-6 - 1e-18, -1e-9);
    assert!((p.dry() - h_r).abs() < 1e-11, "{} vs {h_r}", p.dry());
}

#[test]
fn pending_reversal_holds_h_at_the_extremum() {
    let (m, mut p) = after_first_motion(0.1);
    let h_ext = p.dry();
    assert_close!(h_ext, 1.539_689_423_385_825_4);
    // Same position, new velocity: H follows the branch with the current v,
    // and H(x_ext) is that latest value (the reversal starts from it).
    p.update(&m, 0.5, 0.0);
    assert_close!(p.dry(), 1.693_147_180_559_945_4);
    assert_ne!(h_ext, p.dry());
    let h_ext = p.dry();
    assert_eq!(p.dry_at_extremum(), h_ext);
    // Back by 0.05 <= ε: pending, H held at H(x_ext), d unchanged.
    p.update(&m, 0.45, -0.3);
    assert_eq!(p.direction(), 1);
    assert_eq!(p.dry(), h_ext);
    p.update(&m, 0.4, -0.3); // exactly ε back (up to rounding: 0.5 − 0.4 = 0.09999…)
    assert_eq!(p.direction(), 1);
    assert_eq!(p.dry(), h_ext);
    // Back by 0.12 > ε: confirmed; new branch already w = 0.12 along it:
    // H = H_r + (−S(−0.3) − H_r)·g(0.12).
    p.update(&m, 0.38, -0.3);
    assert_eq!(p.direction(), -1);
    assert_eq!(p.turning_point(), 0.5);
    assert_eq!(p.dry_at_turning_point(), h_ext);
    assert_close!(p.dry(), 0.407_361_937_431_896_4);
}

#[test]
fn pending_then_forward_again_continues_the_branch() {
    let (m, mut p) = after_first_motion(0.1);
    p.update(&m, 0.45, -0.1);
    assert_eq!(p.direction(), 1);
    // Forward past x_ext: same branch (x_r = 0, H_r = 0), no reversal.
    p.update(&m, 0.6, 0.1);
    assert_eq!(p.direction(), 1);
    assert_eq!(p.turning_point(), 0.0);
    let s = stribeck(&m, 0.1);
    assert_close!(p.dry(), s * shape(0.6));
}

#[test]
fn without_presliding_switches_ideally() {
    let m = model(1.0, 2.0, 1.0, 1.0, 0.0, 0.0, 0.0);
    let mut p = Presliding::new(0.0);
    p.update(&m, 1e-12, 0.5);
    assert_close!(p.dry(), stribeck(&m, 0.5));
    p.update(&m, 0.5e-12, -0.25);
    assert_eq!(p.direction(), -1);
    assert_close!(p.dry(), -stribeck(&m, 0.25));
}

#[test]
fn non_finite_positions_do_not_panic() {
    let m = hand(0.0);
    let mut p = Presliding::new(0.0);
    p.update(&m, f64::NAN, 0.0);
    assert_eq!(p.direction(), 0);
    p.update(&m, 0.5, 0.2);
    let h = p.dry();
    p.update(&m, f64::NAN, 0.0);
    assert_eq!(p.dry(), h);
}

// ---- Friction (§5) ----

fn base() -> Model {
    model(1.0, 1.5, 1e-3, 1.0, 0.3, 1e-5, 0.0)
}

#[test]
fn friction_without_effects_equals_presliding() {
    let m = base();
    let mut f = Friction::new(&m, 0.0, 0.0, 0.0);
    let mut p = Presliding::new(0.0);
    let xs = [0.0, 1e-6, 3e-6, 2e-6, 2.5e-6, 4e-5, 3e-5];
    let vs = [0.0, 1e-4, 2e-4, -1e-4, 5e-5, 1e-2, -1e-3];
    for (i, (&x, &v)) in xs.iter().zip(&vs).enumerate() {
        let a = f.update(&m, 0.01 * i as f64, x, v);
        let b = p.update(&m, x, v);
        assert_eq!(a, b);
        assert_eq!(f.force(), a);
        assert_eq!(f.dry(), p.dry());
    }
}

#[test]
fn offset_and_ripple_add() {
    let mut m = base();
    m.effects.offset = Some(Offset { f0: -0.1 });
    m.effects.position_ripple = Some(PositionRipple {
        amplitude: 0.2,
        wavelength: 4e-6,
        phase: 0.5,
    });
    let mut f = Friction::new(&m, 0.0, 0.0, 0.0);
    // At rest at the start: H = 0, F = F0 + A·sin(φ).
    assert_close!(f.update(&m, 0.0, 0.0, 0.0), -0.1 + 0.2 * 0.5f64.sin());
    let x = 1e-6;
    let v = 2e-4;
    let h = stribeck(&m, v) * shape(0.1);
    let expect = h + 0.3 * v - 0.1 + 0.2 * (2.0 * std::f64::consts::PI * 0.25 + 0.5).sin();
    assert_close!(f.update(&m, 0.1, x, v), expect);
}

#[test]
fn asymmetry_and_drift_scale_the_levels() {
    let mut m = base();
    m.sigma = 0.0;
    m.effects.asymmetry = Some(Asymmetry { a: 0.1 });
    m.effects.drift = Some(Drift { beta: 0.01 });
    let mut f = Friction::new(&m, 10.0, 0.0, 0.0);
    // Gross sliding forward at t = 20 (t − t0 = 10): sc = 1.1·1.1.
    let v = 1e-3;
    let sc = 1.1 * 1.1;
    let s = sc * (1.0 + 0.5 * (-1.0f64).exp());
    assert_close!(f.update(&m, 20.0, 1.0, v), s);
    // Backward, gross sliding (reversal then w = 1): sc = 0.9·1.1.
    let sc = 0.9 * 1.1;
    let s = sc * (1.0 + 0.5 * (-1.0f64).exp());
    assert_close!(f.update(&m, 20.0, 0.0, -v), -s);
}

#[test]
fn dwell_time_and_dwell_stiction() {
    let mut m = base();
    m.sigma = 0.0;
    m.effects.dwell_stiction = Some(DwellStiction {
        delta_fs: 0.2,
        gamma: 0.5,
        v_rest: 1e-4,
    });
    let mut f = Friction::new(&m, 1.0, 0.0, 0.0);
    f.update(&m, 1.0, 0.0, 0.0);
    assert_eq!(f.dwell_time(), 0.0);
    f.update(&m, 2.0, 0.0, 5e-5);
    assert_eq!(f.dwell_time(), 1.0);
    f.update(&m, 3.5, 0.0, 0.0);
    assert_eq!(f.dwell_time(), 2.5);
    // Motion: held.
    f.update(&m, 4.0, 1.0, 1e-2);
    assert_eq!(f.dwell_time(), 2.5);
    // Gross sliding at v = 1e-2 (w = 1): Fs' = 1.5 + 0.2·2.5/3.
    let fs = 1.5 + 0.2 * 2.5 / 3.0;
    assert_close!(f.dry(), 1.0 + (fs - 1.0) * (-10.0f64).exp());
    // A new rest restarts the interval.
    f.update(&m, 5.0, 1.0, 0.0);
    assert_eq!(f.dwell_time(), 0.0);
    f.update(&m, 5.25, 1.0, 0.0);
    assert_eq!(f.dwell_time(), 0.25);
    // Gross sliding at rest: w = 1 from x_r = 0, v = 0: H = Fs'.
    assert_close!(f.dry(), 1.5 + 0.2 * 0.25 / 0.75);
}

#[test]
fn frictional_lag_is_an_exact_first_order_filter() {
    let mut m = base();
    m.sigma = 0.0;
    let tau = 0.01;
    m.effects.frictional_lag = Some(FrictionalLag { tau_l: tau });
    let mut f = Friction::new(&m, 0.0, 0.0, 0.0);
    f.update(&m, 0.0, 0.0, 0.0);
    assert_eq!(f.lagged_velocity(), 0.0);
    // Step to v = 1 held: v_l(t) = 1 − e^{−t/τ} after the linear ramp of the
    // first interval; check the exact FOH update over a constant segment.
    let v = 2e-3;
    f.update(&m, 0.02, 1.0, v);
    // Ramp 0 → v over h = 0.02: v_l = v − v·(τ/h)(1 − e^{−h/τ}).
    let e = (-2.0f64).exp();
    let vl1 = v - v * 0.5 * (1.0 - e);
    assert_close!(f.lagged_velocity(), vl1, 1e-14);
    // Constant v over another 0.01: v_l = v + (vl1 − v)·e^{−1}; the result is
    // independent of how the interval is split.
    let mut g = f.clone();
    f.update(&m, 0.03, 1.0, v);
    g.update(&m, 0.025, 1.0, v);
    g.update(&m, 0.03, 1.0, v);
    let vl2 = v + (vl1 - v) * (-1.0f64).exp();
    assert_close!(f.lagged_velocity(), vl2, 1e-14);
    assert_close!(g.lagged_velocity(), vl2, 1e-14);
    // S is evaluated at v_l (gross sliding, w = 1).
    assert_close!(f.dry(), stribeck(&m, vl2));
}

/// `update_with` given the terms of the model and the sample (the Stribeck
/// decay, `|v|^n`, the ripple's sine) is `update` to the last bit, with and
/// without a dip,
/// with the effects that scale the levels, and with `frictional_lag`, whose
/// curve takes the decay of the lagged velocity (from a [`LagFilter`] run
/// beside it).
#[test]
fn update_with_its_own_terms_is_update() {
    let mut dip = base();
    dip.delta = 1.3;
    dip.effects.asymmetry = Some(Asymmetry { a: 0.1 });
    dip.effects.nonlinear_viscous = Some(NonlinearViscous {
        sigma_n: 0.4,
        n: 0.6,
    });
    let ripple = PositionRipple {
        amplitude: 0.05,
        wavelength: 3e-5,
        phase: 0.4,
    };
    dip.effects.position_ripple = Some(ripple);
    let mut flat = dip.clone();
    flat.fs = flat.fc;
    let mut lag = dip.clone();
    lag.effects.frictional_lag = Some(FrictionalLag { tau_l: 0.02 });
    for m in [dip, flat, lag.clone()] {
        let (mut plain, mut given) = (
            Friction::new(&m, 0.0, 0.0, 0.0),
            Friction::new(&m, 0.0, 0.0, 0.0),
        );
        let mut seen_decay = false;
        let tau_l = m.effects.frictional_lag.map(|l| l.tau_l);
        let mut lag_filter = LagFilter::new(0.0, 0.0);
        for i in 0..4000 {
            let t = i as f64 * 1e-3;
            let x = 2e-4 * (3.0 * t).sin() + 1e-5 * (40.0 * t).sin();
            let v = 6e-4 * (3.0 * t).cos() + 4e-4 * (40.0 * t).cos();
            let v_l = lag_filter.update(tau_l, t, v);
            let decay = stribeck_decay(m.v_stribeck, m.delta, v_l);
            seen_decay |= decay > 1e-3 && decay < 0.999;
            let terms = SampleTerms {
                decay: Some(decay),
                speed_pow: Some(v.abs().powf(0.6)),
                rest_speed: Some(v.abs()),
                ripple_sin: Some(
                    (2.0 * std::f64::consts::PI * x / ripple.wavelength + ripple.phase).sin(),
                ),
            };
            let (a, b) = (
                plain.update(&m, t, x, v),
                given.update_with(&m, t, x, v, terms),
            );
            assert_eq!(a.to_bits(), b.to_bits(), "t = {t}: {a} vs {b}");
        }
        assert!(seen_decay, "the motion never reached the dip");
    }
    // The lag model does read the given decay: the decay of `v` instead of
    // `v_l` moves the force.
    let mut lag_filter = LagFilter::new(0.0, 0.0);
    let (mut plain, mut wrong) = (
        Friction::new(&lag, 0.0, 0.0, 0.0),
        Friction::new(&lag, 0.0, 0.0, 0.0),
    );
    let mut largest: f64 = 0.0;
    for i in 0..4000 {
        let t = i as f64 * 1e-3;
        let x = 2e-4 * (3.0 * t).sin() + 1e-5 * (40.0 * t).sin();
        let v = 6e-4 * (3.0 * t).cos() + 4e-4 * (40.0 * t).cos();
        let v_l = lag_filter.update(Some(0.02), t, v);
        assert_eq!(v_l.to_bits(), {
            plain.update(&lag, t, x, v);
            plain.lagged_velocity().to_bits()
        });
        let terms = SampleTerms {
            decay: Some(stribeck_decay(lag.v_stribeck, lag.delta, v)),
            ..SampleTerms::default()
        };
        largest = largest.max((wrong.update_with(&lag, t, x, v, terms) - plain.force()).abs());
    }
    assert!(largest > 1e-3, "largest difference {largest} N");
}
