//! Runs the `breakaway-lab` binary: JSON keys, tables, and one-line errors with
//! the right exit codes on bad input (never a panic).

use std::process::Output;

mod common;
use common::{error_line, fig5, run, tmp};

fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).unwrap()
}

/// Runs `command --model <fig5.toml> ARGS --json`, asserts success and
/// returns the rows of the JSON array it prints.
fn fig5_json(command: &str, args: &[&str]) -> Vec<serde_json::Value> {
    let model = fig5();
    let mut argv = vec![command, "--model", &model];
    argv.extend_from_slice(args);
    argv.push("--json");
    let o = run(&argv);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_str(&stdout(&o)).unwrap()
}

/// Asserts that the JSON object `row` has every key of `keys`.
fn assert_keys(row: &serde_json::Value, keys: &[&str]) {
    for key in keys {
        assert!(row.get(key).is_some(), "missing {key}");
    }
}

/// Asserts a failure with exit `code` and exactly one stderr line
/// `error: …` containing every needle; returns the line.
fn fails(args: &[&str], code: i32, needles: &[&str]) -> String {
    let o = run(args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(code), "{args:?}: {err}");
    assert!(o.stdout.is_empty(), "{args:?} printed to stdout");
    error_line(args, &o, needles)
}

fn temp_model(name: &str, text: &str) -> String {
    let path = tmp(name);
    std::fs::write(&path, text).unwrap();
    path.to_string_lossy().into_owned()
}

const GOOD: &str = "mass = 1.0\nfc = 1.0\nfs = 1.5\nv_stribeck = 1e-3\ndelta = 1.0\nsigma = 0.0\nz_max = 1e-5\nepsilon = 0.0\n";

#[test]
fn json_keys_and_rows() {
    let rows = fig5_json("breakaway", &["--k", "0.01,1:3:1"]);
    assert_eq!(rows.len(), 4 * 4);
    for r in &rows {
        let obj = r.as_object().unwrap();
        let mut keys: Vec<&str> = obj.keys().map(String::as_str).collect();
        keys.sort_unstable();
        assert_eq!(keys, ["f_ba", "k", "t_ba", "v_b", "variant"]);
        let f = obj["f_ba"].as_f64().unwrap();
        assert!((1.0..=1.5).contains(&f), "{f}");
    }
    let names: Vec<&str> = rows
        .iter()
        .map(|r| r["variant"].as_str().unwrap())
        .collect();
    assert_eq!(names[0], "coulomb");
    assert_eq!(names[15], "consistent");
    assert_eq!(rows[3]["k"].as_f64(), Some(3.0));
}

#[test]
fn json_dynamic_keys() {
    let args = ["--k", "1,3", "--dynamic", "--variant", "mean,consistent"];
    let rows = fig5_json("breakaway", &args);
    assert_eq!(rows.len(), 4);
    for r in &rows {
        let keys = [
            "variant", "k", "v_b", "f_ba", "t_ba", "f_ba_sim", "t_ba_sim",
        ];
        assert_keys(r, &keys);
        assert!(r["f_ba_sim"].as_f64().unwrap() > 0.0);
    }
    // The same simulation for every variant at the same k.
    assert_eq!(rows[0]["f_ba_sim"], rows[2]["f_ba_sim"]);
    assert_eq!(rows[1]["t_ba_sim"], rows[3]["t_ba_sim"]);
}

#[test]
fn table_has_header_and_rows() {
    let o = run(&[
        "breakaway",
        "--model",
        &fig5(),
        "--k",
        "0.01:30:2",
        "--variant",
        "mean",
    ]);
    assert!(o.status.success());
    let text = stdout(&o);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 1 + 15);
    for h in ["variant", "k [N/s]", "v_b [m/s]", "F_ba [N]", "t_ba [s]"] {
        assert!(lines[0].contains(h));
    }
    assert!(!lines[0].contains("sim"));
    assert!(lines[1].starts_with("mean"));
    assert!(lines[15].contains("28.01"));
}

