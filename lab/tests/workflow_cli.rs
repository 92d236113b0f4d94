//! The discrepancy workflow's command line: synth → fit → validate →
//! diagnose on a small synthetic record, the JSON report's keys, and bad
//! input (one-line errors naming file and line/column, non-zero exit, no
//! panic, inputs untouched).

use std::path::PathBuf;

mod common;
use common::{error_line, run};

fn tmp(name: &str) -> PathBuf {
    common::tmp(&format!("wf_{name}"))
}

fn ok(args: &[&str]) -> String {
    let o = run(args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{args:?}: {err}");
    String::from_utf8(o.stdout).unwrap()
}

/// Exit code 1 or 2, exactly one stderr line `error: …` with every needle.
fn fails(args: &[&str], needles: &[&str]) -> String {
    let o = run(args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(matches!(o.status.code(), Some(1 | 2)), "{args:?}: {err}");
    error_line(args, &o, needles)
}

fn write(name: &str, text: &str) -> String {
    common::write(&format!("wf_{name}"), text)
}

/// Steady-state readings `|u| = 1 + v` at 12 speeds both ways.
fn steady_csv() -> String {
    let mut steady = String::from("v,u\n");
    for k in 1..=12 {
        let v = f64::from(k) * 1e-3;
        steady.push_str(&format!("{v},{}\n-{v},-{}\n", 1.0 + v, 1.0 + v));
    }
    steady
}

fn good_csv(n: usize) -> String {
    let mut s = String::from("# comment\nx,t,u,extra\n");
    for i in 0..n {
        let t = i as f64 * 1e-3;
        s.push_str(&format!(
            "{},{t},{},7\n",
            1e-3 * (t * 3.0).sin(),
            (t * 3.0).cos()
        ));
    }
    s
}

#[test]
fn synth_fit_validate_diagnose() {
    let data = tmp("offset.csv");
    let truth = tmp("offset_truth.toml");
    let (d, t) = (data.to_str().unwrap(), truth.to_str().unwrap());
    let out = ok(&[
        "synth", "--effect", "offset", "--seed", "2", "--out", d, "--truth", t,
    ]);
    assert!(out.contains("samples written"));
    let text = std::fs::read_to_string(&data).unwrap();
    assert!(text.starts_with("# breakaway-lab synth --effect offset --seed 2"));
    let before = text.clone();

    // fit with the truth's structure recovers the offset.
    let fitted = tmp("offset_fit.toml");
    let j = ok(&[
        "fit",
        d,
        "--model",
        t,
        "--json",
        "--model-out",
        fitted.to_str().unwrap(),
    ]);
    let v: serde_json::Value = serde_json::from_str(&j).unwrap();
    let f0 = v["model"]["effects"]["offset"]["f0"].as_f64().unwrap();
    let truth_text = std::fs::read_to_string(&truth).unwrap();
    let m = breakaway_reference::Model::from_toml_str(&truth_text).unwrap();
    let f0_true = m.effects.offset.unwrap().f0;
    assert!(
        (f0 - f0_true).abs() < 0.1 * f0_true.abs(),
        "f0 {f0} vs {f0_true}"
    );
    assert!(v["rms_held_out"].as_f64().unwrap() < 0.05);

    // The weights are the data's, not the start's: from a start with both
    // levels doubled, the fit ends at the same model and reports the same
    // figures (with weights from the start, 0.000499 against 0.000488 N).
    let far = tmp("offset_far.toml");
    let mut m2 = m.clone();
    (m2.fc, m2.fs) = (2.0 * m.fc, 2.0 * m.fs);
    std::fs::write(&far, m2.to_toml_string()).unwrap();
    let j2 = ok(&["fit", d, "--model", far.to_str().unwrap(), "--json"]);
    let v2: serde_json::Value = serde_json::from_str(&j2).unwrap();
    let (fc1, fc2) = (
        v["model"]["fc"].as_f64().unwrap(),
        v2["model"]["fc"].as_f64().unwrap(),
    );
    assert!((fc1 - fc2).abs() < 1e-4 * fc1, "fc {fc1} vs {fc2}");
    let (h1, h2) = (
        v["rms_held_out"].as_f64().unwrap(),
        v2["rms_held_out"].as_f64().unwrap(),
    );
    assert!((h1 - h2).abs() < 1e-3 * h1, "held-out rms {h1} vs {h2}");

    // validate: the metric of the fitted model, per regime.
    let j = ok(&["validate", d, "--model", fitted.to_str().unwrap(), "--json"]);
    let v: serde_json::Value = serde_json::from_str(&j).unwrap();
    assert!(v["rms"].as_f64().unwrap() < 0.05);
    assert!(!v["regimes"].as_array().unwrap().is_empty());
    assert_eq!(v["bursts"]["unweighted"], false);
    // --unweigh-bursts: no weight on the bursts; on a record with none (a
    // smooth in-model record), the same figure.
    let j = ok(&[
        "validate",
        d,
        "--model",
        fitted.to_str().unwrap(),
        "--json",
        "--unweigh-bursts",
    ]);
    let u: serde_json::Value = serde_json::from_str(&j).unwrap();
    assert_eq!(u["bursts"]["unweighted"], true);
    assert_eq!(v["bursts"]["samples"], 0);
    assert_eq!(u["bursts"]["samples"], 0);
    assert_eq!(u["rms"], v["rms"]);

    // diagnose: names the offset, JSON keys of issue 6, SVG, model file.
    let (rep, svg, mo) = (tmp("rep.json"), tmp("plot.svg"), tmp("diag.toml"));
    let text = ok(&[
        "diagnose",
        d,
        "--json",
        rep.to_str().unwrap(),
        "--svg",
        svg.to_str().unwrap(),
        "--model-out",
        mo.to_str().unwrap(),
    ]);
    // The offset is named, or its look-alike `asymmetry` with the report
    // saying that `offset` fits as well (on this record the two tie:
    // model errors equal to four digits, 0.0345 N; lab/README.md known
    // gaps).
    assert!(
        text.contains("missing effect `offset`") || text.contains("`offset` fits as well"),
        "{text}"
    );
    assert!(text.contains("largest disagreement"));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&rep).unwrap()).unwrap();
    for key in [
        "effects_added",
        "metric",
        "rms_before",
        "rms_after",
        "regions",
        "steps",
        "model",
    ] {
        assert!(v.get(key).is_some(), "missing key {key}");
    }
    // The level shift comes first: `offset`, or `asymmetry` tied with it.
    let first = &v["steps"][0];
    assert!(
        first["effect"] == "offset"
            || (first["effect"] == "asymmetry" && first["tied_with"] == "offset"),
        "{first}"
    );
    assert!(
        v["effects_added"].as_array().unwrap().len() <= 2,
        "{}",
        v["effects_added"]
    );
    let r0 = &v["regions"][0];
    for key in ["regime", "t_start", "t_end", "rms"] {
        assert!(r0.get(key).is_some(), "regions lack {key}");
    }
    let s0 = &v["steps"][0];
    for key in ["effect", "params", "rms_before", "rms_after", "score"] {
        assert!(s0.get(key).is_some(), "steps lack {key}");
    }
    assert!(v["rms_after"].as_f64().unwrap() < 0.5 * v["rms_before"].as_f64().unwrap());
    assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
    let back = breakaway_reference::Model::load(&mo).unwrap();
    assert!(back.effects.offset.is_some() || back.effects.asymmetry.is_some());
    // The input was not touched.
    assert_eq!(std::fs::read_to_string(&data).unwrap(), before);
    // Refuses to overwrite its input.
    fails(
        &["diagnose", d, "--model-out", d],
        &["refusing to overwrite"],
    );
    assert_eq!(std::fs::read_to_string(&data).unwrap(), before);

    // An output `-` goes to standard output in place of the text report,
    // byte for byte what the file gets (not a file named `-`).
    let piped = ok(&["diagnose", d, "--json", "-"]);
    assert_eq!(piped, std::fs::read_to_string(&rep).unwrap());
    let piped = ok(&["fit", d, "--model", t, "--model-out", "-"]);
    assert_eq!(piped, std::fs::read_to_string(&fitted).unwrap());
    let piped = ok(&["synth", "--effect", "offset", "--seed", "2", "--out", "-"]);
    assert_eq!(piped, before);
    assert!(!std::path::Path::new("-").exists());
    fails(
        &["diagnose", d, "--json", "-", "--model-out", "-"],
        &["`-` (standard output) given to two outputs"],
    );
    fails(
        &["fit", d, "--json", "--model-out", "-"],
        &["both print to standard output"],
    );
}

