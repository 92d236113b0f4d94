//! The compensation blocks (`breakaway::compensation`) against independent
//! sources: the f64 reference model and simulator (`reference/`, written
//! from MODEL.md alone) as the plant and the judge of friction values.

use breakaway::compensation::{
    AdaptationConfig, BreakAwayDetector, ConfigError, DetectorConfig, DisturbanceObserver,
    Feedforward, FeedforwardConfig, LevelAdaptation, ObserverConfig, Setting,
};
use breakaway::{Model, Params, SampleError, Variant};
use breakaway_reference as reference;

mod common;
use common::{reference_model, worse, Plant, FIG5};

/// Fig. 5 with viscous friction σ = 50 N·s/m (σ·V = Fs/30).
const VISCOUS: Params = Params {
    sigma: 50.0,
    ..FIG5
};

/// Sample `n` (1 ms period) of a 0.5 Hz sinusoid of 3·z_max with a 0.4·z_max
/// ripple at 7.3 times the frequency: position [m] and velocity [m/s].
fn ripple(n: i32) -> (f64, f64) {
    let t = n as f64 * 1e-3;
    let w = 2.0 * std::f64::consts::PI * 0.5;
    let x = 3e-5 * (w * t).sin() + 4e-6 * (7.3 * w * t).sin();
    let v = 3e-5 * w * (w * t).cos() + 4e-6 * 7.3 * w * (7.3 * w * t).cos();
    (x, v)
}

#[test]
fn feedforward_follows_the_reference_presliding_model() {
    let p = VISCOUS;
    let model = Model::<f32>::new(p).unwrap();
    let judge_model = reference_model(&p);
    let mut judge = reference::Presliding::new(0.0);
    let mut ff = Feedforward::<f32>::new(FeedforwardConfig::default(), 0.0, 1.0).unwrap();
    let mut worst = 0.0f64;
    for n in 0..4000 {
        let (x, v) = ripple(n);
        let u = ff.update(&model, x as f32, v as f32).unwrap();
        let want = judge.update(&judge_model, x as f32 as f64, v as f32 as f64);
        worst = worse(worst, (u as f64 - want).abs() / p.fs as f64);
    }
    assert!(worst < 1e-5, "feedforward vs reference: {worst:.2e}·Fs");
}

#[test]
fn feedforward_ramps_through_a_reversal() {
    // A sinusoid of amplitude 100·z_max sampled at 1 kHz: at the top
    // reversal the presliding feedforward needs the travel z_max to swing
    // from +S to −S, while sgn(v_ref) steps by 2·Fc in one sample.
    let model = Model::<f32>::new(FIG5).unwrap();
    let mut ff = Feedforward::<f32>::new(FeedforwardConfig::default(), 0.0, 1.0).unwrap();
    let (mut largest_step, mut last) = (0.0f64, None::<f32>);
    let w = 2.0 * core::f32::consts::PI * 0.5;
    for n in 250..1000 {
        let t = n as f32 * 1e-3;
        let u = ff
            .update(
                &model,
                1e-3 * libm::sinf(w * t),
                1e-3 * w * libm::cosf(w * t),
            )
            .unwrap();
        if let Some(l) = last {
            largest_step = worse(largest_step, f64::from((u - l).abs()));
        }
        last = Some(u);
    }
    // Over the reversal at t = 1 s the reference moves 2.5e-9 m in the first
    // ms, 1e-8 m in two: w = 0.25 … the force needs ~6 samples to swing;
    // no step reaches 2·Fc.
    assert!(largest_step < 0.9, "largest step {largest_step} N");
    assert!(ff.force() < -0.99, "sliding back at −Fc: {}", ff.force());
}

#[test]
fn feedforward_options() {
    let model = Model::<f32>::new(FIG5).unwrap();
    let config = FeedforwardConfig {
        gain: 0.8,
        deadband: 1e-3,
        limit: 1.0,
    };
    let mut ff = Feedforward::<f32>::new(config, 0.0, 1.0).unwrap();
    // Deep in sliding at v inside the deadband: S(0) = Fs = 1.5, gain 0.8
    // gives 1.2, the limit cuts to 1.0.
    assert_eq!(ff.update(&model, 1e-3, 5e-4).unwrap(), 1.0);
    // Outside the deadband: 0.8·S(0.01) = 0.8·(1 + 0.5·e^−10).
    let u = ff.update(&model, 2e-3, 1e-2).unwrap();
    let want = 0.8 * (1.0 + 0.5 * (-10.0f64).exp());
    assert!((u as f64 - want).abs() < 1e-6, "{u} vs {want}");
    // The level scale multiplies the dry part.
    ff.set_level_scale(1.1);
    ff.set_level_scale(f32::NAN); // ignored
    let u = ff.update(&model, 3e-3, 1e-2).unwrap();
    assert!((u as f64 - 1.1 * want).abs() < 1e-6);
    // A rejected sample changes nothing.
    let before = ff.clone();
    assert_eq!(ff.update(&model, f32::NAN, 0.0), Err(SampleError::Position));
    assert_eq!(
        ff.update(&model, 0.0, f32::INFINITY),
        Err(SampleError::Velocity)
    );
    assert_eq!(ff, before);
    // Settings are validated and named.
    for (config, setting) in [
        (
            FeedforwardConfig {
                gain: -1.0,
                ..config
            },
            Setting::Gain,
        ),
        (
            FeedforwardConfig {
                deadband: f32::NAN,
                ..config
            },
            Setting::Deadband,
        ),
        (
            FeedforwardConfig {
                limit: 0.0,
                ..config
            },
            Setting::Limit,
        ),
    ] {
        assert_eq!(
            Feedforward::<f32>::new(config, 0.0, 1.0).unwrap_err(),
            ConfigError(setting)
        );
    }
    assert_eq!(
        Feedforward::<i64>::new(config, 0, -1.0).unwrap_err(),
        ConfigError(Setting::MetresPerUnit)
    );
}

