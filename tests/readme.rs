//! The README's recipe (*Recipe: friction compensation in a velocity
//! loop*) as it runs: the README shows its code without hidden lines (GitHub
//! would show them), so the code stands here, in a module, where
//! `recipe_runs` calls it with a stand-in PWM channel and
//! `readme_shows_this_recipe` checks that the README's block is these
//! lines, character for character. The run needs `--features hal` (`cargo
//! xtask test` passes it); the comparison runs in every build.

/// This file and the README, as the package ships them.
const THIS_FILE: &str = include_str!("readme.rs");
const README: &str = include_str!("../README.md");

/// The lines of this file between the two marker lines, without the
/// module's indentation.
fn recipe_here() -> Vec<String> {
    let mut lines = THIS_FILE
        .lines()
        .skip_while(|l| l.trim() != "// README recipe: begin");
    lines.next();
    lines
        .take_while(|l| l.trim() != "// README recipe: end")
        .map(|l| l.strip_prefix("    ").unwrap_or(l).to_string())
        .collect()
}

/// The lines of the README's first code block after the heading
/// `## Recipe`.
fn recipe_in_readme() -> Vec<String> {
    let mut lines = README
        .lines()
        .skip_while(|l| !l.starts_with("## Recipe"))
        .skip_while(|l| !l.starts_with("```rust"));
    lines.next();
    lines
        .take_while(|l| !l.starts_with("```"))
        .map(str::to_string)
        .collect()
}

#[test]
fn readme_shows_this_recipe() {
    let (here, readme) = (recipe_here(), recipe_in_readme());
    // Both found, and the whole loop in them (not two empty blocks).
    assert!(here.len() > 40, "markers not found in tests/readme.rs");
    assert!(readme.len() > 40, "recipe block not found in README.md");
    for (i, (a, b)) in here.iter().zip(&readme).enumerate() {
        assert_eq!(
            a,
            b,
            "line {} of the recipe differs (tests/readme.rs, README.md)",
            i + 1
        );
    }
    assert_eq!(here.len(), readme.len(), "the recipe's length differs");
}

#[cfg(feature = "hal")]
#[path = "support/pwm.rs"]
mod pwm;
#[cfg(feature = "hal")]
mod support;

/// The README's lines, as they stand there.
#[cfg(feature = "hal")]
#[rustfmt::skip] // the README's layout
mod recipe {
    // README recipe: begin
    use breakaway::compensation::{DisturbanceObserver, Feedforward, FeedforwardConfig, ObserverConfig,
        VelocityConfig, VelocityEstimator};
    use breakaway::hal::{DutyMode, PwmForce, SetDutyCycle};
    use breakaway::{Error, Model, Params};

    const PERIOD: f32 = 1e-3; // control period T [s]
    const COUNT: f32 = 1e-8;  // encoder resolution [m per count]

    /// The velocity loop of one axis: `timer` is the motor driver's PWM channel, `encoder`
    /// the raw encoder count once per control period (in firmware: the hardware counter,
    /// read in the period's interrupt). Returns the last feedforward [N].
    pub fn velocity_loop(
        timer: impl SetDutyCycle,
        encoder: impl IntoIterator<Item = i32>,
    ) -> Result<f32, Error> {
        // At start-up. The parameters are checked here, once; the loop cannot fail on them.
        let model = Model::<f32>::new(Params {
            fc: 1.0,          // Coulomb level Fc [N]
            fs: 1.5,          // stiction level Fs [N]
            v_stribeck: 1e-3, // Stribeck velocity V [m/s]
            delta: 1.0,       // shape exponent δ
            sigma: 0.0,       // viscous coefficient σ [N·s/m]
            z_max: 1e-5,      // presliding distance [m]
            epsilon: 0.0,     // turning-point deadband [m]
        })?;
        // Presliding feedforward on the raw encoder count (i32, may wrap), idle at count 0.
        let mut feedforward = Feedforward::<i32>::new(FeedforwardConfig::default(), 0, COUNT)?;
        // Velocity from the raw encoder count: bandwidth ω_e [rad/s], period T [s].
        let config = VelocityConfig { bandwidth: 3000.0, period: PERIOD };
        let mut velocity = VelocityEstimator::<i32>::new(config, COUNT)?;
        // Disturbance observer: nominal mass m_n [kg], bandwidth g [rad/s], period T [s].
        let config = ObserverConfig { mass: 2.0, bandwidth: 100.0, period: PERIOD };
        let mut observer = DisturbanceObserver::new(config)?;
        // The PWM channel as a force output: duty 50 % = 0 N, 0 % / 100 % = ∓5 N.
        let mut output = PwmForce::new(timer, 5.0, DutyMode::Centered)?;

        let (kp, ki) = (200.0, 4000.0); // velocity PI gains [N·s/m], [N/m]
        let v_ref = 5e-3;               // velocity set-point [m/s]
        let mut integral = 0.0f32;
        let (mut applied, mut u_ff) = (0.0f32, 0.0f32);

        for count in encoder { // once per control period
            // 1. Velocity from the encoder (differences of the hardware counter, which
            //    may wrap, through a critically damped α–β filter).
            let v = velocity.update(count)?;
            // 2. Observer: the force applied in the period that just ended (all of it,
            //    as the PWM wrote it), the velocity now, and the "explained" force, the
            //    feedforward that was part of it. r is the friction the model missed.
            let r = observer.update(applied, v, u_ff)?;
            // 3. Feedforward for the coming period: the model's friction at this
            //    position and velocity (in a position loop: the reference x_ref, v_ref).
            u_ff = feedforward.update(&model, count, v)?;
            // 4. Controller output + feedforward + residual r, to the PWM.
            let error = v_ref - v;
            integral += error * PERIOD;
            let written = output.write(kp * error + ki * integral + u_ff + r)?;
            applied = written.force; // after saturation and rounding to the duty step
        }
        Ok(u_ff)
    }
    // README recipe: end
}

/// The recipe on the counts of an axis that starts from rest and slides at
/// 5 mm/s (10 nm counts, one per millisecond).
#[cfg(feature = "hal")]
#[test]
fn recipe_runs() -> Result<(), breakaway::Error> {
    let encoder = support::RECIPE_COUNTS;
    let mut timer = pwm::Timer { duty: 0 };
    let u_ff = recipe::velocity_loop(&mut timer, encoder)?;
    // Sliding now: F = S(v), between Fc and Fs.
    assert!(u_ff > 1.0 && u_ff < 1.5, "{u_ff}");
    // A forward force on the timer.
    assert!(timer.duty > 2048, "{}", timer.duty);
    Ok(())
}