#[test]
fn validity_map_json() {
    let rows = fig5_json("validity-map", &["--masses", "0.1,1", "--k", "0.1,1"]);
    assert_eq!(rows.len(), 4);
    for r in &rows {
        assert_keys(
            r,
            &["m", "pi", "k", "lambda", "f_ba_sim", "t_ba_sim", "variants"],
        );
        for var in ["mean", "consistent"] {
            assert!(r["variants"][var]["f_ba"].as_f64().is_some());
            assert!(r["variants"][var]["drift"].as_f64().is_some());
        }
    }
    // Λ ∝ m·k² (MODEL.md §4): m = 1 kg, k = 1 N/s, F̂ = 1.25 N, z_max = 1e-5 m.
    let lambda = rows[3]["lambda"].as_f64().unwrap();
    let expect = 1e-5 / (1.25f64.powi(3) * 0.95 * 0.95f64.ln().abs().powi(3));
    assert!((lambda / expect - 1.0).abs() < 1e-12);
    // Π = √(2·Fs·z_max/m)/V (MODEL.md §8).
    let pi = rows[3]["pi"].as_f64().unwrap();
    assert!((pi - (3e-5f64).sqrt() / 1e-3).abs() < 1e-9);
    let table = stdout(&run(&[
        "validity-map",
        "--model",
        &fig5(),
        "--masses",
        "1",
        "--k",
        "1",
    ]));
    assert!(table.contains("Π"));
    assert!(table.contains("drift_consistent"));
}

#[test]
fn usage_errors_exit_2() {
    let m = fig5();
    fails(&[], 2, &["subcommand"]);
    fails(&["breakaway", "--model", &m], 2, &["--k"]);
    fails(&["breakaway", "--k", "1"], 2, &["--model"]);
    fails(
        &["breakaway", "--model", &m, "--k", "0"],
        2,
        &["--k", "> 0"],
    );
    fails(&["breakaway", "--model", &m, "--k", "-1,2"], 2, &["--k"]);
    fails(
        &["breakaway", "--model", &m, "--k", "1:x:1"],
        2,
        &["--k", "x"],
    );
    fails(
        &["breakaway", "--model", &m, "--k", "1", "--wb", "1.5"],
        2,
        &["--wb"],
    );
    fails(
        &["breakaway", "--model", &m, "--k", "1", "--wb", "0"],
        2,
        &["--wb"],
    );
    fails(
        &["breakaway", "--model", &m, "--k", "1", "--variant", "x"],
        2,
        &["--variant"],
    );
    fails(
        &["breakaway", "--model", &m, "--k", "1", "--frobnicate"],
        2,
        &["--frobnicate"],
    );
    fails(
        &["validity-map", "--model", &m, "--masses", "0"],
        2,
        &["--masses"],
    );
    // Beyond the library's range: the setting is named, not only the
    // library's field.
    fails(
        &["closed-loop", "--velocity-bandwidth", "1e300"],
        2,
        &["velocity bandwidth", "out of range"],
    );
    // A rate so small that the time to break away overflows.
    fails(
        &["breakaway", "--model", &m, "--k", "1e-320"],
        1,
        &["not finite"],
    );
}

#[test]
fn help_succeeds() {
    let o = run(&["--help"]);
    assert!(o.status.success());
    assert!(stdout(&o).contains("validity-map"));
}

#[test]
fn missing_model_file_names_it() {
    fails(
        &["breakaway", "--model", "/no/such/model.toml", "--k", "1"],
        1,
        &["/no/such/model.toml"],
    );
}

#[test]
fn invalid_model_files_name_the_key() {
    // (file, text, what the error names)
    let cases = [
        ("unknown_key.toml", format!("{GOOD}fcc = 2.0\n"), "fcc"),
        ("bad_fs.toml", GOOD.replace("fs = 1.5", "fs = 0.5"), "fs"),
        (
            "bad_v.toml",
            GOOD.replace("v_stribeck = 1e-3", "v_stribeck = -1e-3"),
            "v_stribeck",
        ),
        ("syntax.toml", "fc = = 1\n".to_string(), "syntax.toml"),
        (
            "no_presliding.toml",
            GOOD.replace("z_max = 1e-5", "z_max = 0.0"),
            "z_max",
        ),
        (
            "bad_effect.toml",
            format!("{GOOD}[effects.asymmetry]\na = 1.5\n"),
            "asymmetry",
        ),
        // A valid §5 addition the break-away prediction does not include.
        (
            "with_offset.toml",
            format!("{GOOD}[effects.offset]\nf0 = 0.5\n"),
            "[effects.offset]",
        ),
    ];
    for (file, text, needle) in cases {
        let model = temp_model(file, &text);
        fails(&["breakaway", "--model", &model, "--k", "1"], 1, &[needle]);
    }
}