/// A velocity PI loop on the reference plant; returns the plant and the
/// blocks after `seconds`.
fn sliding_run(
    level: f64,
    v_ref: f64,
    seconds: f64,
    explain: bool,
) -> (Plant, DisturbanceObserver, LevelAdaptation, f64) {
    const T: f32 = 1e-3;
    let model = Model::<f32>::new(FIG5).unwrap();
    let mut plant = Plant::new(reference::Model {
        fc: FIG5.fc as f64 * level,
        fs: FIG5.fs as f64 * level,
        ..reference_model(&FIG5)
    });
    let mut ff = Feedforward::<f32>::new(FeedforwardConfig::default(), 0.0, 1.0).unwrap();
    let mut observer = DisturbanceObserver::new(ObserverConfig {
        mass: 1.0,
        bandwidth: 100.0,
        period: T,
    })
    .unwrap();
    let mut adaptation = LevelAdaptation::new(AdaptationConfig {
        rate: 2.0,
        min_scale: 0.5,
        max_scale: 2.0,
        min_speed: 2e-3,
        period: T,
    })
    .unwrap();
    let (mut integral, mut u, mut u_ff) = (0.0f64, 0.0f64, 0.0f32);
    let mut worst_residual = 0.0f64;
    let steps = (seconds / T as f64) as usize;
    for n in 0..steps {
        let t = n as f64 * T as f64;
        // Measure, estimate with the command of the period just ended.
        let explained = if explain { u_ff } else { 0.0 };
        let r = observer
            .update(u as f32, plant.v as f32, explained)
            .unwrap();
        if explain {
            let theta = adaptation
                .update(r, ff.dry(), v_ref as f32, ff.is_sliding())
                .unwrap();
            ff.set_level_scale(theta);
        }
        u_ff = ff.update(&model, (v_ref * t) as f32, v_ref as f32).unwrap();
        if t > seconds - 0.5 {
            worst_residual = worse(worst_residual, f64::from(r.abs()));
        }
        let e = v_ref - plant.v;
        integral += e * T as f64;
        let feedforward = if explain { u_ff as f64 } else { 0.0 };
        u = 300.0 * e + 3000.0 * integral + feedforward;
        plant.step(u, T as f64);
    }
    (plant, observer, adaptation, worst_residual)
}

#[test]
fn observer_estimates_the_friction_of_the_reference_plant() {
    // Plain observer (nothing explained) while sliding at 20 mm/s: the
    // estimate is the plant's friction, S(0.02) of the reference curves.
    let (plant, observer, _, _) = sliding_run(1.0, 0.02, 1.0, false);
    let want = reference::stribeck(&plant.model, 0.02);
    let got = observer.estimate() as f64;
    assert!((got - want).abs() < 5e-3 * want, "{got} vs {want}");
    assert!((plant.mean_friction - want).abs() < 1e-3);
}

#[test]
fn adaptation_recovers_a_level_drift() {
    // The plant's Fc and Fs are 20 % above the compensator's: θ → 1.2 and
    // the residual the observer sees vanishes.
    let (_, _, adaptation, residual) = sliding_run(1.2, 0.02, 4.0, true);
    let theta = adaptation.scale();
    assert!((theta - 1.2).abs() < 0.01, "θ = {theta}");
    assert!(residual < 0.02, "residual {residual} N");
}

#[test]
fn adaptation_is_frozen_bounded_and_rejects_bad_samples() {
    let config = AdaptationConfig {
        rate: 10.0,
        min_scale: 0.5,
        max_scale: 1.5,
        min_speed: 1e-3,
        period: 1e-3,
    };
    let mut a = LevelAdaptation::new(config).unwrap();
    // In presliding, or too slow: frozen.
    assert_eq!(a.update(0.5, 1.0, 0.1, false).unwrap(), 1.0);
    assert_eq!(a.update(0.5, 1.0, 1e-4, true).unwrap(), 1.0);
    // Sliding: normalised gradient step γ·T·r/H.
    assert!((a.update(0.5, -1.0, -0.1, true).unwrap() - 0.995).abs() < 1e-6);
    // Bounded.
    for _ in 0..1000 {
        a.update(100.0, 1.0, 0.1, true).unwrap();
    }
    assert_eq!(a.scale(), 1.5);
    assert_eq!(a.update(f32::NAN, 1.0, 0.1, true), Err(SampleError::Force));
    assert_eq!(
        a.update(1.0, 1.0, f32::NAN, true),
        Err(SampleError::Velocity)
    );
    assert_eq!(a.scale(), 1.5);
    for (c, s) in [
        (
            AdaptationConfig {
                rate: 2000.0,
                ..config
            },
            Setting::Rate,
        ),
        (
            AdaptationConfig {
                min_scale: 1.1,
                ..config
            },
            Setting::MinScale,
        ),
        (
            AdaptationConfig {
                max_scale: 0.9,
                ..config
            },
            Setting::MaxScale,
        ),
        (
            AdaptationConfig {
                min_speed: -1.0,
                ..config
            },
            Setting::MinSpeed,
        ),
        (
            AdaptationConfig {
                period: 0.0,
                ..config
            },
            Setting::Period,
        ),
        (
            // γ·T underflows to 0 (a fuzz finding: 0·∞ gave θ = NaN).
            AdaptationConfig {
                rate: 1e-30,
                period: 1e-30,
                ..config
            },
            Setting::Rate,
        ),
    ] {
        assert_eq!(LevelAdaptation::new(c).unwrap_err(), ConfigError(s));
    }
}

#[test]
fn observer_rejects_bad_samples_and_settings() {
    let config = ObserverConfig {
        mass: 1.0,
        bandwidth: 100.0,
        period: 1e-3,
    };
    let mut o = DisturbanceObserver::new(config).unwrap();
    o.update(1.0, 0.0, 0.0).unwrap();
    o.update(1.0, 0.0, 0.0).unwrap();
    let before = o.clone();
    assert_eq!(o.update(f32::NAN, 0.0, 0.0), Err(SampleError::Command));
    assert_eq!(
        o.update(0.0, f32::INFINITY, 0.0),
        Err(SampleError::Velocity)
    );
    assert_eq!(o.update(0.0, 0.0, f32::NAN), Err(SampleError::Force));
    assert_eq!(o, before);
    // A constant force with the axis held still is all disturbance: the
    // estimate rises as 1 − e^(−g·t).
    for _ in 0..8 {
        o.update(1.0, 0.0, 0.0).unwrap();
    }
    let want = 1.0 - (-100.0f64 * 1e-3 * 9.0).exp(); // 9 filter steps
    assert!((o.estimate() as f64 - want).abs() < 1e-6);
    for (c, s) in [
        (
            ObserverConfig {
                mass: 0.0,
                ..config
            },
            Setting::Mass,
        ),
        (
            ObserverConfig {
                bandwidth: f32::NAN,
                ..config
            },
            Setting::Bandwidth,
        ),
        (
            ObserverConfig {
                period: -1.0,
                ..config
            },
            Setting::Period,
        ),
    ] {
        assert_eq!(DisturbanceObserver::new(c).unwrap_err(), ConfigError(s));
    }
}

