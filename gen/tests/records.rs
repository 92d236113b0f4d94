//! Whole records: determinism, the format of every family, servo holding
//! forces, visibility against its target, the truth files and the CLI.

use breakaway_gen::draw::{Kind, Overrides};
use breakaway_gen::excite::Family;
use breakaway_gen::friction::Effect;
use breakaway_gen::plants::PlantKind;
use breakaway_gen::record::{generate, Data, Generated};
use breakaway_gen::write;
use std::process::Command;

fn ov(family: Family, plant: PlantKind, effects: &[Effect], duration: f64) -> Overrides {
    Overrides {
        family: Some(family),
        plant: Some(plant),
        effects: Some(effects.to_vec()),
        stribeck_absent: None,
        duration: Some(duration),
        ramp_pause: None,
    }
}

/// Parses `t,u,x` text; checks the header, finiteness, strictly increasing
/// `t = k·1 ms` and quantised `x`.
fn check_time_csv(g: &Generated) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let text = write::csv(g);
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,u,x"));
    let (mut t, mut u, mut x) = (Vec::new(), Vec::new(), Vec::new());
    for l in lines {
        let f: Vec<f64> = l.split(',').map(|s| s.parse().unwrap()).collect();
        assert_eq!(f.len(), 3);
        assert!(f.iter().all(|v| v.is_finite()), "{l}");
        t.push(f[0]);
        u.push(f[1]);
        x.push(f[2]);
    }
    let q = g.draw.q;
    for (k, w) in t.windows(2).enumerate() {
        assert!(w[1] > w[0], "t not increasing at {k}");
        assert!((w[1] - w[0] - 1e-3).abs() < 1e-9);
    }
    for v in &x {
        let c = v / q;
        assert!((c - c.round()).abs() < 1e-6, "x {v} not a multiple of {q}");
    }
    assert_eq!(t.len(), (g.draw.duration * 1000.0).round() as usize);
    (t, u, x)
}

#[test]
fn same_seed_same_bytes_other_seed_other_bytes() {
    let o = Overrides {
        duration: Some(4.0),
        ..Overrides::default()
    };
    for seed in [7u64, 31] {
        let a = generate(seed, Kind::Mixed, &o).unwrap();
        let b = generate(seed, Kind::Mixed, &o).unwrap();
        assert_eq!(write::csv(&a), write::csv(&b));
        assert_eq!(write::truth_toml(&a), write::truth_toml(&b));
        assert_eq!(write::truth_json(&a), write::truth_json(&b));
    }
    let a = generate(7, Kind::Model, &o).unwrap();
    let c = generate(8, Kind::Model, &o).unwrap();
    assert_ne!(write::csv(&a), write::csv(&c));
    assert_ne!(a.name(), "");
    // A seed's record does not depend on the overrides of another run: the
    // same seed with and without its own drawn family named explicitly.
    let fam = a.draw.family;
    let named = Overrides {
        family: Some(fam),
        duration: Some(4.0),
        ..Overrides::default()
    };
    let a2 = generate(7, Kind::Model, &named).unwrap();
    assert_eq!(write::csv(&a), write::csv(&a2));
}

#[test]
fn every_family_and_plant_gives_well_formed_records() {
    for (i, fam) in Family::DYNAMIC.into_iter().enumerate() {
        let g = generate(
            100 + i as u64,
            Kind::Model,
            &ov(fam, PlantKind::Model, &[], 8.0),
        )
        .unwrap();
        let (_, u, x) = check_time_csv(&g);
        assert!(u.iter().any(|v| v.abs() > 0.3 * g.model.p.fc), "{fam:?}");
        let range =
            x.iter().cloned().fold(f64::MIN, f64::max) - x.iter().cloned().fold(f64::MAX, f64::min);
        assert!(range > 2.0 * g.draw.q, "{fam:?} did not move");
    }
    for (i, plant) in PlantKind::OUTSIDE.into_iter().enumerate() {
        let g = generate(
            200 + i as u64,
            Kind::Outside,
            &ov(Family::Servo, plant, &[Effect::Offset], 6.0),
        )
        .unwrap();
        check_time_csv(&g);
        assert_eq!(g.draw.plant, plant);
        let json = write::truth_json(&g);
        let extra = json["accept_extra"].as_array().unwrap();
        let lag_like = matches!(plant, PlantKind::Lugre | PlantKind::MaxwellSlip);
        assert_eq!(extra.len(), usize::from(lag_like), "{plant:?}");
    }
}

