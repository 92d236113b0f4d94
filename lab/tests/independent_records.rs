//! The discrepancy workflow on the four example records of an outside
//! generator (`shared/data/independent/`, written from MODEL.md alone by
//! code that shares nothing with this repository). Each record's truth file
//! names its hidden effects in its first comment line; the check compares
//! `diagnose --json` against it: the effect-free record names nothing, and
//! `offset` and `frictional_lag` are named exactly with the gap (model error
//! above the noise-and-resolution floor) at most half of what it was.
//! `servo_dwell` (dwell_stiction at 8.1× the noise) is not identified today:
//! the check asserts only that nothing else is named there. The same holds
//! for each half of each record (the first and the second 18–19 s, other
//! stretches of the excitation: a record the workflow has not seen whole).

use std::path::PathBuf;
use std::process::Command;

mod common;
use common::{tmp, BIN};

fn dir() -> PathBuf {
    common::shared_data("independent")
}

/// Hidden effects from the truth file's first line
/// (`# NAME: true model; hidden effects: a, b; …`).
fn hidden(name: &str) -> Vec<String> {
    let text = std::fs::read_to_string(dir().join(format!("{name}.truth.toml")))
        .expect("truth file readable");
    let first = text.lines().next().unwrap_or("");
    let list = first
        .split("hidden effects:")
        .nth(1)
        .and_then(|s| s.split(';').next())
        .expect("truth line names the hidden effects")
        .trim();
    if list == "none" {
        Vec::new()
    } else {
        list.split(',').map(|s| s.trim().to_string()).collect()
    }
}

fn diagnose(name: &str) -> serde_json::Value {
    diagnose_file(name, &dir().join(format!("{name}.csv")))
}

fn diagnose_file(name: &str, data: &std::path::Path) -> serde_json::Value {
    let out = tmp(&format!("indep_{name}.json"));
    let o = Command::new(BIN)
        .arg("diagnose")
        .arg(data)
        .arg("--json")
        .arg(&out)
        .output()
        .expect("runs");
    assert!(
        o.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap()
}

fn named(rep: &serde_json::Value) -> Vec<String> {
    let mut v: Vec<String> = rep["effects_added"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e.as_str().unwrap().to_string())
        .collect();
    v.sort();
    v
}

/// The static level of one report against the truth of `name`: what the
/// report reads off the still samples (each direction's held level) never
/// exceeds what the truth lets the axis hold (`Fs·(1 + |a|)`, plus `ΔFs`
/// where dwell is hidden), and the written `Fs` is not below the level both
/// directions held. On the whole of `servo_dwell` the axis held more than
/// the truth's `Fs` (its dwell raise, in the slow ramps near its end), and
/// the written `Fs` says so.
fn check_static_level(name: &str, label: &str, rep: &serde_json::Value) {
    let truth =
        breakaway_reference::Model::load(&dir().join(format!("{name}.truth.toml"))).unwrap();
    let e = &truth.effects;
    let cap = truth.fs * (1.0 + e.asymmetry.map_or(0.0, |a| a.a.abs()))
        + e.dwell_stiction.map_or(0.0, |d| d.delta_fs);
    let level = &rep["static_level"];
    let held: Vec<f64> = level["held"]
        .as_array()
        .expect("a static level")
        .iter()
        .map(|h| h.as_f64().expect("still samples both ways"))
        .collect();
    let written = rep["model"]["fs"].as_f64().unwrap();
    println!(
        "{label}: held {held:?} N, Fs fitted {} written {written} N, truth Fs {} (cap {cap}) N",
        level["fs_fitted"], truth.fs
    );
    for h in &held {
        assert!(
            *h <= 1.01 * cap,
            "{label}: held {h} N above the truth's {cap} N"
        );
    }
    let both = held[0].min(held[1]);
    assert!(
        written >= 0.99 * both,
        "{label}: Fs {written} N below the held {both} N"
    );
    if label == "servo_dwell" {
        assert!(written > truth.fs, "{label}: Fs {written} N");
    }
}

/// Checks one report against the truth of `name`: the effect-free and the
/// `offset` and `frictional_lag` records named exactly (the gap at least
/// halved where an effect is hidden); `servo_dwell` names nothing else.
/// Returns whether the record was named exactly.
fn check(name: &str, label: &str, rep: &serde_json::Value) -> bool {
    let mut truth = hidden(name);
    truth.sort();
    let got = named(rep);
    let (before, after) = (
        rep["rms_before"].as_f64().unwrap(),
        rep["rms_after"].as_f64().unwrap(),
    );
    println!(
        "{label}: hidden {truth:?}, named {got:?}, gap {before:.4} -> {after:.4} N, floor {:.4} N",
        rep["floor"].as_f64().unwrap()
    );
    check_static_level(name, label, rep);
    if name == "servo_dwell" {
        assert!(got.is_empty() || got == truth, "{label}: named {got:?}");
        return got == truth;
    }
    assert_eq!(got, truth, "{label}");
    if !truth.is_empty() {
        assert!(after <= 0.5 * before, "{label}: gap {before} -> {after}");
    }
    true
}

const RECORDS: [&str; 4] = ["servo_null", "servo_offset", "servo_lag", "servo_dwell"];

#[test]
fn outside_generator_examples() {
    if common::shared_or_skip("independent/servo_null.csv").is_none() {
        return;
    }
    let exact = RECORDS
        .iter()
        .filter(|&&name| check(name, name, &diagnose(name)))
        .count();
    assert_eq!(exact, 3);
}

/// Each record cut in two halves in time, each half diagnosed alone.
#[test]
fn outside_generator_examples_by_halves() {
    if common::shared_or_skip("independent/servo_null.csv").is_none() {
        return;
    }
    let mut exact = 0;
    for name in RECORDS {
        let rec = breakaway_lab::data::load(&dir().join(format!("{name}.csv"))).unwrap();
        let n = rec.len();
        for (k, (lo, hi)) in [(0, n / 2), (n / 2, n)].into_iter().enumerate() {
            let half = breakaway_lab::data::Record {
                t: rec.t[lo..hi].to_vec(),
                u: rec.u[lo..hi].to_vec(),
                x: rec.x[lo..hi].to_vec(),
                v: None,
                source: format!("{name} half {}", k + 1),
            };
            let label = format!("{name}_{}", k + 1);
            let path = tmp(&format!("indep_{label}.csv"));
            breakaway_lab::data::write_csv(&path, &half, &[]).unwrap();
            exact += usize::from(check(name, &label, &diagnose_file(&label, &path)));
        }
    }
    assert_eq!(exact, 6);
}