#[test]
fn detector_measures_the_break_away_of_the_reference_dynamics() {
    let model = Model::<f32>::new(FIG5).unwrap();
    let judge = reference_model(&FIG5);
    const T: f64 = 1e-4;
    let config = DetectorConfig {
        period: T as f32,
        rest_speed: 1e-5,
        break_away_speed: 2e-3,
        min_rate: 0.1,
    };
    let mut detector =
        BreakAwayDetector::<2>::new(config, &model, Variant::Consistent, 0.95).unwrap();
    let rates = [2.0, 5.0, 10.0];
    let mut worst = 0.0f64;
    for k in rates {
        let want = reference::simulate_break_away(&judge, k, 0.95).unwrap();
        let samples =
            reference::simulate(&judge, &|t| k * t, 0.0, 0.0, want.t_ba + 0.05, T).unwrap();
        // At rest before the ramp, then the ramp (the last ramp's rest
        // samples re-arm the detector).
        for _ in 0..10 {
            detector.update(&model, 0.0, 0.0).unwrap();
        }
        let mut found = None;
        for s in &samples {
            if let Some(m) = detector.update(&model, s.u as f32, s.v as f32).unwrap() {
                found = Some(m);
                break;
            }
        }
        let m = found.expect("break-away detected");
        assert!((m.rate as f64 - k).abs() < 1e-3 * k, "k {} vs {k}", m.rate);
        let error = (m.force as f64 - want.f_ba).abs() / want.f_ba;
        worst = worse(worst, error);
        println!(
            "k = {k}: detected F_ba {} N, reference dynamics {} N",
            m.force, want.f_ba
        );
        // Late by the time the velocity takes from break-away (w = w_b) to
        // 2 mm/s: a few ms of ramp, k·Δt ≈ 0.03 N at k = 10 N/s.
        assert!(error < 0.03, "k = {k}: F_ba {} vs {}", m.force, want.f_ba);
        assert!(m.predicted.is_some());
    }
    println!("detector vs reference dynamics: worst F_ba error {worst:.2e}");
    // Capacity 2: the oldest (k = 2) was dropped.
    let kept: Vec<f32> = detector.pairs().map(|(k, _)| k).collect();
    assert_eq!(kept.len(), 2);
    assert!((kept[0] - 5.0).abs() < 0.01 && (kept[1] - 10.0).abs() < 0.01);
    let before = detector.clone();
    assert_eq!(
        detector.update(&model, f32::NAN, 0.0),
        Err(SampleError::Command)
    );
    assert_eq!(detector, before);
}

/// The reference dynamics under a ramp u = k·t from rest: the samples
/// (u [N], v [m/s]) every `period` [s] up to 50 ms past break-away, after
/// 10 samples at rest.
fn break_away_samples(judge: &reference::Model, k: f64, period: f64) -> Vec<(f32, f32)> {
    let want = reference::simulate_break_away(judge, k, 0.95).unwrap();
    let samples =
        reference::simulate(judge, &|t| k * t, 0.0, 0.0, want.t_ba + 0.05, period).unwrap();
    std::iter::repeat_n((0.0, 0.0), 10)
        .chain(samples.iter().map(|s| (s.u as f32, s.v as f32)))
        .collect()
}

/// The first break-away of a detector fed `samples` (u [N], v [m/s]),
/// converted to model units by `force` and `velocity`.
fn first_break_away<T, C, const N: usize>(
    detector: &mut BreakAwayDetector<N, T>,
    model: &Model<T, C>,
    samples: &[(f32, f32)],
    convert: impl Fn(f32, f32) -> (T, T),
) -> Option<breakaway::compensation::Measurement<T>>
where
    T: breakaway::compensation::Accumulate,
    C: breakaway::Curves<T>,
{
    samples.iter().find_map(|&(u, v)| {
        let (u, v) = convert(u, v);
        detector.update(model, u, v).unwrap()
    })
}

/// The differences of a Q16.16 measurement `b` (force in Fs) from the
/// `f32` one `a` of a ramp of `k` [N/s], asserted within the fixed-point
/// resolution: (k relative, F_ba [N], t [s], predicted F_ba relative) and
/// the bound on k relative.
///
/// Bounds from the resolution 2⁻¹⁶ (Fs, s): the command is rounded to
/// 2⁻¹⁷·Fs, which moves F_ba by as much and the least-squares k by at most
/// 3·2⁻¹⁷·Fs/t; k and t are rounded once more to 2⁻¹⁷; the `f32` sums carry
/// ~1e-5 relative on k. The predictor in Q16 is within 1e-3 of F_ba
/// (`tests/fixed_point.rs`).
fn assert_q16_matches_f32(
    a: &breakaway::compensation::Measurement<f32>,
    b: &breakaway::compensation::Measurement<breakaway::Q16>,
    k: f64,
) -> [f64; 5] {
    const LSB: f64 = 1.0 / 65536.0;
    let fs = FIG5.fs as f64;
    let (rate, force, time) = (
        b.rate.to_f32() as f64 * fs,
        b.force.to_f32() as f64 * fs,
        b.time.to_f32() as f64,
    );
    let t = a.time as f64;
    let k_bound = (3.0 * LSB / 2.0 / t + LSB) * fs + 1e-5 * k;
    let (dk, df, dt) = (
        (rate - a.rate as f64).abs(),
        (force - a.force as f64).abs(),
        (time - t).abs(),
    );
    assert!(dk <= k_bound, "k = {k}: Q16 {rate} vs f32 {} N/s", a.rate);
    assert!(df <= LSB * fs, "k = {k}: Q16 {force} vs f32 {} N", a.force);
    assert!(dt <= LSB, "k = {k}: Q16 {time} vs f32 {t} s");
    let (p, q) = (a.predicted.unwrap(), b.predicted.unwrap());
    let dp = (q.f_ba.to_f32() as f64 * fs - p.f_ba as f64).abs() / p.f_ba as f64;
    assert!(dp < 1e-3, "k = {k}: predicted F_ba {dp:.1e} relative");
    [dk / k, df, dt, dp, k_bound / k]
}

