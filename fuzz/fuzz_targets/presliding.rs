//! The presliding state machine fed arbitrary parameters and samples (any
//! f32 bit pattern) in f32 and Q16.16, with f32 positions, i64 counts and
//! the closing memory. Invariants: a finite sample is accepted and gives a
//! finite force with |H| ≤ Fs; a non-finite sample is rejected and leaves
//! the state unchanged.
#![no_main]

use breakaway::{Model, Presliding, Q16};
use libfuzzer_sys::fuzz_target;

#[path = "common.rs"]
mod common;

fuzz_target!(|data: &[u8]| {
    let mut words = common::Words(data);
    let Some(params) = words.params() else { return };
    let Ok(model) = Model::<f32>::new(params) else { return };
    let fixed = Model::<Q16>::new(params).ok();
    let scale = params.z_max / 1000.0;
    let (Ok(mut metres), Ok(mut counts)) = (
        Presliding::<f32>::new(0.0, 1.0),
        Presliding::<i64, f32, 4>::new(0, scale),
    ) else {
        return;
    };
    let mut fixed_axis = fixed
        .as_ref()
        .and_then(|m| m.position_scale::<i32>(scale))
        .and_then(|s| Presliding::<i32, Q16, 2>::new(0, s).ok());
    // |H| ≤ Fs up to the rounding of H_r + (d·S − H_r)·g.
    let fs_bound = params.fs * (1.0 + 4.0 * f32::EPSILON);
    while let (Some(x), Some(v)) = (words.f32(), words.f32()) {
        let finite = x.is_finite() && v.is_finite();
        // f32 positions in metres.
        let before = metres.clone();
        match metres.update(&model, x, v) {
            Ok(f) => {
                assert!(finite, "accepted a non-finite sample {x} {v}");
                assert!(f.is_finite(), "F = {f} for x = {x}, v = {v}, {params:?}");
                assert!(metres.dry().abs() <= fs_bound, "|H| = {} > Fs", metres.dry());
            }
            Err(_) => {
                assert!(!finite, "rejected a finite sample {x} {v}");
                assert_eq!(metres, before, "a rejected sample changed the state");
            }
        }
        // Encoder counts (the position word's bits) with the closing memory.
        let count = i64::from(x.to_bits() as i32);
        let before = counts.clone();
        match counts.update(&model, count, v) {
            Ok(f) => {
                assert!(v.is_finite() && f.is_finite(), "F = {f} for v = {v}, {params:?}");
                assert!(counts.dry().abs() <= fs_bound, "|H| = {} > Fs", counts.dry());
                assert!(counts.memory_len() <= 4);
            }
            Err(_) => {
                assert!(!v.is_finite(), "rejected a finite velocity {v}");
                assert_eq!(counts, before, "a rejected sample changed the state");
            }
        }
        // Q16.16: any bit pattern is a valid number; H stays within ±Fs.
        if let (Some(model), Some(axis)) = (fixed.as_ref(), fixed_axis.as_mut()) {
            let v = Q16::from_bits(v.to_bits() as i32);
            let f = axis.update(model, count as i32, v);
            assert!(f.is_ok(), "Q16 rejected a sample");
            assert!(axis.dry().to_f32().abs() <= 1.0 + 1.0 / 65536.0, "|H| = {:?}", axis.dry());
        }
    }
});
