//! Full dynamics (MODEL.md §1, §4, §8): break-away under a ramp, convergence,
//! and the general simulator.

use breakaway_reference::*;

mod common;

/// The Fig. 5 setting with shape exponent `delta`.
fn setting(delta: f64) -> Model {
    Model {
        delta,
        ..common::paper()
    }
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

fn opts(tol: f64) -> SimOptions {
    SimOptions {
        tol,
        ..SimOptions::default()
    }
}

/// Under the slow ramps k = 0.01, 0.03 and 0.1 N/s (w_b = 0.95): k, the
/// dynamic break-away of `m` at the integrator tolerance `tol` and the
/// quasi-static `Consistent` one.
fn slow_ramps(m: &Model, tol: f64) -> Vec<(f64, DynamicBreakAway, BreakAway)> {
    [0.01, 0.03, 0.1]
        .into_iter()
        .map(|k| {
            let d = simulate_break_away_with(m, k, 0.95, &opts(tol)).unwrap();
            let p = predict_break_away(m, Variant::Consistent, k, 0.95).unwrap();
            (k, d, p)
        })
        .collect()
}

#[test]
fn dynamic_matches_quasi_static_for_slow_ramps() {
    // δ = 2: S'(0) = 0, so presliding is not self-excited at creep speeds;
    // inertia is negligible for k ≪ 3.6 N/s (§4).
    let m = setting(2.0);
    for (k, d, p) in slow_ramps(&m, 1e-9) {
        assert_eq!(d.f_ba, k * d.t_ba);
        assert!(rel(d.t_ba, p.t_ba) < 2e-4, "k={k}: {d:?} vs {p:?}");
        assert!(rel(d.f_ba, p.f_ba) < 0.01, "k={k}: {d:?} vs {p:?}");
        // The velocity at break-away is the creep velocity of eq. 12 (up to
        // the undamped presliding oscillation excited at the start).
        assert!(rel(d.v_b, p.v_b) < 0.25, "k={k}: {d:?} vs {p:?}");
    }
}

#[test]
fn paper_setting_is_close_to_quasi_static_but_self_excited() {
    // δ = 1 (the paper's setting): ∂H/∂v = g·S'(0) = −500·g N·s/m, the creep
    // is unstable and breaks up into micro stick-slip (§8, Π ≈ 5.5); the
    // dynamic break-away is a little below the quasi-static one.
    let m = setting(1.0);
    for (k, d, p) in slow_ramps(&m, 1e-8) {
        assert!(rel(d.f_ba, p.f_ba) < 0.025, "k={k}: {d:?} vs {p:?}");
        assert!(d.f_ba < p.f_ba, "k={k}: {d:?} vs {p:?}");
        assert!(d.f_ba > m.fc);
    }
}

#[test]
fn inertia_raises_the_break_away_at_fast_ramps() {
    // §4/§8: for k ≳ 3.6 N/s (m = 1 kg, z_max = 10 µm) the quasi-static fall
    // towards Fc does not happen in the full dynamics.
    let m = setting(1.0);
    let d = simulate_break_away(&m, 30.0, 0.95).unwrap();
    let p = predict_break_away(&m, Variant::Consistent, 30.0, 0.95).unwrap();
    assert!(d.f_ba > p.f_ba + 0.3, "{d:?} vs {p:?}");
    // Heavier mass, stronger effect.
    let mut heavy = m.clone();
    heavy.mass = 100.0;
    let dh = simulate_break_away(&heavy, 30.0, 0.95).unwrap();
    assert!(dh.f_ba > d.f_ba);
}

/// Tolerances 1e-6·32^{−i}, i = 1..4 (3.1e-8 … 9.5e-13): the DP5(4) step
/// size scales as tol^{1/5}, so each level halves the steps; the error of an
/// order-5 method falls ≈ 32×.
fn halving_sequence(m: &Model, k: f64) -> Vec<f64> {
    (1..5)
        .map(|i| {
            let tol = 1e-6 / 32f64.powi(i);
            simulate_break_away_with(m, k, 0.95, &opts(tol))
                .unwrap()
                .t_ba
        })
        .collect()
}

#[test]
fn break_away_time_converges_under_step_halving() {
    // Smooth case (δ = 2, k = 1): fifth order.
    let t = halving_sequence(&setting(2.0), 1.0);
    let d: Vec<f64> = t.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    eprintln!("delta=2 k=1: t_ba {t:?}, differences {d:?}");
    assert!(d[0] / d[1] > 16.0 && d[1] / d[2] > 16.0, "{d:?}");
    assert!(rel(t[3], t[2]) < 2e-8, "{t:?}");

    // Paper setting at a fast ramp (δ = 1, k = 10): turning points and the
    // w·ln w kink after each reduce the observed order, but it converges.
    let t = halving_sequence(&setting(1.0), 10.0);
    let d: Vec<f64> = t.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    eprintln!("delta=1 k=10: t_ba {t:?}, differences {d:?}");
    assert!(d[0] > d[1] && d[1] > d[2] && d[0] / d[2] > 30.0, "{d:?}");
    assert!(rel(t[3], t[2]) < 2e-7, "{t:?}");
}

#[test]
fn deadband_changes_little_when_small() {
    let m = setting(1.0);
    let mut me = m.clone();
    me.epsilon = 1e-8; // ε = z_max/1000
    let a = simulate_break_away(&m, 3.0, 0.95).unwrap();
    let b = simulate_break_away(&me, 3.0, 0.95).unwrap();
    assert!(rel(a.t_ba, b.t_ba) < 0.02, "{a:?} {b:?}");
}

#[test]
fn break_away_errors() {
    let m = setting(1.0);
    let name = |r: Result<DynamicBreakAway, SimError>| match r {
        Err(SimError::Argument(e)) => e.name,
        other => panic!("{other:?}"),
    };
    assert_eq!(name(simulate_break_away(&m, 0.0, 0.95)), "k");
    assert_eq!(name(simulate_break_away(&m, f64::NAN, 0.95)), "k");
    assert_eq!(name(simulate_break_away(&m, 1.0, 1.0)), "w_b");
    assert_eq!(name(simulate_break_away(&m, 1.0, 0.0)), "w_b");
    let mut m0 = m.clone();
    m0.z_max = 0.0;
    assert_eq!(name(simulate_break_away(&m0, 1.0, 0.95)), "z_max");
    assert_eq!(
        name(simulate_break_away_with(&m, 1.0, 0.95, &opts(0.0))),
        "tol"
    );
    let mut bad = m.clone();
    bad.mass = 0.0;
    assert!(matches!(
        simulate_break_away(&bad, 1.0, 0.95),
        Err(SimError::Model(e)) if e.key == "mass"
    ));
    let r = simulate_break_away_with(
        &m,
        0.01,
        0.95,
        &SimOptions {
            tol: 1e-10,
            max_steps: 100,
        },
    );
    assert!(matches!(r, Err(SimError::TooManySteps { .. })), "{r:?}");
    let e = simulate_break_away(&m, -1.0, 0.95).unwrap_err();
    assert!(e.to_string().starts_with("k:"), "{e}");
}

#[test]
fn simulate_reaches_the_viscous_coulomb_steady_state() {
    let mut m = setting(1.0);
    m.sigma = 1.0;
    let u = |_t: f64| 3.0;
    let s = simulate(&m, &u, 0.0, 0.0, 10.0, 0.01).unwrap();
    assert_eq!(s.len(), 1001);
    assert_eq!(s[0].t, 0.0);
    assert!((s[1000].t - 10.0).abs() < 1e-12);
    // m·v' = 3 − Fc − σ·v (S = Fc for v ≫ V): v = 2·(1 − e^{−t}) closely.
    let last = s[1000];
    assert!((last.v - 2.0).abs() < 1e-3, "{last:?}");
    assert!((last.f - 3.0).abs() < 1e-3, "{last:?}");
    let mid = s[200];
    let approx = 2.0 * (1.0 - (-2.0f64).exp());
    assert!((mid.v - approx).abs() < 2e-3, "{mid:?} vs {approx}");
    // Energy: work of u = kinetic energy + dissipation ∫F·v dt >= 0.
    let work = 3.0 * last.x;
    let kinetic = 0.5 * m.mass * last.v * last.v;
    let dissipated: f64 = s
        .windows(2)
        .map(|w| 0.5 * (w[0].f * w[0].v + w[1].f * w[1].v) * (w[1].t - w[0].t))
        .sum();
    assert!(dissipated > 0.0);
    assert!(
        rel(work, kinetic + dissipated) < 1e-3,
        "{work} vs {kinetic} + {dissipated}"
    );
}

#[test]
fn simulate_at_rest_below_coulomb_stays_in_presliding() {
    // Constant force below Fc, δ = 2, Π = √(2·Fs·z_max/m)/V ≈ 0.55: the mass
    // settles within the presliding range.
    let mut m = setting(2.0);
    m.v_stribeck = 1e-2;
    let u = |_t: f64| 0.5;
    let s = simulate(&m, &u, 1e-3, 0.0, 2.0, 0.01).unwrap();
    for p in &s {
        assert!(p.x >= 1e-3 && p.x - 1e-3 < m.z_max, "{p:?}");
    }
    let last = s[s.len() - 1];
    assert!(last.v.abs() < 1e-6, "{last:?}");
    assert!((last.f - 0.5).abs() < 1e-3, "{last:?}");
}

#[test]
fn simulate_with_effects_offset_and_viscous() {
    let mut m = setting(1.0);
    m.sigma = 2.0;
    m.effects.offset = Some(Offset { f0: 0.5 });
    m.effects.dwell_stiction = Some(DwellStiction {
        delta_fs: 0.2,
        gamma: 0.5,
        v_rest: 1e-4,
    });
    let u = |_t: f64| 4.0;
    let s = simulate(&m, &u, 0.0, 0.0, 5.0, 0.05).unwrap();
    // Steady state v = (u − Fc − F0)/σ = 1.25.
    let last = s[s.len() - 1];
    assert!((last.v - 1.25).abs() < 1e-3, "{last:?}");
}

#[test]
fn simulate_errors() {
    let m = setting(1.0);
    let u = |_t: f64| 0.0;
    let name = |r: Result<Vec<Sample>, SimError>| match r {
        Err(SimError::Argument(e)) => e.name,
        other => panic!("{other:?}"),
    };
    assert_eq!(name(simulate(&m, &u, 0.0, 0.0, 1.0, 0.0)), "dt_out");
    assert_eq!(name(simulate(&m, &u, 0.0, 0.0, -1.0, 0.1)), "t_end");
    assert_eq!(name(simulate(&m, &u, f64::NAN, 0.0, 1.0, 0.1)), "x0");
    assert_eq!(name(simulate(&m, &u, 0.0, f64::INFINITY, 1.0, 0.1)), "v0");
    assert_eq!(name(simulate(&m, &u, 0.0, 0.0, 1e9, 1e-3)), "dt_out");
    let bad_u = |_t: f64| f64::NAN;
    assert!(matches!(
        simulate(&m, &bad_u, 0.0, 0.0, 1.0, 0.1),
        Err(SimError::Breakdown { .. }) | Err(SimError::TooManySteps { .. })
    ));
}
