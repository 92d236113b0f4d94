//! The Q16.16 compensation loop of `compensation_fixed`, shared with
//! `cargo xtask`, which runs the same code on the host and compares the
//! checksum the Cortex-M0 printed.

use breakaway::compensation::{
    AdaptationConfig, DisturbanceObserver, Feedforward, FeedforwardConfig, LevelAdaptation,
    ObserverConfig,
};
use breakaway::hal::{DutyMode, PwmForce};
use breakaway::{Model, Params, Scalar, Q16};

// The Fig. 5 setting of the tests; every includer also includes
// `tests/support` as its sibling module `support`.
const PARAMS: Params = super::support::FIG5;
/// Metres per count and control period [s].
const COUNT: f32 = 1e-8;
const PERIOD: f32 = 1e-3;

// The timer channel (a stand-in that keeps the last duty; `cargo xtask`
// takes it from here too).
#[path = "../../../tests/support/pwm.rs"]
pub mod pwm;
use pwm::Timer;

/// Encoder count at period `n`: a triangle of ±3 000 counts (±3 z_max) at
/// 1 to 9 counts per period, so that the loop reverses and slides.
fn encoder(n: u32) -> i32 {
    let phase = (n % 1200) as i32;
    let speed = 1 + (n / 1200 % 9) as i32;
    let ramp = if phase < 600 { phase } else { 1200 - phase };
    (ramp - 300) * speed
}

/// The loop; returns the sum of the duties written.
#[inline(never)]
pub fn control() -> Option<u32> {
    let mut model = Model::<Q16>::UNIT_COULOMB;
    model.set_params(PARAMS).ok()?;
    let units = model.units();
    let scale = model.position_scale::<i32>(COUNT)?;
    let per_count = model.velocity(COUNT / PERIOD)?;
    let mut ff =
        Feedforward::<i32, Q16>::with_units(FeedforwardConfig::default(), units, 0, scale).ok()?;
    let observer_config = ObserverConfig {
        mass: 1.0,
        bandwidth: 100.0,
        period: PERIOD,
    };
    let mut observer = DisturbanceObserver::<Q16>::with_units(observer_config, units).ok()?;
    let adaptation_config = AdaptationConfig {
        rate: 1.0,
        min_scale: 0.5,
        max_scale: 2.0,
        min_speed: PARAMS.v_stribeck,
        period: PERIOD,
    };
    let mut adaptation = LevelAdaptation::<Q16>::with_units(adaptation_config, units).ok()?;
    let mut pwm =
        PwmForce::<_, Q16>::with_units(Timer { duty: 0 }, 3.0, DutyMode::Centered, units).ok()?;
    let (mut last, mut command, mut u_ff, mut sum) = (0, Q16::ZERO, Q16::ZERO, 0u32);
    for n in 0..2000 {
        let count = encoder(n);
        let velocity = Q16::saturating_from_int(count - last) * per_count;
        last = count;
        let r = observer.update(command, velocity, u_ff).ok()?;
        let theta = adaptation
            .update(r, ff.dry(), velocity, ff.is_sliding())
            .ok()?;
        ff.set_level_scale(theta);
        u_ff = ff.update(&model, count, velocity).ok()?;
        let applied = pwm.write(u_ff + r).ok()?;
        command = applied.force;
        sum = sum.wrapping_add(u32::from(applied.duty));
    }
    Some(sum)
}