#[test]
fn servo_rests_hold_a_force() {
    let g = generate(
        5,
        Kind::Model,
        &ov(Family::Servo, PlantKind::Model, &[], 20.0),
    )
    .unwrap();
    let (_, u, x) = check_time_csv(&g);
    // Rest samples: the position has not changed for the last 100 samples,
    // after the axis has moved.
    let noise = g.draw.noise_std;
    let mut held = 0;
    let mut rests = 0;
    let mut moved = false;
    for k in 100..x.len() {
        moved |= x[k] != x[0];
        if moved && x[k - 100..=k].iter().all(|&v| v == x[k]) {
            rests += 1;
            if u[k].abs() > 10.0 * noise {
                held += 1;
            }
        }
    }
    assert!(rests > 500, "rest samples {rests}");
    assert!(held > 100, "held {held} of {rests}");
}

#[test]
fn a_ramp_pause_lets_go_of_the_axis_before_each_servo_ramp() {
    let plain = ov(Family::Servo, PlantKind::Model, &[], 30.0);
    let paused = Overrides {
        ramp_pause: Some(0.25),
        ..plain.clone()
    };
    let a = generate(5, Kind::Model, &plain).unwrap();
    let b = generate(5, Kind::Model, &paused).unwrap();
    // A pause of 0 is no pause: the same bytes as without the option (the
    // option only adds segments where it is above 0).
    let none = Overrides {
        ramp_pause: Some(0.0),
        ..plain.clone()
    };
    assert_eq!(
        write::csv(&a),
        write::csv(&generate(5, Kind::Model, &none).unwrap())
    );
    // Zero-force stretches of at least 0.15 s (the pause less its 50 ms
    // release, and the noise band): one more per ramp (3 rates, both
    // directions) with the pause.
    let stretches = |g: &Generated| {
        let (_, u, _) = check_time_csv(g);
        let band = 5.0 * g.draw.noise_std;
        let (mut n, mut run) = (0, 0);
        for v in &u {
            if v.abs() <= band {
                run += 1;
            } else {
                n += usize::from(run >= 150);
                run = 0;
            }
        }
        n
    };
    assert_eq!(
        stretches(&b),
        stretches(&a) + 6,
        "zero-force stretches with and without the pause"
    );
}

#[test]
fn visibility_hits_its_target() {
    let cases = [
        (Effect::Offset, Family::Servo),
        (Effect::Viscous, Family::VelocityLoop),
        (Effect::PositionRipple, Family::PointToPoint),
        (Effect::Asymmetry, Family::Servo),
        (Effect::NonlinearViscous, Family::Sinusoid),
        (Effect::DwellStiction, Family::Ramps),
        (Effect::FrictionalLag, Family::Servo),
        (Effect::Drift, Family::Ramps),
    ];
    let mut checked = 0;
    for (i, (e, fam)) in cases.into_iter().enumerate() {
        let g = generate(
            300 + i as u64,
            Kind::Model,
            &ov(fam, PlantKind::Model, &[e], 12.0),
        )
        .unwrap();
        let vis = g.visibility[0];
        assert!(vis >= 3.0, "{e:?}: visibility {vis}");
        if !g.clamped[0] {
            let target = g.draw.targets[0];
            assert!(
                (vis / target - 1.0).abs() <= 0.2,
                "{e:?}: visibility {vis:.2} vs target {target:.2}"
            );
            checked += 1;
        }
        if e == Effect::Offset {
            // The RMS of a constant is the constant.
            let f0 = g.model.e.offset.unwrap().f0;
            assert!((vis * g.draw.noise_std - f0.abs()).abs() < 1e-9 * f0.abs());
        }
    }
    assert!(checked >= 6, "only {checked} unclamped");
}

#[test]
fn two_effects_and_noise() {
    let g = generate(
        77,
        Kind::Model,
        &ov(
            Family::Servo,
            PlantKind::Model,
            &[Effect::Viscous, Effect::Offset],
            10.0,
        ),
    )
    .unwrap();
    assert_eq!(g.visibility.len(), 2);
    for (j, v) in g.visibility.iter().enumerate() {
        assert!((v / g.draw.targets[j] - 1.0).abs() <= 0.2);
    }
    let Data::Time { u, u_clean, .. } = &g.data else {
        panic!("time record expected");
    };
    // The logged u = applied u + N(0, noise_std).
    let n = u.len() as f64;
    let d: Vec<f64> = u.iter().zip(u_clean).map(|(a, b)| a - b).collect();
    let mean = d.iter().sum::<f64>() / n;
    let std = (d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n).sqrt();
    assert!((std / g.draw.noise_std - 1.0).abs() < 0.05);
    assert!(mean.abs() < 0.05 * g.draw.noise_std);
}