/// The Q16.16 detector (force in Fs, velocity in V) and the `f32` one fed
/// the same reference break-aways, at 10 kHz and at 1 kHz with rises of up
/// to 7.3 s (7 300 samples at 1 kHz, 29 000 at 10 kHz): the same k, F_ba and
/// t within the fixed-point resolution, and the same predicted F_ba
/// ([`assert_q16_matches_f32`]).
#[test]
fn fixed_detector_matches_the_f32_detector_on_the_reference_dynamics() {
    use breakaway::Q16;
    let float_model = Model::<f32>::new(FIG5).unwrap();
    let fixed_model = Model::<Q16>::new(FIG5).unwrap();
    let judge = reference_model(&FIG5);
    let (mut worst_k, mut worst_f, mut worst_t, mut worst_p) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    // min_rate at least two Q16 command steps per sample, 2⁻¹⁵·Fs/T
    // (0.46 N/s at 10 kHz).
    for (period, min_rate, rates) in [
        (1e-4, 0.46, &[0.5, 2.0, 5.0, 10.0][..]),
        (1e-3, 0.1, &[0.2, 0.5, 2.0, 10.0][..]),
    ] {
        let config = DetectorConfig {
            period: period as f32,
            rest_speed: 1e-5,
            break_away_speed: 2e-3,
            min_rate,
        };
        let mut float =
            BreakAwayDetector::<2>::new(config, &float_model, Variant::Consistent, 0.95).unwrap();
        let mut fixed =
            BreakAwayDetector::<2, Q16>::new(config, &fixed_model, Variant::Consistent, 0.95)
                .unwrap();
        for &k in rates {
            let samples = break_away_samples(&judge, k, period);
            let a = first_break_away(&mut float, &float_model, &samples, |u, v| (u, v)).unwrap();
            let b = first_break_away(&mut fixed, &fixed_model, &samples, |u, v| {
                (
                    Q16::from_f32(u / FIG5.fs).unwrap(),
                    fixed_model.velocity(v).unwrap(),
                )
            })
            .expect("Q16 break-away detected");
            let [dk, df, dt, dp, k_bound] = assert_q16_matches_f32(&a, &b, k);
            println!(
                "T = {period} s, k = {k} N/s, {:.0} samples: Q16 − f32: k {dk:.1e} (bound \
                 {k_bound:.1e}), F_ba {df:.1e} N, t {dt:.1e} s, predicted F_ba {dp:.1e} relative",
                a.time as f64 / period,
            );
            worst_k = worse(worst_k, dk);
            worst_f = worse(worst_f, df / a.force as f64);
            worst_t = worse(worst_t, dt);
            worst_p = worse(worst_p, dp);
        }
    }
    println!(
        "Q16 vs f32 detector: worst k {worst_k:.1e}, F_ba {worst_f:.1e} relative, \
         t {worst_t:.1e} s, predicted F_ba {worst_p:.1e} relative"
    );
}

/// Beyond the admitted Q16 rise (52 000 samples) the sums would not fit:
/// the Q16 detector gives no measurement where the `f32` one measures, and
/// re-arms for the next rise. Non-finite samples are rejected without a
/// change of state.
#[test]
fn detector_range_and_rejected_samples() {
    use breakaway::Q16;
    const T: f32 = 1e-4;
    let float_model = Model::<f32>::new(FIG5).unwrap();
    let fixed_model = Model::<Q16>::new(FIG5).unwrap();
    let config = DetectorConfig {
        period: T,
        rest_speed: 1e-5,
        break_away_speed: 2e-3,
        min_rate: 0.5, // ≥ 2⁻¹⁵·Fs/T = 0.46 N/s
    };
    // A ramp of k [N/s] over n samples at rest, one sample moving at
    // 4 mm/s, one at rest (re-arms).
    let ramp = |k: f32, n: usize| -> Vec<(f32, f32)> {
        (0..n)
            .map(|i| (k * i as f32 * T, 0.0))
            .chain([(k * n as f32 * T, 4e-3), (0.0, 0.0)])
            .collect()
    };
    let to_fixed = |u: f32, v: f32| {
        (
            Q16::from_f32(u / FIG5.fs).unwrap(),
            fixed_model.velocity(v).unwrap(),
        )
    };
    let mut float =
        BreakAwayDetector::<4>::new(config, &float_model, Variant::Consistent, 0.95).unwrap();
    let mut fixed =
        BreakAwayDetector::<4, Q16>::new(config, &fixed_model, Variant::Consistent, 0.95).unwrap();
    // 60 000 samples (6 s at 10 kHz) to 6 N = 4·Fs.
    let long = ramp(1.0, 60_000);
    let m = first_break_away(&mut float, &float_model, &long, |u, v| (u, v)).unwrap();
    assert!((m.rate - 1.0).abs() < 1e-4, "k {}", m.rate);
    assert!(first_break_away(&mut fixed, &fixed_model, &long, to_fixed).is_none());
    assert!(fixed.is_empty());
    // 50 000 samples: within the range.
    let short = ramp(1.0, 50_000);
    let m = first_break_away(&mut fixed, &fixed_model, &short, to_fixed).unwrap();
    assert!(
        (m.rate.to_f32() * FIG5.fs - 1.0).abs() < 1e-4,
        "k {:?}",
        m.rate
    );
    assert!(
        (m.time.to_f32() - 49_999.0 * T).abs() < 2e-5,
        "t {:?}",
        m.time
    );

    // f32 sums round: past 10⁵ samples (10 s at 10 kHz) a rise gives no
    // measurement (k was 9.7e-4 off at 10⁶), while 10⁵ is still measured.
    let slow = 1.0; // N/s, above min_rate: 10 N after 10⁵ samples
    let too_long = ramp(slow, 100_010);
    assert!(first_break_away(&mut float, &float_model, &too_long, |u, v| (u, v)).is_none());
    let m = first_break_away(&mut float, &float_model, &ramp(slow, 99_999), |u, v| (u, v)).unwrap();
    assert!((m.rate / slow - 1.0).abs() < 2e-4, "k {} vs {slow}", m.rate);

    // Non-finite samples in the middle of a rise: rejected, state unchanged,
    // the measurement the same as without them.
    let mut clean = float.clone();
    let want = first_break_away(&mut clean, &float_model, &ramp(2.0, 3000), |u, v| (u, v));
    let mut got = None;
    for (i, &(u, v)) in ramp(2.0, 3000).iter().enumerate() {
        if i % 100 == 50 {
            let before = float.clone();
            assert_eq!(
                float.update(&float_model, f32::NAN, v),
                Err(SampleError::Command)
            );
            assert_eq!(
                float.update(&float_model, u, f32::INFINITY),
                Err(SampleError::Velocity)
            );
            assert_eq!(float, before);
        }
        if let Some(m) = float.update(&float_model, u, v).unwrap() {
            got = Some(m);
            break;
        }
    }
    assert!(want.is_some());
    assert_eq!(got, want);
}

