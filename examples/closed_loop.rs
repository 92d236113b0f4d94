//! The closed-loop benchmark of `breakaway-lab closed-loop` on the MCU: a
//! PID position loop tracking x_ref = A·(1 − cos 2πft) on the MODEL.md
//! plant (Fc +25 %, Fs +20 %, V +30 %, z_max +30 % against the
//! compensator's Fig. 5 parameters), simulated on the MCU in f32 with the
//! library's own presliding state machine as the plant's friction
//! (semi-implicit Euler, 200 sub-steps per 1 ms period, the position summed
//! with compensation), for the five compensators.
//!
//! Output: `cfg …` (the constants, which `cargo xtask test` checks against
//! the host benchmark's), then one line per compensator
//! `cl <name> <rms_error m> <peak_reversal_error m> <rms_effort N>`, then
//! `done`. xtask compares the figures with the host's f64 run.
#![no_std]
#![no_main]
#![allow(unsafe_code)] // cortex-m-rt's `#[exception]` handler is an `unsafe fn`

#[path = "common/mod.rs"]
mod common;

use breakaway::compensation::{
    AdaptationConfig, DisturbanceObserver, Feedforward, FeedforwardConfig, LevelAdaptation,
    ObserverConfig,
};
use breakaway::{Model, Params, Presliding};
use cortex_m_rt::entry;
use cortex_m_semihosting::hprintln;

const PERIOD: f32 = 1e-3;
const AMPLITUDE: f32 = 1e-3;
const FREQUENCY: f32 = 1.0;
/// Periods per run (8 s).
const STEPS: u32 = 8000;
/// First period of the evaluation window (5 s).
const WINDOW: u32 = 5000;
/// Periods between reversals (0.5 s) and after one that count (50 ms).
const HALF: u32 = 500;
const AFTER: u32 = 50;
const MASS: f32 = 1.0;
const OMEGA: f32 = 125.0;
const OBSERVER_BANDWIDTH: f32 = 100.0;
const ADAPTATION_RATE: f32 = 1.0;
const SUBSTEPS: u32 = 200;

/// The plant's parameters (`MODEL_PLANT` of the lab's benchmark).
const PLANT: Params = Params {
    fc: 1.25,
    fs: 1.8,
    v_stribeck: 1.3e-3,
    delta: 1.0,
    sigma: 0.0,
    z_max: 1.3e-5,
    epsilon: 0.0,
};

const NAMES: [&str; 5] = [
    "none",
    "coulomb",
    "stribeck",
    "presliding",
    "presliding_observer",
];

struct Plant {
    model: Model<f32>,
    friction: Presliding,
    x: f32,
    /// Kahan compensation of x.
    x_lo: f32,
    v: f32,
}

impl Plant {
    fn step(&mut self, u: f32) -> Result<(), breakaway::SampleError> {
        let h = PERIOD / SUBSTEPS as f32;
        for _ in 0..SUBSTEPS {
            let f = self.friction.update(&self.model, self.x, self.v)?;
            self.v += h * (u - f) / MASS;
            let y = h * self.v - self.x_lo;
            let sum = self.x + y;
            self.x_lo = (sum - self.x) - y;
            self.x = sum;
        }
        Ok(())
    }
}

/// (rms_error, peak_reversal_error, rms_effort) of one compensator.
fn run(which: usize, model: &Model<f32>) -> Option<(f32, f32, f32)> {
    let mut plant = Plant {
        model: Model::new(PLANT).ok()?,
        friction: Presliding::at(0.0),
        x: 0.0,
        x_lo: 0.0,
        v: 0.0,
    };
    let mut ff = Feedforward::<f32>::new(FeedforwardConfig::default(), 0.0, 1.0).ok()?;
    let mut observer = DisturbanceObserver::new(ObserverConfig {
        mass: MASS,
        bandwidth: OBSERVER_BANDWIDTH,
        period: PERIOD,
    })
    .ok()?;
    let mut adaptation = LevelAdaptation::new(AdaptationConfig {
        rate: ADAPTATION_RATE,
        min_scale: 0.5,
        max_scale: 2.0,
        min_speed: common::FIG5.v_stribeck,
        period: PERIOD,
    })
    .ok()?;
    let (kp, ki, kd) = (
        3.0 * MASS * OMEGA * OMEGA,
        MASS * OMEGA * OMEGA * OMEGA,
        3.0 * MASS * OMEGA,
    );
    let w = 2.0 * core::f32::consts::PI * FREQUENCY;
    let (mut integral, mut u, mut u_ff) = (0.0f32, 0.0f32, 0.0f32);
    let (mut sum_e2, mut sum_u2, mut peak) = (0.0f32, 0.0f32, 0.0f32);
    for n in 0..STEPS {
        let t = n as f32 * PERIOD;
        let (s, c) = (libm::sinf(w * t), libm::cosf(w * t));
        let (x_ref, v_ref, a_ref) = (
            AMPLITUDE * (1.0 - c),
            AMPLITUDE * w * s,
            AMPLITUDE * w * w * c,
        );
        let e = x_ref - plant.x - plant.x_lo;
        let compensation = match which {
            0 => 0.0,
            1 => {
                if v_ref > 0.0 {
                    model.params().fc
                } else if v_ref < 0.0 {
                    -model.params().fc
                } else {
                    0.0
                }
            }
            2 => model.steady_state(v_ref),
            3 => ff.update(model, x_ref, v_ref).ok()?,
            _ => {
                let r = observer.update(u, plant.v, u_ff).ok()?;
                let theta = adaptation
                    .update(r, ff.dry(), v_ref, ff.is_sliding())
                    .ok()?;
                ff.set_level_scale(theta);
                u_ff = ff.update(model, x_ref, v_ref).ok()?;
                u_ff + r
            }
        };
        integral += e * PERIOD;
        u = kp * e + ki * integral + kd * (v_ref - plant.v) + MASS * a_ref + compensation;
        if n >= WINDOW {
            sum_e2 += e * e;
            sum_u2 += u * u;
            let since = n % HALF;
            if since <= AFTER && n - since >= WINDOW && n - since + AFTER < STEPS {
                peak = peak.max(libm::fabsf(e));
            }
        }
        plant.step(u).ok()?;
    }
    let count = (STEPS - WINDOW) as f32;
    Some((
        libm::sqrtf(sum_e2 / count),
        peak,
        libm::sqrtf(sum_u2 / count),
    ))
}

#[entry]
fn main() -> ! {
    let Ok(model) = Model::<f32>::new(common::FIG5) else {
        common::exit_failure("invalid parameters");
    };
    hprintln!(
        "cfg {} {} {} {} {} {} {} {} {}",
        PERIOD,
        AMPLITUDE,
        FREQUENCY,
        STEPS,
        WINDOW,
        OMEGA,
        OBSERVER_BANDWIDTH,
        ADAPTATION_RATE,
        SUBSTEPS
    );
    for (which, name) in NAMES.iter().enumerate() {
        match run(which, &model) {
            Some((rms, peak, effort)) => hprintln!("cl {} {} {} {}", name, rms, peak, effort),
            None => common::exit_failure("closed loop rejected a sample"),
        }
    }
    hprintln!("done");
    common::exit_success()
}
