//! Link-time proof that the per-sample and prediction paths hold no panic.
//!
//! The panic handler below calls a function that exists nowhere. The linker
//! only needs it if some code that can panic survives optimisation in the
//! functions this program calls with opaque (`black_box`) inputs: the
//! presliding update (f32 and Q16 numbers, `f32`/`i32`/`i64` positions, with
//! and without the closing memory), the curves, the break-away predictor in
//! all variants, and the compensation blocks. If any of them could panic,
//! `cargo build --release -p breakaway-firmware --features qemu --example
//! no_panic --target …` fails with an undefined
//! symbol `breakaway_panic_path_survived`. `cargo xtask test` builds it for
//! every Cortex-M target and runs it.
#![no_std]
#![no_main]
#![allow(unsafe_code)] // the undefined extern function and cortex-m-rt's entry

use core::hint::black_box;

use breakaway::compensation::{
    AdaptationConfig, BreakAwayDetector, DetectorConfig, DisturbanceObserver, Feedforward,
    FeedforwardConfig, LevelAdaptation, ObserverConfig, StictionAdaptation, StictionConfig,
};
use breakaway::{BreakAwayPredictor, Model, Params, Presliding, Scalar, ScaleError, Variant, Q16};
use cortex_m_rt::entry;
use cortex_m_semihosting::debug;

// Links cortex-m, whose single-core critical section semihosting uses.
use cortex_m as _;

extern "C" {
    /// Defined nowhere: referencing it from a reachable panic fails the link.
    fn breakaway_panic_path_survived() -> !;
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    // SAFETY: never reached; the link fails if this handler is reachable.
    unsafe { breakaway_panic_path_survived() }
}

#[inline(never)]
fn sample<T>(x: T) -> T {
    black_box(x)
}

