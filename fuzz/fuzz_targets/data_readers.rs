//! The measured-data readers of `breakaway-lab` (MODEL.md §6 CSV and the
//! EMPS .mat layout) on arbitrary bytes. Invariants: no panic; an accepted
//! record has equal column lengths, at least the minimum number of samples,
//! finite values and strictly increasing time.
#![no_main]

use std::path::Path;

use breakaway_lab::data::{parse_csv, read_mat, Record, MIN_SAMPLES};
use libfuzzer_sys::fuzz_target;

fn check(record: &Record) {
    let n = record.t.len();
    assert!(n >= MIN_SAMPLES, "{n} samples accepted");
    assert_eq!(record.u.len(), n);
    assert_eq!(record.x.len(), n);
    if let Some(v) = &record.v {
        assert_eq!(v.len(), n);
        assert!(v.iter().all(|v| v.is_finite()));
    }
    assert!(record.t.windows(2).all(|w| w[1] > w[0]), "time does not increase");
    assert!(record.t.iter().chain(&record.u).chain(&record.x).all(|v| v.is_finite()));
}

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Ok(record) = parse_csv(text, Path::new("fuzz.csv")) {
            check(&record);
        }
    }
    let path = std::env::temp_dir().join(format!("breakaway-fuzz-{}.mat", std::process::id()));
    if std::fs::write(&path, data).is_ok() {
        if let Ok(record) = read_mat(&path) {
            check(&record);
        }
    }
});