/// Q16 admits rises of at least two command steps (2⁻¹⁶·Fs) per sample: a
/// min_rate below 2⁻¹⁵·Fs/T is a setting error, and a slower ramp gives no
/// measurement where it came out at one step per sample before (0.2 N/s at
/// 10 kHz, 0.87 steps: 15 % too high; a command rounded twice at 1.2
/// steps: 25 % too high). A ramp just inside, 2.05 steps per sample,
/// matches the `f32` detector within the fixed-point resolution
/// ([`assert_q16_matches_f32`]), the command rounded once or twice.
#[test]
fn fixed_detector_admits_two_command_steps_per_sample() {
    use breakaway::Q16;
    let fs = FIG5.fs as f64;
    let step = fs / 65536.0; // N
    let float_model = Model::<f32>::new(FIG5).unwrap();
    let fixed_model = Model::<Q16>::new(FIG5).unwrap();
    let judge = reference_model(&FIG5);
    let velocity = |v: f32| fixed_model.velocity(v).unwrap();
    // The command in Fs, rounded once (from the f32 command in N), or twice:
    // first to 2⁻¹⁶ N, as a controller computing in Q16 newtons would.
    let once = |u: f32, v: f32| (Q16::from_f32(u / FIG5.fs).unwrap(), velocity(v));
    let twice = |u: f32, v: f32| {
        let newtons = (u as f64 * 65536.0).round() / 65536.0;
        (Q16::from_f32((newtons / fs) as f32).unwrap(), velocity(v))
    };
    type Convert<'a> = &'a dyn Fn(f32, f32) -> (Q16, Q16);
    let roundings: [(&str, Convert); 2] = [("once", &once), ("twice", &twice)];
    for period in [1e-4, 1e-3] {
        let bound = 2.0 * step / period; // N/s
        let config = |min_rate: f64| DetectorConfig {
            period: period as f32,
            rest_speed: 1e-5,
            break_away_speed: 2e-3,
            min_rate: min_rate as f32,
        };
        let fixed = |min_rate| {
            BreakAwayDetector::<1, Q16>::new(
                config(min_rate),
                &fixed_model,
                Variant::Consistent,
                0.95,
            )
        };
        let float = |min_rate| {
            BreakAwayDetector::<1>::new(config(min_rate), &float_model, Variant::Consistent, 0.95)
                .unwrap()
        };
        // The bound, to its rounding; none for f32.
        assert_eq!(
            fixed(0.99 * bound).unwrap_err(),
            ConfigError(Setting::MinRate)
        );
        // 0.2 N/s is below it at 10 kHz (0.46 N/s), above it at 1 kHz
        // (0.046 N/s).
        assert_eq!(fixed(0.2).is_ok(), period > 1e-4, "T = {period} s");
        if period <= 1e-4 {
            assert_eq!(fixed(0.2).unwrap_err(), ConfigError(Setting::MinRate));
        }
        let admitted = 1.01 * bound;
        assert!(fixed(admitted).is_ok());
        // Below: the f32 detector measures the ramp, the Q16 one at the
        // smallest admitted min_rate gives no measurement.
        for (x, (name, convert)) in [(0.87, roundings[0]), (1.2, roundings[1])] {
            let k = x * step / period;
            let samples = break_away_samples(&judge, k, period);
            let mut float = float(0.1 * k);
            let a = first_break_away(&mut float, &float_model, &samples, |u, v| (u, v)).unwrap();
            assert!(
                (a.rate as f64 / k - 1.0).abs() < 1e-4,
                "f32 k {} vs {k}",
                a.rate
            );
            let mut fixed = fixed(admitted).unwrap();
            let b = first_break_away(&mut fixed, &fixed_model, &samples, convert);
            assert_eq!(
                b, None,
                "T = {period} s, {x} steps per sample, rounded {name}"
            );
            assert!(fixed.is_empty());
            println!(
                "T = {period} s, k = {k:.4} N/s ({x} steps, rounded {name}): no Q16 measurement"
            );
        }
        // Just inside: 2.05 steps per sample.
        let k = 2.05 * step / period;
        let samples = break_away_samples(&judge, k, period);
        let a =
            first_break_away(&mut float(admitted), &float_model, &samples, |u, v| (u, v)).unwrap();
        for (name, convert) in roundings {
            let mut fixed = fixed(admitted).unwrap();
            let b = first_break_away(&mut fixed, &fixed_model, &samples, convert)
                .expect("Q16 break-away detected");
            let [dk, df, dt, dp, k_bound] = assert_q16_matches_f32(&a, &b, k);
            println!(
                "T = {period} s, k = {k:.4} N/s (2.05 steps, rounded {name}), {:.0} samples: \
                 Q16 − f32: k {dk:.1e} (bound {k_bound:.1e}), F_ba {df:.1e} N, t {dt:.1e} s, \
                 predicted F_ba {dp:.1e} relative",
                a.time as f64 / period,
            );
        }
    }
}

/// Settings that Q16 cannot hold: a sample rate of 32 768 Hz or more, or a
/// rest speed and break-away speed that round together.
#[test]
fn fixed_detector_settings() {
    use breakaway::Q16;
    let float_model = Model::<f32>::new(FIG5).unwrap();
    let fixed_model = Model::<Q16>::new(FIG5).unwrap();
    let config = DetectorConfig {
        period: 1e-3,
        rest_speed: 1e-5,
        break_away_speed: 2e-3,
        min_rate: 0.1,
    };
    let fast = DetectorConfig {
        period: 1e-5,
        ..config
    };
    let detector = |c| BreakAwayDetector::<1, Q16>::new(c, &fixed_model, Variant::Mean, 0.95);
    assert!(BreakAwayDetector::<1>::new(fast, &float_model, Variant::Mean, 0.95).is_ok());
    assert_eq!(detector(fast).unwrap_err(), ConfigError(Setting::Period));
    // 1 mm/s = 1·V: both far beyond 32768·V.
    let beyond = DetectorConfig {
        rest_speed: 100.0,
        break_away_speed: 200.0,
        ..config
    };
    assert_eq!(
        detector(beyond).unwrap_err(),
        ConfigError(Setting::BreakAwaySpeed)
    );
    // Sub-resolution speeds round to 0 (1.5e-5·V = 1.5e-8 m/s).
    let tiny = DetectorConfig {
        rest_speed: 1e-9,
        ..config
    };
    assert_eq!(detector(tiny).unwrap_err(), ConfigError(Setting::RestSpeed));
    assert!(detector(config).is_ok());
}

/// The same feedforward in Q16.16 (forces in Fs, velocities in V, 10 nm
/// counts) against the f64 reference presliding model: one algorithm in
/// both number types, within the fixed-point bound 1e-3·Fs.
#[test]
fn fixed_feedforward_follows_the_reference_presliding_model() {
    use breakaway::Q16;
    let p = VISCOUS;
    let model = Model::<Q16>::new(p).unwrap();
    let scale = model.position_scale::<i32>(1e-8).unwrap();
    let judge_model = reference_model(&p);
    let mut judge = reference::Presliding::new(0.0);
    let config = FeedforwardConfig {
        gain: 1.0,
        deadband: 1e-6,
        limit: 100.0,
    };
    let mut ff = Feedforward::<i32, Q16>::with_units(config, model.units(), 0, scale).unwrap();
    let mut worst = 0.0f64;
    for n in 0..4000 {
        let (x, v) = ripple(n);
        let count = (x / 1e-8).round() as i32;
        let v_q = model.velocity(v as f32).unwrap();
        let u = ff.update(&model, count, v_q).unwrap().to_f32() as f64 * p.fs as f64;
        // The reference sees what the fixed-point model received.
        let v_seen = v_q.to_f32() as f64 * p.v_stribeck as f64;
        let v_seen = if v_seen.abs() <= 1e-6 { 0.0 } else { v_seen };
        let want = judge.update(&judge_model, count as f64 * 1e-8, v_seen);
        worst = worse(worst, (u - want).abs() / p.fs as f64);
    }
    assert!(worst < 1e-3, "Q16 feedforward vs reference: {worst:.2e}·Fs");
}

