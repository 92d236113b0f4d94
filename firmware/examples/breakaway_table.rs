//! The break-away table F_ba(k) of the paper's Fig. 5 setting, computed on
//! the MCU (MODEL.md §4), for the four variants of F̂.
//!
//! Output, one line per (variant, k): `ba <variant> <k> <v_b> <f_ba> <t_ba>`,
//! then `done`. `cargo xtask test` compares every line with the f64 reference.
#![no_std]
#![no_main]
#![allow(unsafe_code)] // cortex-m-rt's `#[exception]` handler is an `unsafe fn`

#[path = "common/mod.rs"]
mod common;

use breakaway::{BreakAwayPredictor, Variant, DEFAULT_BOUNDARY};
use cortex_m_rt::entry;
use cortex_m_semihosting::hprintln;

#[entry]
fn main() -> ! {
    let model = common::model::<f32>(common::FIG5);
    let Ok(predictor) = BreakAwayPredictor::new(&model, DEFAULT_BOUNDARY) else {
        common::exit_failure("invalid boundary");
    };
    for variant in Variant::ALL {
        for k in common::BREAKAWAY_RATES {
            match predictor.predict(&model, variant, k) {
                Ok(ba) => hprintln!(
                    "ba {} {} {} {} {}",
                    variant.name(),
                    k,
                    ba.v_b,
                    ba.f_ba,
                    ba.t_ba
                ),
                Err(_) => common::exit_failure("prediction failed"),
            }
        }
    }
    hprintln!("done");
    common::exit_success()
}
