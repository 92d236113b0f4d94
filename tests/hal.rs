//! The `hal` adapter against a recording `SetDutyCycle` (run with
//! `--features hal`).
#![cfg(feature = "hal")]

use breakaway::compensation::{ConfigError, Setting};
use breakaway::hal::{DutyMode, PwmForce};
use breakaway::SampleError;
use embedded_hal::pwm::{ErrorType, SetDutyCycle};

/// A PWM channel of `max` steps that keeps the last duty written.
#[derive(Debug)]
struct Recorder {
    max: u16,
    duty: Option<u16>,
}

impl Recorder {
    fn new(max: u16) -> Self {
        Self { max, duty: None }
    }
}

impl ErrorType for Recorder {
    type Error = core::convert::Infallible;
}

impl SetDutyCycle for Recorder {
    fn max_duty_cycle(&self) -> u16 {
        self.max
    }
    fn set_duty_cycle(&mut self, duty: u16) -> Result<(), Self::Error> {
        assert!(duty <= self.max, "duty {duty} above max {}", self.max);
        self.duty = Some(duty);
        Ok(())
    }
}

#[test]
fn centered_scale_with_saturation() {
    let pwm = Recorder::new(1000);
    let mut out = PwmForce::new(pwm, 2.0, DutyMode::Centered).unwrap();
    for (force, duty, saturated) in [
        (0.0, 500, false),
        (1.0, 750, false),
        (-2.0, 0, false),
        (2.0, 1000, false),
        (5.0, 1000, true),
        (-1e30, 0, true),
        (0.0031, 501, false), // rounded to the nearest step of 4 mN
    ] {
        let a = out.write(force).unwrap();
        assert_eq!((a.duty, a.saturated), (duty, saturated), "force {force}");
        assert_eq!(out.inner().duty, Some(duty));
        assert!((a.force - (duty as f32 / 500.0 - 1.0) * 2.0).abs() < 1e-6);
    }
    // A non-finite force leaves the output as it was.
    assert_eq!(out.write(f32::NAN), Err(SampleError::Force));
    assert_eq!(out.inner().duty, Some(501));
}

#[test]
fn magnitude_scale_reports_the_direction() {
    let pwm = Recorder::new(255);
    let mut out = PwmForce::new(pwm, 3.0, DutyMode::Magnitude).unwrap();
    let a = out.write(-1.5).unwrap();
    assert_eq!(a.duty, 128);
    assert!(a.reverse && !a.saturated);
    assert!((a.force + 128.0 / 255.0 * 3.0).abs() < 1e-6);
    let a = out.write(4.0).unwrap();
    assert_eq!((a.duty, a.reverse, a.saturated), (255, false, true));
    assert_eq!(
        PwmForce::new(Recorder::new(1), 0.0, DutyMode::Magnitude).unwrap_err(),
        ConfigError(Setting::FullScale)
    );
}

/// The Q16.16 adapter (force in units of Fs) writes the duty the `f32` one
/// writes for the same force, to the step, and reports the same force.
#[test]
fn fixed_point_duty_equals_the_f32_duty() {
    use breakaway::{Units, Q16};
    let units = Units {
        force: 1.5,
        velocity: 1e-3,
        length: 1e-5 / 256.0,
    };
    for mode in [DutyMode::Centered, DutyMode::Magnitude] {
        let mut float = PwmForce::new(Recorder::new(4095), 2.0, mode).unwrap();
        let mut fixed =
            PwmForce::<_, Q16>::with_units(Recorder::new(4095), 2.0, mode, units).unwrap();
        for i in -300..=300 {
            let newtons = i as f32 * 0.01;
            let q = Q16::from_f32(newtons / units.force).unwrap();
            let a = float.write(q.to_f32() * units.force).unwrap();
            let b = fixed.write(q).unwrap();
            assert!(
                a.duty.abs_diff(b.duty) <= 1,
                "{mode:?} {newtons} N: {} vs {}",
                a.duty,
                b.duty
            );
            assert_eq!((a.saturated, a.reverse), (b.saturated, b.reverse));
            let step = 2.0 * 2.0 / 4095.0;
            assert!(
                // One duty step, plus the Q16 resolution of duty/max.
                (b.force.to_f32() * units.force - a.force).abs() <= step + 1e-4,
                "{mode:?} {newtons} N"
            );
        }
    }
    assert_eq!(
        PwmForce::<_, Q16>::with_units(Recorder::new(1), 1e6, DutyMode::Centered, units)
            .unwrap_err(),
        ConfigError(Setting::FullScale)
    );
}

/// A driver error comes back as the crate's one per-sample error, with the
/// driver's `ErrorKind`.
#[test]
fn driver_error_is_a_sample_error() {
    use embedded_hal::pwm::{Error, ErrorKind};

    #[derive(Debug)]
    struct Broken;
    impl Error for Broken {
        fn kind(&self) -> ErrorKind {
            ErrorKind::Other
        }
    }
    struct Failing;
    impl ErrorType for Failing {
        type Error = Broken;
    }
    impl SetDutyCycle for Failing {
        fn max_duty_cycle(&self) -> u16 {
            100
        }
        fn set_duty_cycle(&mut self, _: u16) -> Result<(), Self::Error> {
            Err(Broken)
        }
    }

    let mut out = PwmForce::new(Failing, 1.0, DutyMode::Centered).unwrap();
    let e = out.write(0.5).unwrap_err();
    assert_eq!(e, SampleError::Pwm(ErrorKind::Other));
    assert!(e.to_string().starts_with("PWM driver error: "), "{e}");
    assert_eq!(out.write(f32::INFINITY), Err(SampleError::Force));
}