#[test]
fn steady_records() {
    for seed in 0..6u64 {
        let g = generate(seed, Kind::Steady, &Overrides::default()).unwrap();
        let Data::Steady { v, u } = &g.data else {
            panic!("steady record expected");
        };
        assert!(v.len() >= 24);
        let pos: Vec<f64> = v.iter().cloned().filter(|s| *s > 0.0).collect();
        let neg = v.iter().filter(|s| **s < 0.0).count();
        assert_eq!(pos.len(), neg);
        let decades = (pos.iter().cloned().fold(0.0, f64::max)
            / pos.iter().cloned().fold(f64::MAX, f64::min))
        .log10();
        assert!((3.0 - 1e-9..=4.0 + 1e-9).contains(&decades));
        for (s, f) in v.iter().zip(u) {
            let r = f - g.model.steady(*s);
            assert!(r.abs() < 6.0 * g.draw.noise_std);
        }
        let text = write::csv(&g);
        assert!(text.lines().any(|l| l == "v,u"));
        for e in &g.draw.hidden {
            assert!(e.steady_visible());
        }
        if g.draw.stribeck_absent {
            assert_eq!(g.model.p.fs, g.model.p.fc);
        }
    }
    let g = generate(
        3,
        Kind::Steady,
        &Overrides {
            effects: Some(vec![]),
            stribeck_absent: Some(true),
            ..Overrides::default()
        },
    )
    .unwrap();
    assert_eq!(g.model.p.fs, g.model.p.fc);
    assert!(g.name().ends_with("stribeck-absent"));
}

#[test]
fn truth_files_follow_model_md() {
    let g = generate(
        11,
        Kind::Model,
        &ov(
            Family::Ramps,
            PlantKind::Model,
            &[Effect::DwellStiction, Effect::PositionRipple],
            6.0,
        ),
    )
    .unwrap();
    let text = write::truth_toml(&g).unwrap();
    let first = text.lines().next().unwrap();
    assert!(first.starts_with(&format!("# {}: hidden effects: ", g.name())));
    assert!(first.contains("force noise std"));
    assert!(first.contains("visibility: "));
    let v: toml::Value = toml::from_str(&text).unwrap();
    let t = v.as_table().unwrap();
    let mut keys: Vec<&str> = t.keys().map(String::as_str).collect();
    keys.sort_unstable();
    // Exactly the §7 keys, sorted.
    let expected = [
        "delta",
        "effects",
        "epsilon",
        "fc",
        "fs",
        "mass",
        "sigma",
        "v_stribeck",
        "z_max",
    ];
    assert_eq!(keys, expected);
    let eff = t["effects"].as_table().unwrap();
    assert_eq!(eff.len(), 2);
    let dw = eff["dwell_stiction"].as_table().unwrap();
    assert_eq!(dw.len(), 3);
    assert!(dw["delta_fs"].as_float().unwrap() > 0.0);
    let rp = eff["position_ripple"].as_table().unwrap();
    assert_eq!(
        rp["amplitude"].as_float().unwrap(),
        g.model.e.position_ripple.unwrap().amplitude
    );
    let j = write::truth_json(&g);
    for k in [
        "name",
        "seed",
        "family",
        "plant",
        "hidden",
        "visibility",
        "noise_std",
        "encoder",
        "mass",
        "pi",
        "duration",
        "accept_extra",
    ] {
        assert!(!j[k].is_null(), "truth.json lacks {k}");
    }
    assert_eq!(j["hidden"].as_array().unwrap().len(), 2);
    let pi = j["pi"].as_f64().unwrap();
    let p = g.model.p;
    assert!((pi - (2.0 * p.fs * p.z_max / p.mass).sqrt() / p.v_stribeck).abs() < 1e-9 * pi);
}