#[test]
fn bad_csv_input() {
    let missing = write("missing.csv", "t,u\n0,1\n");
    fails(
        &["validate", &missing, "--model", "m.toml"],
        &["missing.csv", "line 1", "`x`"],
    );
    let g = good_csv(400);
    let mut lines: Vec<String> = g.lines().map(String::from).collect();
    lines[100] = lines[99].clone(); // repeats t
    let nonincr = write("nonincr.csv", &lines.join("\n"));
    fails(
        &["fit", &nonincr],
        &["nonincr.csv", "line 101", "`t`", "does not increase"],
    );
    let mut lines: Vec<String> = g.lines().map(String::from).collect();
    let f: Vec<String> = lines[50].split(',').map(String::from).collect();
    lines[50] = format!("{},{},NaN,{}", f[0], f[1], f[3]);
    let nan = write("nan.csv", &lines.join("\n"));
    fails(&["fit", &nan], &["nan.csv", "line 51", "`u`", "not finite"]);
    let mut lines: Vec<String> = g.lines().map(String::from).collect();
    let f: Vec<&str> = lines[70].split(',').collect();
    lines[70] = format!("inf,{},{},{}", f[1], f[2], f[3]);
    let inf = write("inf.csv", &lines.join("\n"));
    fails(
        &["diagnose", &inf],
        &["inf.csv", "line 71", "`x`", "not finite"],
    );
    let mut lines: Vec<String> = g.lines().map(String::from).collect();
    lines[30] = "1,abc,2,3".into();
    let text = write("text.csv", &lines.join("\n"));
    fails(
        &["diagnose", &text],
        &["text.csv", "line 31", "`t`", "`abc` is not a number"],
    );
    let few = write("few.csv", &good_csv(20));
    fails(&["diagnose", &few], &["few.csv", "too few samples"]);
    let short_row = write("short.csv", "t,u,x\n0,1,2\n0.001,1\n");
    fails(
        &["fit", &short_row],
        &["short.csv", "line 3", "`x` missing"],
    );
    fails(
        &["fit", &tmp("nope.csv").to_string_lossy()],
        &["nope.csv", "cannot read"],
    );
    fails(&["fit", "--model"], &["--model", "a value is required"]);
    fails(&["diagnose", "a.csv", "--candidates", "magic"], &["magic"]);
    fails(
        &["synth", "--effect", "magic", "--out", "x.csv"],
        &["magic"],
    );
    fails(&["synth", "--effect", "offset"], &["--out"]);
    fails(
        &["synth", "--effect", "none,offset", "--out", "x.csv"],
        &["`none` stands alone"],
    );
    let cr = write("cr_only.csv", &good_csv(400).replace('\n', "\r"));
    fails(&["fit", &cr], &["cr_only.csv", "carriage return"]);
    fails(&["validate", "a.csv"], &["--model"]);
}

