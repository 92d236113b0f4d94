//! The closed-loop benchmark of `breakaway-lab closed-loop` on the MCU
//! (`common/closed_loop.rs`) with the nine `f32` compensators (four
//! feedforwards, each with and without the disturbance observer, and the
//! presliding one with observer and the adaptation of the Coulomb and
//! stiction levels) measured ideally,
//! then three of them through a 1 µm encoder. Then `done`. xtask compares
//! the figures with the host's f64 run.
#![no_std]
#![no_main]
#![allow(unsafe_code)] // cortex-m-rt's `#[exception]` handler is an `unsafe fn`

#[path = "common/closed_loop.rs"]
mod harness;

use breakaway::compensation::{
    DisturbanceObserver, Feedforward, FeedforwardConfig, StictionAdaptation,
};
use breakaway::Model;
use cortex_m_rt::entry;
use cortex_m_semihosting::hprintln;
use harness::{common, Inputs};

/// Compensators: (name, feedforward 0 none, 1 Coulomb, 2 Stribeck,
/// 3 presliding; observer; adaptation), as the host benchmark names them.
const COMPENSATORS: [(&str, u8, bool, bool); 9] = [
    ("none", 0, false, false),
    ("coulomb", 1, false, false),
    ("stribeck", 2, false, false),
    ("presliding", 3, false, false),
    ("none+observer", 0, true, false),
    ("coulomb+observer", 1, true, false),
    ("stribeck+observer", 2, true, false),
    ("presliding+observer", 3, true, false),
    ("presliding+observer+adaptation", 3, true, true),
];

/// Runs through the 1 µm encoder.
const ENCODER: f32 = 1e-6;
const ENCODER_ROWS: [usize; 3] = [5, 3, 8];

/// One compensator through the benchmark.
fn run(
    (_, feedforward, observe, adapt): (&str, u8, bool, bool),
    model: &Model<f32>,
    encoder: f32,
) -> Option<(f32, f32, f32)> {
    let mut ff = Feedforward::<f32>::new(FeedforwardConfig::default(), 0.0, 1.0).ok()?;
    if adapt {
        ff = ff.with_split_levels();
    }
    let mut observer = DisturbanceObserver::new(harness::OBSERVER).ok()?;
    let mut adaptation = StictionAdaptation::new(harness::ADAPTATION).ok()?;
    let mut u_ff = 0.0f32;
    harness::run(encoder, |i: &Inputs| {
        let residual = if observe {
            let r = observer.update(i.command, i.velocity, u_ff).ok()?;
            if adapt {
                let (coulomb, stiction) = adaptation.update(r, &ff, i.v_ref).ok()?;
                ff.set_level_scales(coulomb, stiction);
            }
            r
        } else {
            0.0
        };
        u_ff = match feedforward {
            0 => 0.0,
            1 if i.v_ref > 0.0 => model.params().fc,
            1 if i.v_ref < 0.0 => -model.params().fc,
            1 => 0.0,
            2 => model.steady_state(i.v_ref),
            _ => ff.update(model, i.x_ref, i.v_ref).ok()?,
        };
        Some(u_ff + residual)
    })
}

#[entry]
fn main() -> ! {
    let model = common::model::<f32>(common::FIG5);
    harness::print_config();
    let runs = COMPENSATORS
        .iter()
        .map(|&c| (c, 0.0))
        .chain(ENCODER_ROWS.iter().map(|&i| (COMPENSATORS[i], ENCODER)));
    for (compensator, encoder) in runs {
        match run(compensator, &model, encoder) {
            Some(figures) => harness::print_row(compensator.0, encoder, figures),
            None => common::exit_failure("closed loop rejected a sample"),
        }
    }
    hprintln!("done");
    common::exit_success()
}
