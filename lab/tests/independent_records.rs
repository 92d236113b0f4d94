//! The discrepancy workflow on the four example records of an outside
//! generator (`shared/data/independent/`, written from MODEL.md alone by
//! code that shares nothing with this repository). Each record's truth file
//! names its hidden effects in its first comment line; the check compares
//! `diagnose --json` against it: the effect-free record names nothing, and
//! `offset` and `frictional_lag` are named exactly with the gap (model error
//! above the noise-and-resolution floor) at most half of what it was.
//! `servo_dwell` (dwell_stiction at 8.1× the noise) is not identified today:
//! the check asserts only that nothing else is named there.

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
    let out = tmp(&format!("indep_{name}.json"));
    let o = Command::new(BIN)
        .arg("diagnose")
        .arg(dir().join(format!("{name}.csv")))
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

#[test]
fn outside_generator_examples() {
    if !dir().join("servo_null.csv").exists() {
        println!("note: {} not found; skipped", dir().display());
        return;
    }
    let mut exact = 0;
    for name in ["servo_null", "servo_offset", "servo_lag", "servo_dwell"] {
        let truth = hidden(name);
        let rep = diagnose(name);
        let got = named(&rep);
        let (before, after) = (
            rep["rms_before"].as_f64().unwrap(),
            rep["rms_after"].as_f64().unwrap(),
        );
        println!(
            "{name}: hidden {truth:?}, named {got:?}, gap {before:.4} -> {after:.4} N, floor {:.4} N",
            rep["floor"].as_f64().unwrap()
        );
        let mut t = truth.clone();
        t.sort();
        if name == "servo_dwell" {
            assert!(got.is_empty() || got == t, "{name}: named {got:?}");
            continue;
        }
        assert_eq!(got, t, "{name}");
        if !t.is_empty() {
            assert!(after <= 0.5 * before, "{name}: gap {before} -> {after}");
        }
        exact += 1;
    }
    assert_eq!(exact, 3);
}
