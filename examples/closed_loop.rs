//! The closed-loop benchmark of `breakaway-lab closed-loop` on the MCU
//! (`common/closed_loop.rs`) with the five `f32` compensators: none,
//! Coulomb, Stribeck, presliding feedforward, and presliding feedforward
//! with the disturbance observer and the level adaptation. Then `done`.
//! xtask compares the figures with the host's f64 run.
#![no_std]
#![no_main]
#![allow(unsafe_code)] // cortex-m-rt's `#[exception]` handler is an `unsafe fn`

#[path = "common/mod.rs"]
mod common;
#[path = "common/closed_loop.rs"]
mod harness;

use breakaway::compensation::{
    AdaptationConfig, DisturbanceObserver, Feedforward, FeedforwardConfig, LevelAdaptation,
    ObserverConfig,
};
use breakaway::Model;
use cortex_m_rt::entry;
use cortex_m_semihosting::hprintln;
use harness::{Inputs, ADAPTATION_RATE, MASS, OBSERVER_BANDWIDTH, PERIOD};

const NAMES: [&str; 5] = [
    "none",
    "coulomb",
    "stribeck",
    "presliding",
    "presliding_observer",
];

/// Compensator `which` of [`NAMES`] through the benchmark.
fn run(which: usize, model: &Model<f32>) -> Option<(f32, f32, f32)> {
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
    let mut u_ff = 0.0f32;
    harness::run(|i: &Inputs| {
        Some(match which {
            0 => 0.0,
            1 => {
                if i.v_ref > 0.0 {
                    model.params().fc
                } else if i.v_ref < 0.0 {
                    -model.params().fc
                } else {
                    0.0
                }
            }
            2 => model.steady_state(i.v_ref),
            3 => ff.update(model, i.x_ref, i.v_ref).ok()?,
            _ => {
                let r = observer.update(i.command, i.velocity, u_ff).ok()?;
                let theta = adaptation
                    .update(r, ff.dry(), i.v_ref, ff.is_sliding())
                    .ok()?;
                ff.set_level_scale(theta);
                u_ff = ff.update(model, i.x_ref, i.v_ref).ok()?;
                u_ff + r
            }
        })
    })
}

#[entry]
fn main() -> ! {
    let Ok(model) = Model::<f32>::new(common::FIG5) else {
        common::exit_failure("invalid parameters");
    };
    harness::print_config();
    for (which, name) in NAMES.iter().enumerate() {
        match run(which, &model) {
            Some((rms, peak, effort)) => hprintln!("cl {} {} {} {}", name, rms, peak, effort),
            None => common::exit_failure("closed loop rejected a sample"),
        }
    }
    hprintln!("done");
    common::exit_success()
}
