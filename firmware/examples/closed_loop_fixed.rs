//! The closed-loop benchmark of `breakaway-lab closed-loop` on a Cortex-M0
//! (`common/closed_loop.rs`: the plant and the PID in `f32`) with the
//! compensators in Q16.16: the same `Feedforward`, `DisturbanceObserver`
//! and `StictionAdaptation` code as the `f32` example, on a `Model<Q16>` built
//! in place, the reference position read as 10 nm encoder counts. Rows
//! `presliding` and `presliding+observer+adaptation`, measured ideally and
//! through a 1 µm encoder, then `done`; xtask compares them with the host's
//! f64 run of the `f32` compensators.
#![no_std]
#![no_main]
#![allow(unsafe_code)] // cortex-m-rt's `#[exception]` handler is an `unsafe fn`

#[path = "common/closed_loop.rs"]
mod harness;

use breakaway::compensation::{
    DisturbanceObserver, Feedforward, FeedforwardConfig, StictionAdaptation,
};
use breakaway::{Model, Scalar, Q16};
use cortex_m_rt::entry;
use cortex_m_semihosting::hprintln;
use harness::{common, Inputs};

/// Metres per encoder count of the reference position.
const COUNT: f32 = 1e-8;

/// (name, observer and adaptation, encoder [m per count]).
const RUNS: [(&str, bool, f32); 4] = [
    ("presliding", false, 0.0),
    ("presliding+observer+adaptation", true, 0.0),
    ("presliding", false, 1e-6),
    ("presliding+observer+adaptation", true, 1e-6),
];

/// The presliding compensator in Q16, with the observer and the adaptation
/// when `observe`, through the benchmark.
fn run(observe: bool, model: &Model<Q16>, encoder: f32) -> Option<(f32, f32, f32)> {
    let units = model.units();
    let scale = model.position_scale::<i32>(COUNT)?;
    let mut ff =
        Feedforward::<i32, Q16>::with_units(FeedforwardConfig::default(), units, 0, scale).ok()?;
    if observe {
        ff = ff.with_split_levels();
    }
    let mut observer = DisturbanceObserver::<Q16>::with_units(harness::OBSERVER, units).ok()?;
    let mut adaptation = StictionAdaptation::<Q16>::with_units(harness::ADAPTATION, units).ok()?;
    let mut u_ff = Q16::ZERO;
    harness::run(encoder, |i: &Inputs| {
        // The boundary: SI in f32 → counts and per-unit Q16.
        let count = libm::roundf(i.x_ref / COUNT) as i32;
        let v_ref = model.velocity(i.v_ref)?;
        let force = if observe {
            let command = Q16::from_f32(i.command / units.force)?;
            let velocity = model.velocity(i.velocity)?;
            let r = observer.update(command, velocity, u_ff).ok()?;
            let (coulomb, stiction) = adaptation.update(r, &ff, v_ref).ok()?;
            ff.set_level_scales(coulomb, stiction);
            u_ff = ff.update(model, count, v_ref).ok()?;
            u_ff + r
        } else {
            ff.update(model, count, v_ref).ok()?
        };
        Some(force.to_f32() * units.force)
    })
}

#[entry]
fn main() -> ! {
    let mut model = Model::<Q16>::UNIT_COULOMB;
    if model.set_params(common::FIG5).is_err() {
        common::exit_failure("invalid parameters");
    }
    harness::print_config();
    for (name, observe, encoder) in RUNS {
        match run(observe, &model, encoder) {
            Some(figures) => harness::print_row(name, encoder, figures),
            None => common::exit_failure("closed loop rejected a sample"),
        }
    }
    hprintln!("done");
    common::exit_success()
}
