//! `compensation::VelocityEstimator` against closed forms of the α–β filter
//! computed here in f64: the double pole at p = exp(−ω_e·T), the steady
//! velocity lag a·T·((1 + p)/(1 − p) − ½) under a constant acceleration a
//! (Kalata, "The tracking index", IEEE Trans. AES 20(2), 1984), no lag at
//! constant speed through a quantising encoder, a wrapping 32-bit counter,
//! Q16 against `f32`, and rejected settings and samples.

use breakaway::compensation::{ConfigError, Setting, VelocityConfig, VelocityEstimator};
use breakaway::{Model, SampleError, Q16};

mod support;
use support::{worse, FIG5};

const PERIOD: f32 = 1e-3;

fn config(bandwidth: f32) -> VelocityConfig {
    VelocityConfig {
        bandwidth,
        period: PERIOD,
    }
}

#[test]
fn error_decays_with_a_double_pole_at_exp_minus_bandwidth_times_period() {
    let bandwidth = 300.0;
    let p = (-(bandwidth as f64) * PERIOD as f64).exp();
    let v0 = 1e-3;
    let mut estimator = VelocityEstimator::<f32>::new(config(bandwidth), 1.0).unwrap();
    let errors: Vec<f64> = (0..40)
        .map(|n| {
            let x = (v0 * PERIOD as f64 * n as f64) as f32;
            v0 - f64::from(estimator.update(x).unwrap())
        })
        .collect();
    // The first update only sets the position; from the second on the
    // error obeys e[n+2] − 2p·e[n+1] + p²·e[n] = 0.
    let mut worst = 0.0f64;
    for n in 1..errors.len() - 2 {
        let residual = errors[n + 2] - 2.0 * p * errors[n + 1] + p * p * errors[n];
        worst = worse(worst, residual.abs() / v0);
    }
    eprintln!("double pole: recurrence residual {worst:.2e} of v0");
    // Measured 2.2e-7 (f32 rounding).
    assert!(worst < 1e-6, "recurrence residual {worst:.2e} of v0");
    // And it does decay: after 40 periods (ω_e·t = 12) below 1e-3·v0.
    assert!(errors[39].abs() < 1e-3 * v0, "{}", errors[39]);
}

#[test]
fn lag_under_constant_acceleration_matches_the_alpha_beta_formula() {
    let (bandwidth, a, q) = (300.0f32, 0.04f64, 1e-9f64);
    let t = PERIOD as f64;
    let p = (-(bandwidth as f64) * t).exp();
    let lag = a * t * ((1.0 + p) / (1.0 - p) - 0.5);
    let mut estimator = VelocityEstimator::<i64>::new(config(bandwidth), q as f32).unwrap();
    let mut v_hat = 0.0;
    let n_last = 2000;
    for n in 0..=n_last {
        let x = 0.5 * a * (n as f64 * t).powi(2);
        v_hat = f64::from(estimator.update((x / q).round() as i64).unwrap());
    }
    let measured = a * n_last as f64 * t - v_hat;
    eprintln!("lag {measured:.5e} m/s, formula {lag:.5e} m/s");
    assert!(
        // Measured 4e-5 relative (1 nm counts).
        (measured / lag - 1.0).abs() < 1e-3,
        "lag {measured:.4e} m/s, formula {lag:.4e} m/s"
    );
}

/// v̂ of `count(n)` for `periods` periods at ω_e = 3000 rad/s, 1 µm counts.
fn run<P: breakaway::Position<f32, Scale = f32>>(
    periods: usize,
    count: impl Fn(usize) -> P,
) -> Vec<f32> {
    let mut estimator = VelocityEstimator::<P>::new(config(3000.0), 1e-6).unwrap();
    (0..periods)
        .map(|n| estimator.update(count(n)).unwrap())
        .collect()
}