/// The Q16.16 observer on the reference plant, fed the same samples as the
/// `f32` one: the same estimate of the plant's friction within 1e-3·Fs.
#[test]
fn fixed_observer_matches_the_f32_observer_on_the_reference_plant() {
    use breakaway::{Scalar, Q16};
    const T: f32 = 1e-3;
    let model = Model::<Q16>::new(FIG5).unwrap();
    let config = ObserverConfig {
        mass: 1.0,
        bandwidth: 100.0,
        period: T,
    };
    let mut float = DisturbanceObserver::new(config).unwrap();
    let mut fixed = DisturbanceObserver::<Q16>::with_units(config, model.units()).unwrap();
    let mut plant = Plant::new(reference_model(&FIG5));
    let (v_ref, mut integral, mut u) = (0.02f64, 0.0f64, 0.0f64);
    let mut worst = 0.0f64;
    for _ in 0..1000 {
        let r = float.update(u as f32, plant.v as f32, 0.0).unwrap();
        let q = fixed
            .update(
                Q16::from_f32(u as f32 / FIG5.fs).unwrap(),
                model.velocity(plant.v as f32).unwrap(),
                Q16::ZERO,
            )
            .unwrap();
        worst = worse(
            worst,
            (q.to_f32() * FIG5.fs - r).abs() as f64 / FIG5.fs as f64,
        );
        let e = v_ref - plant.v;
        integral += e * T as f64;
        u = 300.0 * e + 3000.0 * integral;
        plant.step(u, T as f64);
    }
    let want = reference::stribeck(&plant.model, v_ref);
    let got = fixed.estimate().to_f32() as f64 * FIG5.fs as f64;
    assert!((got - want).abs() < 5e-3 * want, "{got} vs {want}");
    assert!(worst < 1e-3, "Q16 vs f32 observer: {worst:.2e}·Fs");
}

/// The split feedforward is linear in Fc and Fs − Fc, turning points
/// included: with (θ_c, θ_s) it is the reference presliding model at
/// Fc' = θ_c·Fc, Fs' = θ_c·Fc + θ_s·(Fs − Fc), and its Coulomb part H_c is
/// the reference model with Fs = Fc.
#[test]
fn split_feedforward_is_the_reference_model_at_the_scaled_levels() {
    let model = Model::<f32>::new(FIG5).unwrap();
    let (theta_c, theta_s) = (1.2f32, 0.6f32);
    let scaled = Params {
        fc: theta_c * FIG5.fc,
        fs: theta_c * FIG5.fc + theta_s * (FIG5.fs - FIG5.fc),
        ..FIG5
    };
    let judge_model = reference_model(&scaled);
    let coulomb_model = reference_model(&Params {
        fs: FIG5.fc,
        ..FIG5
    });
    let mut judge = reference::Presliding::new(0.0);
    let mut coulomb_judge = reference::Presliding::new(0.0);
    let mut ff = Feedforward::<f32>::new(FeedforwardConfig::default(), 0.0, 1.0)
        .unwrap()
        .with_split_levels();
    ff.set_level_scales(theta_c, theta_s);
    let mut plain = Feedforward::<f32>::new(FeedforwardConfig::default(), 0.0, 1.0).unwrap();
    plain.set_level_scale(1.1);
    let mut even = Feedforward::<f32>::new(FeedforwardConfig::default(), 0.0, 1.0)
        .unwrap()
        .with_split_levels();
    even.set_level_scales(1.1, 1.1);
    let (mut worst, mut worst_coulomb, mut worst_even) = (0.0f64, 0.0f64, 0.0f64);
    for n in 0..4000 {
        let t = n as f64 * 1e-3;
        let w = 2.0 * std::f64::consts::PI * 0.5;
        let x = 3e-5 * (w * t).sin() + 4e-6 * (7.3 * w * t).sin();
        let v = 3e-5 * w * (w * t).cos() + 4e-6 * 7.3 * w * (7.3 * w * t).cos();
        let (xf, vf) = (x as f32, v as f32);
        let u = ff.update(&model, xf, vf).unwrap();
        let want = judge.update(&judge_model, xf as f64, vf as f64);
        worst = worse(worst, (u as f64 - want).abs() / FIG5.fs as f64);
        let want_c = coulomb_judge.update(&coulomb_model, xf as f64, vf as f64);
        worst_coulomb = worse(worst_coulomb, (ff.coulomb_dry() as f64 - want_c).abs());
        // θ_c = θ_s = θ is the single scale θ.
        let a = plain.update(&model, xf, vf).unwrap();
        let b = even.update(&model, xf, vf).unwrap();
        worst_even = worse(worst_even, f64::from((a - b).abs()));
    }
    assert!(
        worst < 1e-5,
        "split feedforward vs reference: {worst:.2e}·Fs"
    );
    assert!(
        worst_coulomb < 1e-5,
        "H_c vs reference: {worst_coulomb:.2e} N"
    );
    assert!(worst_even < 1e-6, "split (θ, θ) vs θ: {worst_even:.2e} N");
    assert_eq!(plain.stiction_dry(), 0.0);
}

/// A position loop as the lab's closed-loop benchmark (PID at (s + 125)³,
/// T = 1 ms, x_ref = A·(1 − cos 2πft), A = 1 mm, f = 1 Hz), ideal
/// measurement, on the reference plant at the levels (fc, fs) with the
/// compensator's V, δ and z_max: the split feedforward, the observer and the
/// stiction adaptation, with a shadow Q16 adaptation fed the same samples.
/// Returns (θ_c, θ_s) of f32 and Q16 and the largest difference between
/// them over the run.
fn stiction_run(fc: f64, fs: f64, seconds: f64) -> ([f32; 2], [f32; 2], f64) {
    stiction_drift_run(fc, fs, None, seconds)
}