#[test]
fn bad_model_file() {
    let data = write("ok.csv", &good_csv(400));
    let bad = write("bad_model.toml", "mass = 1.0\nfc = 1.0\n");
    fails(
        &["validate", &data, "--model", &bad],
        &["bad_model.toml", "fs", "missing"],
    );
    let bad = write("bad_key.toml", "mass = 1.0\nfc = 1.0\nfs = 0.5\nv_stribeck = 1e-3\ndelta = 1.0\nsigma = 0.0\nz_max = 1e-5\nepsilon = 0.0\n");
    fails(
        &["diagnose", &data, "--model", &bad],
        &["bad_key.toml", "fs", ">= fc"],
    );
    let bad = write("syntax.toml", "mass = = 1\n");
    fails(&["fit", &data, "--model", &bad], &["syntax.toml", "line 1"]);
}

/// A MATLAB v5 file with uncompressed real double arrays.
fn mat_file(vars: &[(&str, Vec<f64>)]) -> Vec<u8> {
    let mut b = vec![b' '; 116];
    b[..20].copy_from_slice(b"MATLAB 5.0 MAT-file ");
    b.extend_from_slice(&[0u8; 8]);
    b.extend_from_slice(&0x0100u16.to_le_bytes());
    b.extend_from_slice(b"IM");
    let pad = |v: &mut Vec<u8>| {
        while v.len() & 7 != 0 {
            v.push(0);
        }
    };
    for (name, data) in vars {
        let mut e = Vec::new();
        let tag = |e: &mut Vec<u8>, ty: u32, n: usize| {
            e.extend_from_slice(&ty.to_le_bytes());
            e.extend_from_slice(&(n as u32).to_le_bytes());
        };
        tag(&mut e, 6, 8); // array flags
        e.extend_from_slice(&6u32.to_le_bytes()); // mxDOUBLE_CLASS
        e.extend_from_slice(&0u32.to_le_bytes());
        tag(&mut e, 5, 8); // dimensions
        e.extend_from_slice(&(data.len() as i32).to_le_bytes());
        e.extend_from_slice(&1i32.to_le_bytes());
        tag(&mut e, 1, name.len());
        e.extend_from_slice(name.as_bytes());
        pad(&mut e);
        tag(&mut e, 9, 8 * data.len());
        for x in data {
            e.extend_from_slice(&x.to_le_bytes());
        }
        pad(&mut e);
        b.extend_from_slice(&14u32.to_le_bytes());
        b.extend_from_slice(&(e.len() as u32).to_le_bytes());
        b.extend_from_slice(&e);
    }
    b
}

