//! The closed-loop benchmark of `breakaway-lab closed-loop` as firmware: a
//! PID position loop tracking x_ref = A·(1 − cos 2πft) on the MODEL.md
//! plant (Fc +25 %, Fs +20 %, V +30 %, z_max +30 % against the
//! compensator's Fig. 5 parameters), simulated on the MCU in `f32` with the
//! library's own presliding state machine as the plant's friction
//! (semi-implicit Euler, 200 sub-steps per 1 ms period, the position summed
//! with compensation). The compensator is the example's: a function of
//! [`Inputs`] returning the compensation force [N].
//!
//! The controller measures either the plant's own position and velocity
//! (`encoder` = 0) or an encoder's count ⌊x/q⌋, read as the centre of the
//! count, and the library's `VelocityEstimator` on it, as the host
//! benchmark does.
//!
//! Output: `cfg …` (the constants, which `cargo xtask test` checks against
//! the host benchmark's), then per run `cl <name> <encoder m> <rms_error m>
//! <peak_reversal_error m> <rms_effort N>`.
//!
//! It brings the firmware plumbing it runs on (`common/mod.rs`) as
//! `harness::common`, so that an example declares the harness alone.

// `common/mod.rs`, beside this file.
#[path = "mod.rs"]
pub mod common;

use breakaway::compensation::{ObserverConfig, StictionConfig, VelocityConfig, VelocityEstimator};
use breakaway::{Model, Presliding};
use cortex_m_semihosting::hprintln;

pub const PERIOD: f32 = 1e-3;
pub const AMPLITUDE: f32 = 1e-3;
const FREQUENCY: f32 = 1.0;
/// Periods per run (8 s).
const STEPS: u32 = 8000;
/// First period of the evaluation window (5 s).
const WINDOW: u32 = 5000;
/// Periods between reversals (0.5 s) and after one that count (50 ms).
const HALF: u32 = 500;
const AFTER: u32 = 50;
pub const MASS: f32 = 1.0;
const OMEGA: f32 = 125.0;
pub const OBSERVER_BANDWIDTH: f32 = 100.0;
pub const ADAPTATION_RATE: f32 = 1.0;
/// κ of the stiction adaptation.
pub const REVERSAL_GAIN: f32 = 0.3;
const SUBSTEPS: u32 = 200;
const VELOCITY_BANDWIDTH: f32 = 3000.0;

/// The disturbance observer of the benchmark's compensators.
pub const OBSERVER: ObserverConfig = ObserverConfig {
    mass: MASS,
    bandwidth: OBSERVER_BANDWIDTH,
    period: PERIOD,
};

/// The stiction adaptation of the benchmark's compensators (its speed
/// threshold the compensator's Stribeck velocity).
pub const ADAPTATION: StictionConfig = StictionConfig {
    rate: ADAPTATION_RATE,
    reversal_gain: REVERSAL_GAIN,
    bandwidth: OBSERVER_BANDWIDTH,
    min_scale: 0.5,
    max_scale: 2.0,
    max_stiction_scale: 3.0,
    min_speed: common::FIG5.v_stribeck,
    period: PERIOD,
};

/// What a compensator sees in period `n`.
pub struct Inputs {
    /// Reference position [m] and velocity [m/s].
    pub x_ref: f32,
    pub v_ref: f32,
    /// The plant's measured velocity [m/s] now.
    pub velocity: f32,
    /// The command u [N] applied during the period that just ended.
    pub command: f32,
}

/// Prints the `cfg` line.
pub fn print_config() {
    hprintln!(
        "cfg {} {} {} {} {} {} {} {} {} {} {}",
        PERIOD,
        AMPLITUDE,
        FREQUENCY,
        STEPS,
        WINDOW,
        OMEGA,
        OBSERVER_BANDWIDTH,
        ADAPTATION_RATE,
        SUBSTEPS,
        VELOCITY_BANDWIDTH,
        REVERSAL_GAIN
    );
}

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

/// Prints the `cl` line of a run.
pub fn print_row(name: &str, encoder: f32, figures: (f32, f32, f32)) {
    let (rms, peak, effort) = figures;
    hprintln!("cl {} {} {} {} {}", name, encoder, rms, peak, effort);
}

/// Runs the loop with `compensate`, measuring through an encoder of
/// `encoder` metres per count (0: ideal); (rms_error [m],
/// peak_reversal_error [m], rms_effort [N]), `None` when a sample was
/// rejected.
pub fn run(
    encoder: f32,
    mut compensate: impl FnMut(&Inputs) -> Option<f32>,
) -> Option<(f32, f32, f32)> {
    let mut estimator = if encoder > 0.0 {
        let config = VelocityConfig {
            bandwidth: VELOCITY_BANDWIDTH,
            period: PERIOD,
        };
        Some(VelocityEstimator::<i64>::new(config, encoder).ok()?)
    } else {
        None
    };
    let mut plant = Plant {
        model: Model::new(common::CLOSED_LOOP_PLANT).ok()?,
        friction: Presliding::at(0.0),
        x: 0.0,
        x_lo: 0.0,
        v: 0.0,
    };
    let (kp, ki, kd) = (
        3.0 * MASS * OMEGA * OMEGA,
        MASS * OMEGA * OMEGA * OMEGA,
        3.0 * MASS * OMEGA,
    );
    let w = 2.0 * core::f32::consts::PI * FREQUENCY;
    let (mut integral, mut u) = (0.0f32, 0.0f32);
    let (mut sum_e2, mut sum_u2, mut peak) = (0.0f32, 0.0f32, 0.0f32);
    for n in 0..STEPS {
        let t = n as f32 * PERIOD;
        let (s, c) = (libm::sinf(w * t), libm::cosf(w * t));
        let (x_ref, v_ref, a_ref) = (
            AMPLITUDE * (1.0 - c),
            AMPLITUDE * w * s,
            AMPLITUDE * w * w * c,
        );
        // The figures judge the true position; the controller sees x_m.
        let e = x_ref - plant.x - plant.x_lo;
        let (e_m, v_m) = match estimator.as_mut() {
            None => (e, plant.v),
            Some(estimator) => {
                // The centre of the count, as the host benchmark reads it.
                let count = libm::floorf((plant.x + plant.x_lo) / encoder) as i64;
                let x_m = (count as f32 + 0.5) * encoder;
                (x_ref - x_m, estimator.update(count).ok()?)
            }
        };
        let compensation = compensate(&Inputs {
            x_ref,
            v_ref,
            velocity: v_m,
            command: u,
        })?;
        integral += e_m * PERIOD;
        u = kp * e_m + ki * integral + kd * (v_ref - v_m) + MASS * a_ref + compensation;
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
