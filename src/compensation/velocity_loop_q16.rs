use breakaway::compensation::{DisturbanceObserver, Feedforward, FeedforwardConfig,
    ObserverConfig, VelocityConfig, VelocityEstimator};
use breakaway::hal::{DutyMode, PwmForce, SetDutyCycle};
use breakaway::{Error, Model, Params, Scalar, Q16};

const PERIOD: f32 = 1e-3; // control period T [s]
const COUNT: f32 = 1e-8;  // encoder resolution [m per count]
const PARAMS: Params = Params { fc: 1.0, fs: 1.5, v_stribeck: 1e-3, delta: 1.0,
    sigma: 0.0, z_max: 1e-5, epsilon: 0.0 };

/// The loop on the raw encoder counts `encoder`, one per period, driving
/// `timer`; returns the last feedforward [N].
pub fn velocity_loop(
    timer: impl SetDutyCycle,
    encoder: impl IntoIterator<Item = i32>,
) -> Result<f32, Error> {
    // At start-up (soft-float f32 here, once; not in the loop).
    let mut model = Model::<Q16>::UNIT_COULOMB;
    model.set_params(PARAMS)?; // built in place
    let units = model.units(); // N per force unit (Fs), m/s per velocity unit (V)
    let scale = model.position_scale::<i32>(COUNT).ok_or(Error::Range("count"))?;
    let mut feedforward =
        Feedforward::<i32, Q16>::with_units(FeedforwardConfig::default(), units, 0, scale)?;
    let config = VelocityConfig { bandwidth: 3000.0, period: PERIOD };
    let mut velocity = VelocityEstimator::<i32, Q16>::with_units(config, units, scale)?;
    let config = ObserverConfig { mass: 2.0, bandwidth: 100.0, period: PERIOD };
    let mut observer = DisturbanceObserver::<Q16>::with_units(config, units)?;
    let mut output = PwmForce::<_, Q16>::with_units(timer, 5.0, DutyMode::Centered, units)?;
    // PI gains and set-point in model units.
    let (kp, ki) = (200.0, 4000.0); // [N·s/m], [N/m]
    let to_q16 = |x: f32| Q16::from_f32(x).ok_or(Error::Range("gain"));
    let kp = to_q16(kp * units.velocity / units.force)?;
    let ki_t = to_q16(ki * PERIOD * units.velocity / units.force)?;
    let v_ref = model.velocity(5e-3).ok_or(Error::Range("set-point"))?; // 5 mm/s

    // The loop: integer arithmetic only.
    let mut sum_error = Q16::ZERO;
    let (mut applied, mut u_ff) = (Q16::ZERO, Q16::ZERO);
    for count in encoder {
        let v = velocity.update(count)?;
        let r = observer.update(applied, v, u_ff)?;
        u_ff = feedforward.update(&model, count, v)?;
        let error = v_ref - v;
        sum_error = sum_error + error;
        applied = output.write(kp * error + ki_t * sum_error + u_ff + r)?.force;
    }
    Ok(u_ff.to_f32() * units.force)
}