#[test]
fn bad_mat_input() {
    let junk = tmp("junk.mat");
    std::fs::write(&junk, "this is not a MATLAB file").unwrap();
    fails(
        &["diagnose", junk.to_str().unwrap()],
        &["junk.mat", "not a readable MATLAB v5 file"],
    );
    let n = 500;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-3).collect();
    let x: Vec<f64> = t.iter().map(|t| 1e-3 * (3.0 * t).sin()).collect();
    let u: Vec<f64> = t.iter().map(|t| (3.0 * t).cos()).collect();
    // Missing `qm`.
    let p = tmp("noqm.mat");
    std::fs::write(
        &p,
        mat_file(&[("t", t.clone()), ("vir", u.clone()), ("gtau", vec![2.0])]),
    )
    .unwrap();
    fails(&["fit", p.to_str().unwrap()], &["noqm.mat", "`qm` missing"]);
    // Lengths differ.
    let p = tmp("len.mat");
    std::fs::write(
        &p,
        mat_file(&[
            ("t", t.clone()),
            ("qm", x[..400].to_vec()),
            ("vir", u.clone()),
            ("gtau", vec![2.0]),
        ]),
    )
    .unwrap();
    fails(
        &["fit", p.to_str().unwrap()],
        &["len.mat", "`qm` has 400 elements"],
    );
    // NaN inside.
    let mut xn = x.clone();
    xn[123] = f64::NAN;
    let p = tmp("nan.mat");
    std::fs::write(
        &p,
        mat_file(&[
            ("t", t.clone()),
            ("qm", xn),
            ("vir", u.clone()),
            ("gtau", vec![2.0]),
        ]),
    )
    .unwrap();
    fails(
        &["fit", p.to_str().unwrap()],
        &["nan.mat", "`qm`, element 124", "not finite"],
    );
    // A well-formed file is read (u = gtau·vir) and fitted.
    let p = tmp("ok.mat");
    std::fs::write(
        &p,
        mat_file(&[("t", t), ("qm", x), ("vir", u), ("gtau", vec![2.0])]),
    )
    .unwrap();
    let rec = breakaway_lab::data::load(&p).unwrap();
    assert_eq!(rec.len(), n);
    assert!((rec.u[0] - 2.0).abs() < 1e-12);
}

#[test]
fn static_curve_indy7_joint1() {
    let Some(f) = common::shared_or_skip("indy7/joint1_steady_state.csv") else {
        return;
    };
    let f = f.as_str();
    let j = ok(&["static-curve", f, "--json"]);
    let v: serde_json::Value = serde_json::from_str(&j).unwrap();
    let c = v["curves"].as_array().unwrap();
    assert_eq!(c.len(), 2);
    for c in c {
        assert!(c["rms"].as_f64().unwrap() < 4.0);
        assert!(c["fs"].as_f64().unwrap() >= c["fc"].as_f64().unwrap());
    }
}

