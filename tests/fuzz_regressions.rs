//! Inputs that `cargo xtask fuzz` found failing, kept as regression tests.

use breakaway::compensation::{Feedforward, FeedforwardConfig};
use breakaway::{Model, Params};

/// compensation target, crash-77ff5fb3: with σ = 5.3e35 N·s/m and
/// v_ref = −1.7e38 m/s the friction saturates at −f32::MAX, and
/// f − H overflowed to ∞; with gain 0 the feedforward returned 0·∞ = NaN.
/// Each product is now saturated before the sum.
#[test]
fn feedforward_with_extreme_settings_stays_finite() {
    let model = Model::<f32>::new(Params {
        fc: 3.251_395_8e35,
        fs: 3.251_412e35,
        v_stribeck: 3.251_395_8e35,
        delta: 2.415_608_4e35,
        sigma: 5.308_563_4e35,
        z_max: 1.124_786_7e-38,
        epsilon: 0.0,
    })
    .unwrap();
    let limit = 5.308_515e35;
    for gain in [0.0, 1.0, 3.4e38] {
        let config = FeedforwardConfig {
            gain,
            deadband: 0.0,
            limit,
        };
        let mut ff = Feedforward::<f32, f32, 2>::new(config, 0.0, 1.0).unwrap();
        for (x, v) in [
            (6.162_976e-33, -1.701_411_8e38),
            (3.251_395_8e35, -48_884_200.0),
        ] {
            let u = ff.update(&model, x, v).unwrap();
            assert!(u.is_finite() && u.abs() <= limit, "gain {gain}: u_ff = {u}");
        }
    }
}