#[entry]
fn main() -> ! {
    let params = sample(Params {
        fc: 1.0,
        fs: 1.5,
        v_stribeck: 1e-3,
        delta: 1.3,
        sigma: 0.1,
        z_max: 1e-5,
        epsilon: 1e-8,
    });
    if let (Ok(model), Ok(fixed)) = (Model::<f32>::new(params), Model::<Q16>::new(params)) {
        let mut acc = 0.0f32;
        if let (Ok(mut a), Ok(mut b), Ok(mut c), Ok(mut d)) = (
            Presliding::<i64>::new(sample(0), sample(1e-8)),
            Presliding::<i32, f32, 8>::new(sample(0), sample(1e-8)),
            Presliding::<f32>::new(sample(0.0), sample(1.0)),
            fixed
                .position_scale::<i32>(sample(1e-8))
                .ok_or(ScaleError)
                .and_then(|scale| Presliding::<i32, Q16, 4>::new(sample(0), scale)),
        ) {
            for _ in 0..4 {
                acc += a.update(&model, sample(5i64), sample(1e-4)).unwrap_or(0.0);
                acc += b.update(&model, sample(5i32), sample(1e-4)).unwrap_or(0.0);
                acc += c
                    .update(&model, sample(5e-6f32), sample(1e-4))
                    .unwrap_or(0.0);
                let q = d
                    .update(&fixed, sample(5i32), sample(Q16::ONE))
                    .unwrap_or(Q16::ONE);
                acc += q.to_bits() as f32;
            }
        }
        acc += model.stribeck(sample(1e-3)) + model.shape(sample(0.5));
        acc += (fixed.stribeck(sample(Q16::ONE)) + fixed.shape(sample(Q16::ONE))).to_bits() as f32;
        if let (Ok(p), Ok(q)) = (
            BreakAwayPredictor::new(&model, sample(0.95)),
            BreakAwayPredictor::new(&fixed, sample(0.95)),
        ) {
            for variant in Variant::ALL {
                let variant = sample(variant);
                acc += p
                    .predict(&model, variant, sample(2.0))
                    .map_or(0.0, |b| b.f_ba);
                acc += q
                    .predict(&fixed, variant, sample(Q16::ONE))
                    .map_or(0, |b| b.f_ba.to_bits()) as f32;
                acc +=
                    BreakAwayPredictor::phase_velocity(&model, variant, sample(2.0), sample(0.5))
                        .unwrap_or(0.0);
            }
        }
        if let Ok(mut ff) = Feedforward::<f32>::new(sample(FeedforwardConfig::default()), 0.0, 1.0)
        {
            acc += ff.update(&model, sample(1e-6), sample(1e-4)).unwrap_or(0.0);
        }
        let observer = ObserverConfig {
            mass: 1.0,
            bandwidth: 100.0,
            period: 1e-3,
        };
        if let Ok(mut obs) = DisturbanceObserver::new(sample(observer)) {
            acc += obs
                .update(sample(1.0), sample(1e-3), sample(0.5))
                .unwrap_or(0.0);
        }
        let adaptation = AdaptationConfig {
            rate: 0.5,
            min_scale: 0.5,
            max_scale: 2.0,
            min_speed: 1e-3,
            period: 1e-3,
        };
        if let Ok(mut ad) = LevelAdaptation::new(sample(adaptation)) {
            acc += ad
                .update(sample(0.1), sample(1.0), sample(1e-2), sample(true))
                .unwrap_or(0.0);
        }
        let stiction = StictionConfig {
            rate: 0.5,
            reversal_gain: 0.3,
            bandwidth: 100.0,
            min_scale: 0.5,
            max_scale: 2.0,
            max_stiction_scale: 3.0,
            min_speed: 1e-3,
            period: 1e-3,
        };
        // Out and back: a reversal window opens and closes.
        let stroke = [0.0, 2e-5, 4e-5, 2e-5, 0.0];
        if let (Ok(mut ad), Ok(ff)) = (
            StictionAdaptation::new(sample(stiction)),
            Feedforward::<f32>::new(sample(FeedforwardConfig::default()), 0.0, 1.0),
        ) {
            let mut ff = ff.with_split_levels();
            for x in stroke {
                let (c, s) = ad
                    .update(sample(0.1), &ff, sample(1e-2))
                    .unwrap_or((1.0, 1.0));
                ff.set_level_scales(c, s);
                acc += ff.update(&model, sample(x), sample(1e-2)).unwrap_or(0.0);
            }
        }
        if let (Some(scale), Ok(mut ad)) = (
            fixed.position_scale::<i32>(sample(1e-8)),
            StictionAdaptation::<Q16>::with_units(sample(stiction), fixed.units()),
        ) {
            if let Ok(ff) = Feedforward::<i32, Q16>::with_units(
                sample(FeedforwardConfig::default()),
                fixed.units(),
                0,
                scale,
            ) {
                let mut ff = ff.with_split_levels();
                for x in stroke {
                    let (c, s) = ad
                        .update(sample(Q16::ONE), &ff, sample(Q16::ONE))
                        .unwrap_or((Q16::ONE, Q16::ONE));
                    ff.set_level_scales(c, s);
                    let count = sample((x / 1e-8) as i32);
                    acc += ff
                        .update(&fixed, count, sample(Q16::ONE))
                        .map_or(0, Q16::to_bits) as f32;
                }
            }
        }
        let detector = DetectorConfig {
            period: 1e-3,
            rest_speed: 1e-5,
            break_away_speed: 1e-3,
            // ≥ 2⁻¹⁵·Fs/T = 0.046 N/s, the Q16 bound at 1 kHz.
            min_rate: 0.1,
        };
        // A ramp at rest, then a break-away: the measurement path runs.
        let ramp = [(0.0, 0.0), (0.1, 0.0), (0.2, 0.0), (0.3, 0.0), (0.4, 2e-3)];
        if let Ok(mut det) =
            BreakAwayDetector::<8>::new(sample(detector), &model, Variant::Consistent, 0.95)
        {
            for (u, v) in ramp {
                if let Ok(Some(m)) = det.update(&model, sample(u), sample(v)) {
                    acc += m.force;
                }
            }
        }
        if let Ok(mut det) =
            BreakAwayDetector::<8, Q16>::new(sample(detector), &fixed, Variant::Consistent, 0.95)
        {
            for (u, v) in ramp {
                let (u, v) = (Q16::from_f32(u / 1.5), fixed.velocity(v));
                if let (Some(u), Some(v)) = (u, v) {
                    if let Ok(Some(m)) = det.update(&fixed, sample(u), sample(v)) {
                        acc += (m.rate + m.time).to_bits() as f32;
                    }
                }
            }
        }
        black_box(acc);
    }
    debug::exit(debug::EXIT_SUCCESS);
    #[allow(clippy::empty_loop)]
    loop {}
}