/// Indy7 joint 1 (real data, both directions, steady-state layout):
/// `diagnose` names `nonlinear_viscous` with a concave exponent and takes
/// at least 70 % of the gap (issue 10's target); the gap is model error
/// above the readings' noise, not above the held-out rms.
#[test]
fn indy7_joint1_names_nonlinear_viscous() {
    let Some(f) = common::shared_or_skip("indy7/joint1_steady_state.csv") else {
        return;
    };
    let (rep, model) = (tmp("indy7_joint1.json"), tmp("indy7_joint1.toml"));
    let text = ok(&[
        "diagnose",
        f.as_str(),
        "--json",
        rep.to_str().unwrap(),
        "--model-out",
        model.to_str().unwrap(),
    ]);
    // A rotary joint: its units said, in the model file too (whose key
    // comments name the linear ones), and the file still reads back.
    assert!(text.contains("forces in N·m, speeds in rad/s"), "{text}");
    let toml = std::fs::read_to_string(&model).unwrap();
    assert!(toml.starts_with("# rotary joint"), "{toml}");
    breakaway_reference::Model::load(&model).unwrap();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&rep).unwrap()).unwrap();
    assert_eq!(v["units"], "N*m, rad/s");
    assert_eq!(
        v["effects_added"],
        serde_json::json!(["nonlinear_viscous"]),
        "{v}"
    );
    let n = v["model"]["effects"]["nonlinear_viscous"]["n"]
        .as_f64()
        .unwrap();
    assert!(n > 0.15 && n < 0.9, "n {n}");
    let (before, after) = (
        v["rms_before"].as_f64().unwrap(),
        v["rms_after"].as_f64().unwrap(),
    );
    assert!(after <= 0.3 * before, "{before} -> {after}");
    let (raw, floor) = (
        v["rms_raw_after"].as_f64().unwrap(),
        v["floor"].as_f64().unwrap(),
    );
    assert!(floor > 0.0 && after < raw, "{after} {raw} {floor}");
    assert!((after.powi(2) + floor.powi(2) - raw.powi(2)).abs() < 1e-9 * raw.powi(2));
}

/// The EMPS benchmark record (real data): `diagnose` names velocity
/// strengthening and an offset or asymmetry, writes no parameter at a bound,
/// halves the gap, and the fitted mass is within 2 % of the published one.
#[test]
fn emps_real_data() {
    let Some(f) = common::shared_or_skip("emps/DATA_EMPS.mat") else {
        return;
    };
    let f = f.as_str();
    let rep = tmp("emps.json");
    ok(&["diagnose", f, "--json", rep.to_str().unwrap()]);
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&rep).unwrap()).unwrap();
    let added: Vec<&str> = v["effects_added"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e.as_str().unwrap())
        .collect();
    // Velocity strengthening (`viscous`; `nonlinear_viscous` in earlier
    // versions, see lab/README.md) and a level shift between the
    // directions.
    assert!(
        (added.contains(&"viscous") || added.contains(&"nonlinear_viscous"))
            && (added.contains(&"offset") || added.contains(&"asymmetry")),
        "{added:?}"
    );
    // No parameter at a bound or non-physical in the written model.
    let m = &v["model"];
    let delta = m["delta"].as_f64().unwrap();
    assert!(delta > 0.31 && delta < 3.9, "delta {delta}");
    let vs = m["v_stribeck"].as_f64().unwrap();
    assert!(vs > 1e-6 && vs < 1.0, "v_stribeck {vs}");
    let (fc, fs) = (m["fc"].as_f64().unwrap(), m["fs"].as_f64().unwrap());
    let fs_max = (1.0 + breakaway_lab::fit::FS_EXCESS_MAX) * fc;
    assert!(
        fc > 0.0 && fs >= fc && fs < fc + 0.99 * (fs_max - fc),
        "fc {fc} fs {fs}"
    );
    if let Some(n) = m["effects"]["nonlinear_viscous"]["n"].as_f64() {
        assert!(n > 0.06 && n < 1.95 && (n - 1.0).abs() > 0.1, "n {n}");
    }
    let mass = v["model"]["mass"].as_f64().unwrap();
    assert!((mass - 95.1089).abs() < 0.02 * 95.1089, "mass {mass}");
    assert!(v["rms_after"].as_f64().unwrap() < 0.5 * v["rms_before"].as_f64().unwrap());
}