/// [`stiction_run`] whose plant levels step to `drift` = (Fc, Fs) at t = 2 s.
fn stiction_drift_run(
    fc: f64,
    fs: f64,
    drift: Option<(f64, f64)>,
    seconds: f64,
) -> ([f32; 2], [f32; 2], f64) {
    use breakaway::compensation::{StictionAdaptation, StictionConfig};
    use breakaway::Q16;
    const T: f64 = 1e-3;
    let model = Model::<f32>::new(FIG5).unwrap();
    let fixed_model = Model::<Q16>::new(FIG5).unwrap();
    let mut judge = reference_model(&FIG5);
    (judge.fc, judge.fs) = (fc, fs);
    let mut plant = Plant::new(judge);
    let mut ff = Feedforward::<f32>::new(FeedforwardConfig::default(), 0.0, 1.0)
        .unwrap()
        .with_split_levels();
    let scale = fixed_model.position_scale::<i32>(1e-8).unwrap();
    let units = fixed_model.units();
    let mut fixed_ff =
        Feedforward::<i32, Q16>::with_units(FeedforwardConfig::default(), units, 0, scale)
            .unwrap()
            .with_split_levels();
    let mut observer = DisturbanceObserver::new(ObserverConfig {
        mass: 1.0,
        bandwidth: 100.0,
        period: T as f32,
    })
    .unwrap();
    let config = StictionConfig {
        rate: 1.0,
        reversal_gain: 0.3,
        bandwidth: 100.0,
        min_scale: 0.5,
        max_scale: 2.0,
        max_stiction_scale: 3.0,
        min_speed: FIG5.v_stribeck,
        period: T as f32,
    };
    let mut adaptation = StictionAdaptation::new(config).unwrap();
    let mut fixed = StictionAdaptation::<Q16>::with_units(config, units).unwrap();
    let omega = 125.0;
    let (kp, ki, kd) = (3.0 * omega * omega, omega * omega * omega, 3.0 * omega);
    let (mut integral, mut u, mut u_ff) = (0.0f64, 0.0f64, 0.0f32);
    let mut worst = 0.0f64;
    let w = 2.0 * std::f64::consts::PI;
    for n in 0..(seconds / T) as usize {
        let t = n as f64 * T;
        if let (Some((fc, fs)), 2000) = (drift, n) {
            (plant.model.fc, plant.model.fs) = (fc, fs);
        }
        let (x_ref, v_ref, a_ref) = (
            1e-3 * (1.0 - (w * t).cos()),
            1e-3 * w * (w * t).sin(),
            1e-3 * w * w * (w * t).cos(),
        );
        let r = observer.update(u as f32, plant.v as f32, u_ff).unwrap();
        let (c, s) = adaptation.update(r, &ff, v_ref as f32).unwrap();
        ff.set_level_scales(c, s);
        let v_q = fixed_model.velocity(v_ref as f32).unwrap();
        let r_q = Q16::from_f32(r / units.force).unwrap();
        let (cq, sq) = fixed.update(r_q, &fixed_ff, v_q).unwrap();
        fixed_ff.set_level_scales(cq, sq);
        worst = worse(
            worse(worst, f64::from((cq.to_f32() - c).abs())),
            f64::from((sq.to_f32() - s).abs()),
        );
        u_ff = ff.update(&model, x_ref as f32, v_ref as f32).unwrap();
        fixed_ff
            .update(&fixed_model, (x_ref / 1e-8).round() as i32, v_q)
            .unwrap();
        let e = x_ref - plant.x;
        integral += e * T;
        u = kp * e + ki * integral + kd * (v_ref - plant.v) + a_ref + u_ff as f64 + r as f64;
        plant.step(u, T);
    }
    (
        [adaptation.coulomb_scale(), adaptation.stiction_scale()],
        [
            fixed.coulomb_scale().to_f32(),
            fixed.stiction_scale().to_f32(),
        ],
        worst,
    )
}

/// The estimated levels of a stiction-adaptation run against the plant's
/// Fc = `fc` and Fs = `fs` [N]: θ_c = Fc/Fc_model within 1 %, the stiction
/// level θ_c·Fc + θ_s·(Fs − Fc) within 3 % of Fs, and the Q16 scales within
/// 0.02 of the f32 ones all along (`run`: the f32 scales, the Q16 scales,
/// the largest Q16 − f32 difference).
fn check_levels(fc: f64, fs: f64, run: ([f32; 2], [f32; 2], f64)) {
    let ([c, s], [cq, sq], worst) = run;
    let want_c = (fc / FIG5.fc as f64) as f32;
    let want_s = ((fs - fc) / (FIG5.fs - FIG5.fc) as f64) as f32;
    let stiction = c * FIG5.fc + s * (FIG5.fs - FIG5.fc);
    eprintln!(
        "({fc}, {fs}): θ_c {c} ({:+.3} %), stiction level {stiction} N ({:+.3} %), Q16 vs f32 {worst}",
        (c / want_c - 1.0) * 100.0,
        (stiction / fs as f32 - 1.0) * 100.0
    );
    assert!(
        (c - want_c).abs() < 0.01 * want_c,
        "({fc}, {fs}): θ_c {c} vs {want_c}"
    );
    assert!(
        (stiction - fs as f32).abs() < 0.03 * fs as f32,
        "({fc}, {fs}): Fs {stiction} N vs {fs} N (θ_s {s} vs {want_s})"
    );
    assert!(
        worst < 0.02,
        "({fc}, {fs}): Q16 vs f32 {worst} ({cq}, {sq})"
    );
}

#[test]
fn stiction_adaptation_finds_the_levels_of_the_reference_plant() {
    // The plant's Fc is 20 % above the compensator's and its stiction excess
    // Fs − Fc 20 % below (θ_c* = 1.2, θ_s* = 0.8): the single scale of
    // `LevelAdaptation` cannot represent this; the split estimate finds both.
    // Measured after 12 s (24 reversals), with the window fit on Q[H_s]
    // alone: θ_c within 0.04 %, the stiction level θ_c·Fc + θ_s·(Fs − Fc)
    // within 0.5 % (1.593 N for 1.6 N; 1.2 % with the earlier joint fit of
    // both errors), Q16 within 0.0045 of f32 on θ_c and θ_s all along.
    for (fc, fs) in [(1.2, 1.6), (1.0, 1.5), (0.9, 1.6)] {
        check_levels(fc, fs, stiction_run(fc, fs, 12.0));
    }
}

#[test]
fn stiction_adaptation_follows_a_step_drift_of_the_levels() {
    // The plant at the compensator's levels, then at t = 2 s Fc and Fs
    // + 20 % together (θ_c* = θ_s* = 1.2), or Fc alone + 20 % (θ_c* = 1.2,
    // θ_s* = 0.6), ideal measurement. The truth is the plant's: θ_c* =
    // Fc/Fc_model and the stiction level θ_c·Fc + θ_s·(Fs − Fc) = Fs.
    // Measured 10 s after the step (20 reversals): θ_c within 0.04 %, the
    // stiction level within 0.2 % (Fc, Fs: 1.796 N for 1.8 N) and 0.6 %
    // (Fc: 1.492 N for 1.5 N); Q16 within 0.0045 of f32 all along.
    for (fc, fs) in [(1.2, 1.8), (1.2, 1.5)] {
        check_levels(fc, fs, stiction_drift_run(1.0, 1.5, Some((fc, fs)), 12.0));
    }
}

