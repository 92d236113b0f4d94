//! The compensation blocks with arbitrary settings and signals. Invariants:
//! settings are validated (an error, never a panic); finite signals give
//! finite outputs within their documented bounds; a rejected signal leaves
//! the state unchanged.
#![no_main]

use breakaway::compensation::{
    AdaptationConfig, BreakAwayDetector, DetectorConfig, DisturbanceObserver, Feedforward,
    FeedforwardConfig, LevelAdaptation, ObserverConfig,
};
use breakaway::{Model, Variant};
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    let mut w = common::Words(data);
    let Some(params) = w.params() else { return };
    let Ok(model) = Model::<f32>::new(params) else { return };
    let (Some(gain), Some(deadband), Some(limit)) = (w.f32(), w.f32(), w.f32()) else { return };
    let feedforward = FeedforwardConfig { gain, deadband, limit };
    let (Some(mass), Some(bandwidth), Some(period)) = (w.f32(), w.f32(), w.f32()) else { return };
    let observer = ObserverConfig { mass, bandwidth, period };
    let adaptation = AdaptationConfig {
        rate: w.f32().unwrap_or(1.0),
        min_scale: w.f32().unwrap_or(0.5),
        max_scale: w.f32().unwrap_or(2.0),
        min_speed: w.f32().unwrap_or(1e-3),
        period,
    };
    let detector = DetectorConfig {
        period,
        rest_speed: w.f32().unwrap_or(1e-5),
        break_away_speed: w.f32().unwrap_or(1e-3),
        min_rate: w.f32().unwrap_or(0.01),
    };
    let mut ff = Feedforward::<f32, f32, 2>::new(feedforward, 0.0, 1.0).ok();
    let mut obs = DisturbanceObserver::new(observer).ok();
    let mut ad = LevelAdaptation::new(adaptation).ok();
    let mut det = BreakAwayDetector::<4>::new(detector, &model, Variant::Consistent, 0.95).ok();
    while let (Some(a), Some(b), Some(c)) = (w.f32(), w.f32(), w.f32()) {
        let finite = a.is_finite() && b.is_finite() && c.is_finite();
        if let Some(ff) = ff.as_mut() {
            let before = ff.clone();
            match ff.update(&model, a, b) {
                Ok(u) => {
                    assert!(u.is_finite() && u.abs() <= limit, "u_ff = {u}, limit {limit}");
                }
                Err(_) => {
                    assert!(!(a.is_finite() && b.is_finite()));
                    assert_eq!(*ff, before);
                }
            }
        }
        if let Some(obs) = obs.as_mut() {
            let before = obs.clone();
            match obs.update(a, b, c) {
                Ok(r) => assert!(r.is_finite() || !finite, "estimate {r}"),
                Err(_) => assert_eq!(*obs, before),
            }
        }
        if let Some(ad) = ad.as_mut() {
            let before = ad.clone();
            match ad.update(a, b, c, a > 0.0) {
                Ok(theta) => assert!(theta.is_finite() && theta >= adaptation.min_scale && theta <= adaptation.max_scale),
                Err(_) => assert_eq!(*ad, before),
            }
        }
        if let Some(det) = det.as_mut() {
            let before = format!("{det:?}");
            match det.update(&model, a, b) {
                Ok(Some(m)) => assert!(m.force.is_finite() && m.rate.is_finite()),
                Ok(None) => {}
                Err(_) => assert_eq!(format!("{det:?}"), before),
            }
        }
    }
});