/// Hardening battery: malformed inputs of every kind give one `error:` line
/// naming the file, a non-zero exit, no panic, and leave the file as it was.
#[test]
fn malformed_input_battery() {
    let good = good_csv(400);
    let huge = good
        .replacen("\n0,", "\n1e400,", 1)
        .replace(",7\n", ",1e400\n");
    let mut cases: Vec<(String, Vec<u8>, Vec<&str>)> = vec![
        ("empty.csv".into(), Vec::new(), vec!["empty.csv"]),
        (
            "header_only.csv".into(),
            b"t,u,x\n".to_vec(),
            vec!["header_only.csv"],
        ),
        (
            "comments_only.csv".into(),
            b"# nothing\n# here\n".to_vec(),
            vec!["comments_only.csv"],
        ),
        (
            "semicolons.csv".into(),
            good.replace(',', ";").into_bytes(),
            vec!["semicolons.csv"],
        ),
        (
            "tabs.csv".into(),
            good.replace(',', "\t").into_bytes(),
            vec!["tabs.csv"],
        ),
        ("huge.csv".into(), huge.into_bytes(), vec!["huge.csv"]),
        (
            "binary.csv".into(),
            (0..=255u8).cycle().take(4096).collect(),
            vec!["binary.csv"],
        ),
        (
            "crlf_missing_x.csv".into(),
            b"t,u\r\n0,1\r\n".to_vec(),
            vec!["crlf_missing_x.csv", "`x`"],
        ),
    ];
    // A MATLAB file cut short, at several places (header, tag, data).
    let n = 500;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-3).collect();
    let x: Vec<f64> = t.iter().map(|t| 1e-3 * (3.0 * t).sin()).collect();
    let u: Vec<f64> = t.iter().map(|t| (3.0 * t).cos()).collect();
    let mat = mat_file(&[("t", t), ("qm", x), ("vir", u), ("gtau", vec![2.0])]);
    for cut in [10, 128, 140, mat.len() / 2, mat.len() - 3] {
        cases.push((format!("cut{cut}.mat"), mat[..cut].to_vec(), vec![".mat"]));
    }
    // The real EMPS file, truncated.
    if let Some(f) = common::shared_or_skip("emps/DATA_EMPS.mat") {
        let emps = std::fs::read(f).unwrap();
        cases.push((
            "emps_cut.mat".into(),
            emps[..emps.len() / 3].to_vec(),
            vec!["emps_cut.mat"],
        ));
    }
    for (name, bytes, needles) in &cases {
        let path = tmp(name);
        std::fs::write(&path, bytes).unwrap();
        let p = path.to_string_lossy().into_owned();
        for command in ["fit", "diagnose"] {
            fails(&[command, &p], needles);
            assert_eq!(&std::fs::read(&path).unwrap(), bytes, "{name} was modified");
        }
    }
}