#[test]
fn no_lag_at_constant_speed_through_an_encoder_and_a_wrapping_counter() {
    // 2.5 mm/s through 1 µm counts: 2.5 counts per period, read as 2 or 3.
    let v0 = 2.5e-3;
    let counts = |n: usize| (n as f64 * v0 * PERIOD as f64 / 1e-6).floor() as i64;
    let v = run(2000, counts);
    let settled = &v[1000..];
    let mean = settled.iter().map(|&x| f64::from(x)).sum::<f64>() / settled.len() as f64;
    eprintln!("constant speed: mean {mean:.6e} m/s of {v0:e}");
    assert!((mean / v0 - 1.0).abs() < 1e-4, "mean {mean}");
    // The spread is the count quantisation: below one count per period
    // (1 mm/s; measured 0.41 mm/s).
    let worst = settled
        .iter()
        .map(|&x| (f64::from(x) - v0).abs())
        .fold(0.0, worse);
    eprintln!("constant speed: worst |v̂ − v| {worst:.3e} m/s");
    assert!(worst < 5e-4, "worst {worst}");
    // A 32-bit hardware counter that wraps through i32::MAX gives the same
    // estimate as the 64-bit count.
    let wrapping = run(2000, |n| {
        (i64::from(i32::MAX) - 1000 + counts(n)) as i32 // wraps after ~400 periods
    });
    assert_eq!(v, wrapping);
}

#[test]
fn q16_estimator_matches_the_f32_estimator() {
    let model = Model::<Q16>::new(FIG5).unwrap();
    let units = model.units();
    let scale = model.position_scale::<i32>(1e-6).unwrap();
    let mut fixed =
        VelocityEstimator::<i32, Q16>::with_units(config(3000.0), units, scale).unwrap();
    let mut float = VelocityEstimator::<i32>::new(config(3000.0), 1e-6).unwrap();
    // A reversal: x = A·(1 − cos 2πt), A = 1 mm, as the lab's benchmark.
    let mut worst = 0.0f64;
    for n in 0..2000 {
        let t = n as f64 * PERIOD as f64;
        let x = 1e-3 * (1.0 - (2.0 * std::f64::consts::PI * t).cos());
        let count = (x / 1e-6).floor() as i32;
        let v_fixed = fixed.update(count).unwrap().to_f32() * units.velocity;
        let v_float = float.update(count).unwrap();
        worst = worse(worst, f64::from((v_fixed - v_float).abs()));
    }
    // Q16 resolution of v̂: 2⁻¹⁶·V = 1.5e-8 m/s; of the travel per period
    // 2⁻¹⁶ length units (z_max/256) per ms, 6e-10 m/s. Measured 1.7e-8.
    eprintln!("Q16 vs f32: worst {worst:.2e} m/s");
    assert!(worst < 5e-8, "worst {worst:.2e} m/s");
}

#[test]
fn rejects_bad_settings_and_samples() {
    let bad = |c: VelocityConfig, q: f32| VelocityEstimator::<f32>::new(c, q).unwrap_err();
    for bandwidth in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        assert_eq!(
            bad(config(bandwidth), 1e-6),
            ConfigError(Setting::Bandwidth)
        );
    }
    // ω_e·T so small that l₂ = (1 − p)² underflows: no velocity at all.
    assert_eq!(bad(config(1e-30), 1e-6), ConfigError(Setting::Bandwidth));
    for period in [0.0, -1e-3, f32::NAN] {
        let c = VelocityConfig {
            bandwidth: 300.0,
            period,
        };
        assert_eq!(bad(c, 1e-6), ConfigError(Setting::Period));
    }
    for q in [0.0, -1e-6, f32::NAN, f32::INFINITY] {
        assert_eq!(bad(config(300.0), q), ConfigError(Setting::MetresPerUnit));
    }
    // A huge bandwidth is the plain difference of positions over T.
    let mut diff = VelocityEstimator::<f32>::new(config(1e30), 1.0).unwrap();
    diff.update(0.0).unwrap();
    assert!((diff.update(1e-6).unwrap() - 1e-3).abs() < 1e-9);

    let mut estimator = VelocityEstimator::<f32>::new(config(300.0), 1.0).unwrap();
    for n in 0..10 {
        estimator.update(n as f32 * 1e-6).unwrap();
    }
    let before = estimator.clone();
    for x in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        assert_eq!(estimator.update(x), Err(SampleError::Position));
    }
    assert_eq!(estimator, before);
    // A jump to the far end of f32 keeps the state finite.
    let v = estimator.update(f32::MAX).unwrap();
    assert!(v.is_finite());
    estimator.reset();
    assert_eq!(estimator.update(5.0), Ok(0.0));
}