fn gen_cmd(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_breakaway-gen"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn cli_rejects_bad_input_with_code_2() {
    let dir = std::env::temp_dir().join(format!("breakaway-gen-cli-{}", std::process::id()));
    let out = dir.to_str().unwrap();
    for args in [
        vec!["record", "--seed", "x", "--out", out],
        vec!["record", "--seed", "1", "--family", "nope", "--out", out],
        vec!["record", "--seed", "1", "--plant", "nope", "--out", out],
        vec!["record", "--seed", "1", "--effects", "bogus", "--out", out],
        vec![
            "record",
            "--seed",
            "1",
            "--plant",
            "lugre",
            "--effects",
            "dwell_stiction",
            "--out",
            out,
        ],
        vec![
            "record",
            "--seed",
            "1",
            "--family",
            "steady",
            "--effects",
            "drift",
            "--out",
            out,
        ],
        vec!["record", "--seed", "1", "--duration", "nan", "--out", out],
        vec!["suite", "--seeds", "5..3", "--out", out],
        vec!["suite", "--seeds", "a..b", "--out", out],
        vec!["suite", "--seeds", "1..3", "--kind", "odd", "--out", out],
        vec!["record", "--seed", "1", "--ramp-pause", "9", "--out", out],
        vec![
            "suite",
            "--seeds",
            "1..3",
            "--ramp-pause",
            "-1",
            "--out",
            out,
        ],
        vec!["bogus"],
    ] {
        let o = gen_cmd(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("error"), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    let o = gen_cmd(&[
        "record",
        "--seed",
        "3",
        "--family",
        "servo",
        "--effects",
        "offset",
        "--duration",
        "3",
        "--out",
        out,
    ]);
    assert_eq!(o.status.code(), Some(0));
    for f in ["data.csv", "truth.toml", "truth.json"] {
        assert!(dir.join(f).is_file(), "{f}");
    }
    // A directory that holds a record is not written over without
    // --force; with it, no file of the earlier record is left (the
    // dwell record's rest log).
    let data = std::fs::read(dir.join("data.csv")).unwrap();
    let again = [
        "record",
        "--seed",
        "4",
        "--family",
        "servo",
        "--duration",
        "3",
    ];
    let o = gen_cmd(&[&again[..], &["--effects", "dwell_stiction", "--out", out]].concat());
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("is not empty"));
    assert_eq!(std::fs::read(dir.join("data.csv")).unwrap(), data);
    let o = gen_cmd(
        &[
            &again[..],
            &["--effects", "dwell_stiction", "--out", out, "--force"],
        ]
        .concat(),
    );
    assert_eq!(o.status.code(), Some(0));
    assert!(dir.join("rest_log.csv").is_file());
    let o = gen_cmd(&[&again[..], &["--effects", "none", "--out", out, "--force"]].concat());
    assert_eq!(o.status.code(), Some(0));
    assert!(!dir.join("rest_log.csv").exists());
    // A suite directory holding a record of one of its seeds, likewise.
    let suite = dir.join("suite");
    let first = ["suite", "--seeds", "5..7", "--kind", "steady", "--out"];
    assert_eq!(
        gen_cmd(&[&first[..], &[suite.to_str().unwrap()]].concat())
            .status
            .code(),
        Some(0)
    );
    let o = gen_cmd(&[
        "suite",
        "--seeds",
        "6..8",
        "--kind",
        "steady",
        "--out",
        suite.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("already holds a record of these seeds"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_suite_with_a_ramp_pause_writes_the_records_of_record() {
    let dir = std::env::temp_dir().join(format!("breakaway-gen-pause-{}", std::process::id()));
    let (one, all) = (dir.join("one"), dir.join("all"));
    let seed = "7600001";
    let o = gen_cmd(&[
        "record",
        "--seed",
        seed,
        "--kind",
        "suite",
        "--ramp-pause",
        "0.25",
        "--out",
        one.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0));
    for pause in [Some("0.25"), None] {
        let _ = std::fs::remove_dir_all(&all);
        let mut args = vec!["suite", "--seeds", seed, "--kind", "suite"];
        if let Some(p) = pause {
            args.extend(["--ramp-pause", p]);
        }
        args.extend(["--out", all.to_str().unwrap()]);
        assert_eq!(gen_cmd(&args).status.code(), Some(0));
        let written = std::fs::read_dir(&all)
            .unwrap()
            .filter_map(Result::ok)
            .find(|e| e.path().is_dir())
            .unwrap()
            .path();
        let same = std::fs::read(written.join("data.csv")).unwrap()
            == std::fs::read(one.join("data.csv")).unwrap();
        assert_eq!(same, pause.is_some(), "{pause:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn shares_no_code_with_the_judged_crates() {
    let manifest: toml::Value = toml::from_str(include_str!("../Cargo.toml")).unwrap();
    for section in ["dependencies", "dev-dependencies", "build-dependencies"] {
        let Some(deps) = manifest.get(section).and_then(|d| d.as_table()) else {
            continue;
        };
        for (name, spec) in deps {
            assert!(!name.starts_with("breakaway"), "depends on {name}");
            assert!(spec.get("path").is_none(), "{name} is a path dependency");
        }
    }
}