/// Input that would give a number that is not one (a record that never
/// moves, forces near the `f64` range), outputs that would replace each
/// other or the data, and layouts read as something else: each is refused
/// with one line naming what is wrong.
#[test]
fn refused_rather_than_silently_wrong() {
    let good = good_csv(400);
    // The position never changes: the residual weighs nothing.
    let still: String = good
        .lines()
        .map(|l| match l.split_once(',') {
            Some((x, rest)) if !l.starts_with('#') && x != "x" => format!("5e-3,{rest}\n"),
            _ => format!("{l}\n"),
        })
        .collect();
    let model = common::fig5();
    // `fit`, `validate` and `diagnose` of the record `text` written as
    // `name` each fail naming it and every needle.
    let refused_by_all = |name: &str, text: &str, needles: &[&str]| {
        let data = write(name, text);
        for args in [
            vec!["fit", data.as_str()],
            vec!["validate", data.as_str(), "--model", model.as_str()],
            vec!["diagnose", data.as_str()],
        ] {
            fails(&args, &[&[name], needles].concat());
        }
    };
    refused_by_all("still.csv", &still, &["never changes"]);
    // The position dithers by one count now and then (a force below the
    // stiction level throughout): no sample moves over a velocity window,
    // so no figure can be formed (a fresh sweep's slow sinusoid 9700105
    // came out as a "NaN" rms before).
    let creep: String = good
        .lines()
        .enumerate()
        .map(|(k, l)| match l.split_once(',') {
            Some((x, rest)) if !l.starts_with('#') && x != "x" => {
                format!("{},{rest}\n", 5e-3 + 1e-6 * ((k / 150) % 2) as f64)
            }
            _ => format!("{l}\n"),
        })
        .collect();
    refused_by_all(
        "creep.csv",
        &creep,
        &["hardly moves", "0 of 400 samples move"],
    );
    // Forces near the f64 range: the residual overflows.
    let huge: String = good
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            match f.as_slice() {
                [x, t, u, e] if !l.starts_with('#') && *x != "x" => {
                    format!("{x},{t},{:e},{e}\n", u.parse::<f64>().unwrap() * 1e300)
                }
                _ => format!("{l}\n"),
            }
        })
        .collect();
    refused_by_all("huge_u.csv", &huge, &["out of the range"]);
    // Two outputs of one run naming one file, or an output that is the
    // data under another name.
    let data = write("collide.csv", &good);
    let report = tmp("collide.json").to_string_lossy().into_owned();
    fails(
        &["diagnose", &data, "--json", &report, "--model-out", &report],
        &["collide.json", "same file"],
    );
    let out = tmp("synth_same.csv").to_string_lossy().into_owned();
    fails(
        &["synth", "--out", &out, "--truth", &out],
        &["synth_same.csv", "same file"],
    );
    #[cfg(unix)]
    {
        let link = tmp("collide_link.csv");
        let _ = std::fs::remove_file(&link);
        std::fs::hard_link(&data, &link).unwrap();
        let link = link.to_string_lossy().into_owned();
        fails(
            &["fit", &data, "--model-out", &link],
            &["collide_link.csv", "input file"],
        );
        assert_eq!(std::fs::read_to_string(&data).unwrap(), good);
    }
    // A time record whose time column is misnamed is not a steady-state
    // record.
    let misnamed = write("misnamed.csv", &good.replace("x,t,u,extra", "x,time,u,v"));
    fails(&["diagnose", &misnamed], &["misnamed.csv", "`t`"]);
    // Steady-state readings at one speed identify no curve.
    let one_speed = write(
        "one_speed.csv",
        "v,u\n1e-3,5\n1e-3,5\n1e-3,5\n1e-3,5\n1e-3,5\n",
    );
    fails(&["diagnose", &one_speed], &["one_speed.csv", "distinct"]);
    let steady = write("steady_opts.csv", &steady_csv());
    let svg = tmp("steady.svg").to_string_lossy().into_owned();
    fails(
        &["diagnose", &steady, "--svg", &svg],
        &["steady_opts.csv", "--svg", "time records only"],
    );
    // A reading of the Indy7 layout that is not a number is refused, not
    // skipped.
    let indy = write(
        "indy_bad.csv",
        "logger preamble\ndesired vel, real vel, tau\n\n0.05, 0.03, 11.3,\nO.10, 0.07, 12.5,\n",
    );
    fails(
        &["static-curve", &indy],
        &["indy_bad.csv", "line 5", "`O.10`"],
    );
}