#[test]
fn stiction_window_fit_is_the_least_squares_step() {
    // Closed form: a residual that is exactly Δ·Q[H_s] over one reversal
    // window (Q the first-order low pass of bandwidth g, as the estimator
    // filters its regressors), with no Coulomb error: the window moves θ_s
    // by κ·Δ, and θ_c (frozen below min_speed in the window) by nothing
    // beyond the sliding steps before and after.
    use breakaway::compensation::{StictionAdaptation, StictionConfig};
    const T: f32 = 1e-3;
    let (bandwidth, gain, delta) = (100.0f32, 0.5f32, 0.4f32);
    let alpha = -(-(bandwidth * T) as f64).exp_m1();
    let model = Model::<f32>::new(FIG5).unwrap();
    let mut ff = Feedforward::<f32>::new(FeedforwardConfig::default(), 0.0, 1.0)
        .unwrap()
        .with_split_levels();
    let mut a = StictionAdaptation::new(StictionConfig {
        rate: 1.0,
        reversal_gain: gain,
        bandwidth,
        min_scale: 0.5,
        max_scale: 2.0,
        max_stiction_scale: 3.0,
        min_speed: FIG5.v_stribeck,
        period: T,
    })
    .unwrap();
    let w = 2.0 * std::f64::consts::PI;
    let mut q = 0.0f64;
    let (mut theta_s, mut closed) = (1.0f32, 0);
    for n in 0..1500 {
        let t = n as f64 * 1e-3;
        let (x_ref, v_ref) = (1e-3 * (1.0 - (w * t).cos()), 1e-3 * w * (w * t).sin());
        q += alpha * (f64::from(ff.stiction_dry()) - q);
        let r = delta * q as f32;
        let (_, s) = a.update(r, &ff, v_ref as f32).unwrap();
        if s != theta_s {
            assert!(
                (s - theta_s - gain * delta).abs() < 1e-4,
                "window {closed}: θ_s {theta_s} -> {s}, want + {}",
                gain * delta
            );
            (theta_s, closed) = (s, closed + 1);
        }
        ff.update(&model, x_ref as f32, v_ref as f32).unwrap();
    }
    // Reversals at 0.5 s and 1.0 s, each window closed once.
    assert_eq!(closed, 2);
}

#[test]
fn stiction_adaptation_is_bounded_and_rejects_bad_samples() {
    use breakaway::compensation::{StictionAdaptation, StictionConfig};
    use breakaway::Q16;
    let config = StictionConfig {
        rate: 10.0,
        reversal_gain: 1.0,
        bandwidth: 100.0,
        min_scale: 0.5,
        max_scale: 1.5,
        max_stiction_scale: 2.0,
        min_speed: 1e-3,
        period: 1e-3,
    };
    let model = Model::<f32>::new(FIG5).unwrap();
    let fixed_model = Model::<Q16>::new(FIG5).unwrap();
    let units = fixed_model.units();
    let scale = fixed_model.position_scale::<i32>(1e-8).unwrap();
    let mut ff = Feedforward::<f32>::new(FeedforwardConfig::default(), 0.0, 1.0)
        .unwrap()
        .with_split_levels();
    let mut fixed_ff =
        Feedforward::<i32, Q16>::with_units(FeedforwardConfig::default(), units, 0, scale)
            .unwrap()
            .with_split_levels();
    let mut a = StictionAdaptation::new(config).unwrap();
    let mut q = StictionAdaptation::<Q16>::with_units(config, units).unwrap();
    // Adversarial: a reference reversing every 3 to 40 samples over ±50 µm,
    // speeds up to 0.1 m/s, residuals up to ±1e30 N (saturating in Q16).
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut x, mut dir, mut left) = (0.0f64, 1.0f64, 0u32);
    for _ in 0..20_000 {
        if left == 0 {
            dir = -dir;
            left = 3 + (next() * 37.0) as u32;
        }
        left -= 1;
        let v = dir * next() * 0.1;
        x = (x + v * 1e-3).clamp(-5e-5, 5e-5);
        let r = ((next() - 0.5) * 2.0 * 10f64.powf(next() * 30.0)) as f32;
        let (c, s) = a.update(r, &ff, v as f32).unwrap();
        assert!(
            (0.5..=1.5).contains(&c) && (0.0..=2.0).contains(&s),
            "{c} {s}"
        );
        ff.set_level_scales(c, s);
        let u = ff.update(&model, x as f32, v as f32).unwrap();
        assert!(
            u.is_finite() && u.abs() <= 1.5 * 1.5 + 2.0 * 0.5 + 1e-4,
            "{u}"
        );
        let r_q = Q16::from_f32((r / units.force).clamp(-3e4, 3e4)).unwrap();
        let v_q = fixed_model.velocity((v as f32).clamp(-1.0, 1.0)).unwrap();
        let (cq, sq) = q.update(r_q, &fixed_ff, v_q).unwrap();
        assert!((0.5..=1.5).contains(&cq.to_f32()) && (0.0..=2.0).contains(&sq.to_f32()));
        fixed_ff.set_level_scales(cq, sq);
        fixed_ff
            .update(&fixed_model, (x / 1e-8).round() as i32, v_q)
            .unwrap();
    }
    let before = a.clone();
    assert_eq!(a.update(f32::NAN, &ff, 0.01), Err(SampleError::Force));
    assert_eq!(a.update(f32::INFINITY, &ff, 0.01), Err(SampleError::Force));
    assert_eq!(a.update(0.1, &ff, f32::NAN), Err(SampleError::Velocity));
    assert_eq!(a, before);
    a.reset();
    assert_eq!((a.coulomb_scale(), a.stiction_scale()), (1.0, 1.0));
    for (c, s) in [
        (
            StictionConfig {
                rate: 2000.0,
                ..config
            },
            Setting::Rate,
        ),
        (
            StictionConfig {
                reversal_gain: 0.0,
                ..config
            },
            Setting::ReversalGain,
        ),
        (
            StictionConfig {
                reversal_gain: 1.5,
                ..config
            },
            Setting::ReversalGain,
        ),
        (
            StictionConfig {
                bandwidth: f32::NAN,
                ..config
            },
            Setting::Bandwidth,
        ),
        (
            StictionConfig {
                min_scale: 1.1,
                ..config
            },
            Setting::MinScale,
        ),
        (
            StictionConfig {
                max_scale: 0.9,
                ..config
            },
            Setting::MaxScale,
        ),
        (
            StictionConfig {
                max_stiction_scale: 0.5,
                ..config
            },
            Setting::MaxStictionScale,
        ),
        (
            StictionConfig {
                min_speed: -1.0,
                ..config
            },
            Setting::MinSpeed,
        ),
        (
            StictionConfig {
                period: 0.0,
                ..config
            },
            Setting::Period,
        ),
    ] {
        assert_eq!(StictionAdaptation::new(c).unwrap_err(), ConfigError(s));
    }
}