/// Input a user's export can get wrong, found before the analysis and
/// named (an outside audit's list): a `v` column that is not the velocity
/// of `x`, a force of the wrong sign, a column named twice, a
/// steady-state record given to `fit` or `validate`, an output directory
/// that does not exist, an interval off the sampling (named by its line).
#[test]
fn refused_before_the_analysis() {
    let good = good_csv(400);
    let rows = |f: &dyn Fn(&[&str]) -> String| -> String {
        good.lines()
            .map(|l| {
                let c: Vec<&str> = l.split(',').collect();
                if l.starts_with('#') {
                    format!("{l}\n")
                } else {
                    f(&c) + "\n"
                }
            })
            .collect()
    };
    // `good_csv`: x, t, u, extra; the extra column becomes `v`.
    let zero_v = write(
        "zero_v.csv",
        &rows(&|c| {
            if c[0] == "x" {
                "x,t,u,v".into()
            } else {
                format!("{},{},{},0", c[0], c[1], c[2])
            }
        }),
    );
    fails(
        &["diagnose", &zero_v],
        &["zero_v.csv", "column `v`", "velocity of `x`"],
    );
    // The sinusoid's own velocity as the column, in mm/s and in m/s.
    let with_v = |name: &str, scale: f64| {
        write(
            name,
            &rows(&|c| {
                if c[0] == "x" {
                    "x,t,u,v".into()
                } else {
                    let t: f64 = c[1].parse().unwrap();
                    let v = scale * 3e-3 * (t * 3.0).cos();
                    format!("{},{},{},{v}", c[0], c[1], c[2])
                }
            }),
        )
    };
    let mm_v = with_v("mm_v.csv", 1e3);
    fails(
        &["diagnose", &mm_v],
        &["mm_v.csv", "column `v`", "scale is 1000"],
    );
    let si_v = with_v("si_v.csv", 1.0);
    ok(&["validate", &si_v, "--model", &common::fig5()]);
    // The force negated: it does negative work on the axis.
    let neg_u = write(
        "neg_u.csv",
        &rows(&|c| {
            if c[0] == "x" {
                c.join(",")
            } else {
                let u: f64 = c[2].parse().unwrap();
                format!("{},{},{},{}", c[0], c[1], -u, c[3])
            }
        }),
    );
    fails(
        &["diagnose", &neg_u],
        &["neg_u.csv", "negative work", "wrong sign"],
    );
    let dup = write("dup_col.csv", &good.replace("x,t,u,extra", "x,t,u,x"));
    fails(
        &["diagnose", &dup],
        &["dup_col.csv", "line 2", "`x` named twice"],
    );
    let steady = write("steady_fit.csv", &steady_csv());
    fails(
        &["fit", &steady],
        &["steady_fit.csv", "steady-state record", "diagnose"],
    );
    fails(
        &["validate", &steady, "--model", &common::fig5()],
        &["steady_fit.csv", "steady-state record"],
    );
    fails(
        &[
            "diagnose",
            &steady,
            "--candidates",
            "offset,position_ripple",
        ],
        &["steady_fit.csv", "`position_ripple` cannot show"],
    );
    // A header a spreadsheet would write: the hint names what is wrong.
    for (name, header, hint) in [
        ("semicolon.csv", "x;t;u;extra", "separator must be a comma"),
        ("units.csv", "x [m],t [s],u [N],extra", "no units"),
        ("upper.csv", "X,T,U,extra", "lower case"),
    ] {
        let f = write(name, &good.replace("x,t,u,extra", header));
        fails(&["diagnose", &f], &[name, "lacks column", hint]);
    }
    let data = write("nodir.csv", &good);
    let missing = tmp("no_such_dir/report.json")
        .to_string_lossy()
        .into_owned();
    fails(
        &["diagnose", &data, "--json", &missing],
        &["report.json", "does not exist"],
    );
    // A file where the directory should be.
    fails(
        &["diagnose", &data, "--json", &format!("{data}/report.json")],
        &["nodir.csv is not a directory"],
    );
    // Sample 101 (file line 103: comment and header first) 0.3 ms after
    // the one before, at a 1 ms median interval.
    let jitter = rows(&|c| {
        if c[0] == "x" {
            c.join(",")
        } else {
            let t: f64 = c[1].parse().unwrap();
            let t = if (t - 0.1).abs() < 1e-9 { 0.0993 } else { t };
            format!("{},{t},{},{}", c[0], c[2], c[3])
        }
    });
    let jitter = write("jitter.csv", &jitter);
    fails(
        &["diagnose", &jitter],
        &["jitter.csv", "line 103", "uniform sampling"],
    );
}

/// The version of the workflow that wrote a report, in the report and on
/// the command line.
#[test]
fn reports_say_their_version() {
    let out = ok(&["--version"]);
    let version = breakaway_lab::diagnose::WORKFLOW_VERSION;
    assert!(
        out.contains(&format!("discrepancy workflow {version}")),
        "{out}"
    );
    let steady = write("steady_version.csv", &steady_csv());
    let report = tmp("steady_version.json").to_string_lossy().into_owned();
    ok(&["diagnose", &steady, "--json", &report]);
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(j["version"], version);
}

/// `fit` writes what it fitted, and says what of it the record did not
/// identify: on a fast sinusoid the mass runs to its lower limit.
#[test]
fn fit_says_what_it_did_not_identify() {
    // The force in phase with the velocity (it does positive work, as on
    // any axis with friction), none of it with the acceleration.
    let mut s = String::from("t,u,x\n");
    for i in 0..3000 {
        let t = f64::from(i) * 1e-3;
        let angle = 2.0 * std::f64::consts::PI * 400.0 * t;
        s.push_str(&format!("{t},{},{}\n", angle.cos(), 1e-3 * angle.sin()));
    }
    let data = write("fast_sine.csv", &s);
    let text = ok(&["fit", &data]);
    assert!(
        text.contains("not identified here: the mass ran to its lower limit"),
        "{text}"
    );
    let json: serde_json::Value = serde_json::from_str(&ok(&["fit", &data, "--json"])).unwrap();
    let flags = json["not_identified"].as_array().expect("not_identified");
    assert!(!flags.is_empty(), "{json}");
}
