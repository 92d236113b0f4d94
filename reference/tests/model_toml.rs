//! Model files (MODEL.md §7): exact round trip, strict reading, validation.

mod common;
use breakaway_reference::*;
use common::paper;

/// splitmix64: a small deterministic generator for the tests.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// A finite float from random bits (any exponent), or a special value.
    fn any_finite(&mut self) -> f64 {
        const SPECIAL: [f64; 12] = [
            0.0,
            -0.0,
            1.0,
            1e-5,
            0.1,
            1e16,
            1e15,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            -f64::MAX,
            123456789.0,
        ];
        if self.next().is_multiple_of(4) {
            return SPECIAL[(self.next() % SPECIAL.len() as u64) as usize];
        }
        loop {
            let v = f64::from_bits(self.next());
            if v.is_finite() {
                return v;
            }
        }
    }
    fn positive(&mut self) -> f64 {
        loop {
            let v = self.any_finite().abs();
            if v > 0.0 {
                return v;
            }
        }
    }
    fn non_negative(&mut self) -> f64 {
        // Keeps the sign bit of -0.0 (valid: -0.0 >= 0).
        let v = self.any_finite();
        if v == 0.0 {
            v
        } else {
            v.abs()
        }
    }
}

fn random_model(r: &mut Rng) -> Model {
    let fc = r.positive();
    let fs = if r.next().is_multiple_of(3) {
        fc
    } else {
        let f = fc * (1.0 + 10.0 * r.unit());
        if f.is_finite() {
            f
        } else {
            fc
        }
    };
    let mut e = Effects::default();
    if r.next().is_multiple_of(2) {
        e.offset = Some(Offset { f0: r.any_finite() });
    }
    if r.next().is_multiple_of(2) {
        let a = 2.0 * r.unit() - 1.0;
        e.asymmetry = Some(Asymmetry {
            a: if a > -1.0 { a } else { 0.0 },
        });
    }
    if r.next().is_multiple_of(2) {
        e.position_ripple = Some(PositionRipple {
            amplitude: r.any_finite(),
            wavelength: r.positive(),
            phase: r.any_finite(),
        });
    }
    if r.next().is_multiple_of(2) {
        e.dwell_stiction = Some(DwellStiction {
            delta_fs: r.non_negative(),
            gamma: r.positive(),
            v_rest: r.positive(),
        });
    }
    if r.next().is_multiple_of(2) {
        e.frictional_lag = Some(FrictionalLag {
            tau_l: r.positive(),
        });
    }
    if r.next().is_multiple_of(2) {
        e.drift = Some(Drift {
            beta: r.any_finite(),
        });
    }
    if r.next().is_multiple_of(2) {
        e.nonlinear_viscous = Some(NonlinearViscous {
            sigma_n: r.non_negative(),
            n: 2.0 * (1.0 - r.unit()).max(1e-9),
        });
    }
    Model {
        mass: r.positive(),
        fc,
        fs,
        v_stribeck: r.positive(),
        delta: r.positive(),
        sigma: r.non_negative(),
        z_max: r.non_negative(),
        epsilon: r.non_negative(),
        effects: e,
    }
}

/// All floats of a model, in a fixed order, as bits (None for absent effects).
fn bits(m: &Model) -> Vec<Option<u64>> {
    let mut v: Vec<Option<u64>> = [
        m.mass,
        m.fc,
        m.fs,
        m.v_stribeck,
        m.delta,
        m.sigma,
        m.z_max,
        m.epsilon,
    ]
    .iter()
    .map(|x| Some(x.to_bits()))
    .collect();
    let e = &m.effects;
    let mut opt = |vals: Option<Vec<f64>>, n: usize| match vals {
        Some(vals) => v.extend(vals.iter().map(|x| Some(x.to_bits()))),
        None => v.extend(std::iter::repeat_n(None, n)),
    };
    opt(e.offset.map(|o| vec![o.f0]), 1);
    opt(e.asymmetry.map(|a| vec![a.a]), 1);
    opt(
        e.position_ripple
            .map(|r| vec![r.amplitude, r.wavelength, r.phase]),
        3,
    );
    opt(
        e.dwell_stiction
            .map(|d| vec![d.delta_fs, d.gamma, d.v_rest]),
        3,
    );
    opt(e.frictional_lag.map(|l| vec![l.tau_l]), 1);
    opt(e.drift.map(|d| vec![d.beta]), 1);
    opt(e.nonlinear_viscous.map(|n| vec![n.sigma_n, n.n]), 2);
    v
}

#[test]
fn round_trip_is_bit_exact_for_random_models() {
    let mut r = Rng(0x5eed);
    for i in 0..3000 {
        let m = random_model(&mut r);
        m.validate()
            .unwrap_or_else(|e| panic!("generator made invalid model {i}: {e}"));
        let text = m.to_toml_string();
        let back = Model::from_toml_str(&text)
            .unwrap_or_else(|e| panic!("model {i} does not read back: {e}\n{text}"));
        assert_eq!(bits(&m), bits(&back), "model {i}:\n{text}");
        // Writing again gives the same text.
        assert_eq!(text, back.to_toml_string());
    }
}

#[test]
fn special_floats_are_written_as_toml_floats() {
    let mut m = paper();
    m.sigma = -0.0;
    m.epsilon = 5e-324;
    m.mass = f64::MAX;
    m.z_max = 1e-5;
    m.fs = 1e16;
    let text = m.to_toml_string();
    assert!(text.contains("fc = 1.0"), "{text}");
    assert!(text.contains("sigma = -0.0"), "{text}");
    assert!(text.contains("z_max = 1e-5"), "{text}");
    assert!(text.contains("epsilon = 5e-324"), "{text}");
    assert!(text.contains("fs = 1e16"), "{text}");
    let back = Model::from_toml_str(&text).unwrap();
    assert_eq!(back.sigma.to_bits(), (-0.0f64).to_bits());
    assert_eq!(back.epsilon.to_bits(), 5e-324f64.to_bits());
    assert_eq!(back.mass, f64::MAX);
}

const SPEC_EXAMPLE: &str = r#"
mass = 1.0           # m [kg]
fc = 1.0             # Fc [N]
fs = 1.5             # Fs [N]
v_stribeck = 1e-3    # V [m/s]
delta = 2.0          # δ
sigma = 0.0          # σ [N·s/m]; the effect `viscous` is σ > 0
z_max = 1e-5         # [m]
epsilon = 0.0        # turning-point deadband [m]

[effects.offset]
f0 = -0.1
[effects.asymmetry]
a = 0.1
[effects.position_ripple]
amplitude = 0.1
wavelength = 1e-3
phase = 0.0
[effects.dwell_stiction]
delta_fs = 0.2
gamma = 0.5
v_rest = 1e-4
[effects.frictional_lag]
tau_l = 0.01
[effects.drift]
beta = 1e-3
[effects.nonlinear_viscous]
sigma_n = 2.0
n = 0.5
"#;

#[test]
fn reads_the_spec_example() {
    let m = Model::from_toml_str(SPEC_EXAMPLE).unwrap();
    assert_eq!(m.mass, 1.0);
    assert_eq!(m.fs, 1.5);
    assert_eq!(m.v_stribeck, 1e-3);
    assert_eq!(m.delta, 2.0);
    assert_eq!(m.z_max, 1e-5);
    assert_eq!(m.effects.offset, Some(Offset { f0: -0.1 }));
    assert_eq!(m.effects.asymmetry, Some(Asymmetry { a: 0.1 }));
    assert_eq!(
        m.effects.position_ripple,
        Some(PositionRipple {
            amplitude: 0.1,
            wavelength: 1e-3,
            phase: 0.0
        })
    );
    assert_eq!(
        m.effects.dwell_stiction,
        Some(DwellStiction {
            delta_fs: 0.2,
            gamma: 0.5,
            v_rest: 1e-4
        })
    );
    assert_eq!(
        m.effects.frictional_lag,
        Some(FrictionalLag { tau_l: 0.01 })
    );
    assert_eq!(m.effects.drift, Some(Drift { beta: 1e-3 }));
    assert_eq!(
        m.effects.nonlinear_viscous,
        Some(NonlinearViscous {
            sigma_n: 2.0,
            n: 0.5
        })
    );
    assert_eq!(Model::from_toml_str(&m.to_toml_string()).unwrap(), m);
}

#[test]
fn integers_are_accepted_as_floats() {
    let text =
        "mass = 2\nfc = 1\nfs = 3\nv_stribeck = 1\ndelta = 2\nsigma = 0\nz_max = 0\nepsilon = 0\n";
    let m = Model::from_toml_str(text).unwrap();
    assert_eq!(m.mass, 2.0);
    assert_eq!(m.fs, 3.0);
    assert_eq!(m.z_max, 0.0);
    assert_eq!(m.effects, Effects::default());
}

fn err_key(text: &str) -> String {
    match Model::from_toml_str(text) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => {
            let shown = e.to_string();
            assert!(!shown.contains('\n'), "multi-line error: {shown}");
            if !e.key.is_empty() {
                assert!(shown.contains(&e.key), "{shown}");
            }
            e.key
        }
    }
}

/// Replaces `key = ...` (first occurrence, as a whole line start) in the spec example.
fn with_value(key: &str, value: &str) -> String {
    let mut out = String::new();
    let mut done = false;
    for line in SPEC_EXAMPLE.lines() {
        let name = line.split('=').next().unwrap_or("").trim();
        if !done && name == key {
            out.push_str(&format!("{key} = {value}\n"));
            done = true;
        } else {
            out.push_str(line);
            out.push('\n');
        }
    }
    assert!(done, "{key}");
    out
}

#[test]
fn each_invalid_value_is_an_error_naming_its_key() {
    let cases: &[(&str, &str, &str)] = &[
        ("mass", "mass", "0.0"),
        ("mass", "mass", "-1.0"),
        ("mass", "mass", "inf"),
        ("fc", "fc", "0.0"),
        ("fc", "fc", "nan"),
        ("fs", "fs", "0.5"),
        ("fs", "fs", "inf"),
        ("v_stribeck", "v_stribeck", "0.0"),
        ("v_stribeck", "v_stribeck", "-1e-3"),
        ("delta", "delta", "0.0"),
        ("delta", "delta", "-inf"),
        ("sigma", "sigma", "-0.1"),
        ("sigma", "sigma", "nan"),
        ("z_max", "z_max", "-1e-5"),
        ("z_max", "z_max", "inf"),
        ("epsilon", "epsilon", "-1e-9"),
        ("epsilon", "epsilon", "nan"),
        ("f0", "effects.offset.f0", "inf"),
        ("a", "effects.asymmetry.a", "1.0"),
        ("a", "effects.asymmetry.a", "-1.0"),
        ("a", "effects.asymmetry.a", "nan"),
        ("amplitude", "effects.position_ripple.amplitude", "nan"),
        ("wavelength", "effects.position_ripple.wavelength", "0.0"),
        ("wavelength", "effects.position_ripple.wavelength", "-1.0"),
        ("phase", "effects.position_ripple.phase", "-inf"),
        ("delta_fs", "effects.dwell_stiction.delta_fs", "-0.2"),
        ("gamma", "effects.dwell_stiction.gamma", "0.0"),
        ("v_rest", "effects.dwell_stiction.v_rest", "0.0"),
        ("tau_l", "effects.frictional_lag.tau_l", "0.0"),
        ("tau_l", "effects.frictional_lag.tau_l", "-0.01"),
        ("beta", "effects.drift.beta", "nan"),
        ("sigma_n", "effects.nonlinear_viscous.sigma_n", "-1.0"),
        ("n", "effects.nonlinear_viscous.n", "0.0"),
        ("n", "effects.nonlinear_viscous.n", "2.5"),
        // wrong types
        ("mass", "mass", "\"1.0\""),
        ("beta", "effects.drift.beta", "true"),
        ("a", "effects.asymmetry.a", "[0.1]"),
    ];
    for (line_key, path, value) in cases {
        let text = with_value(line_key, value);
        assert_eq!(err_key(&text), *path, "{line_key} = {value}");
    }
}

#[test]
fn validate_names_the_key_too() {
    let mut m = paper();
    m.effects.asymmetry = Some(Asymmetry { a: 1.5 });
    assert_eq!(m.validate().unwrap_err().key, "effects.asymmetry.a");
    let mut m = paper();
    m.fs = 0.9;
    let e = m.validate().unwrap_err();
    assert_eq!(e.key, "fs");
    assert!(e.to_string().starts_with("fs: "), "{e}");
    assert!(paper().validate().is_ok());
}

#[test]
fn unknown_keys_are_errors_naming_the_path() {
    let text = format!("{SPEC_EXAMPLE}\n[effects.offset2]\nf0 = 1.0\n");
    assert_eq!(err_key(&text), "effects.offset2");
    let text = SPEC_EXAMPLE.replace("a = 0.1", "a = 0.1\nb = 0.2");
    assert_eq!(err_key(&text), "effects.asymmetry.b");
    let text = SPEC_EXAMPLE.replace("mass = 1.0", "mass = 1.0\nmas = 1.0");
    assert_eq!(err_key(&text), "mas");
    let text = SPEC_EXAMPLE.replace("tau_l = 0.01", "tau_l = 0.01\ntau = 0.01");
    assert_eq!(err_key(&text), "effects.frictional_lag.tau");
    // `viscous` has no table (§7).
    let text = format!("{SPEC_EXAMPLE}\n[effects.viscous]\nsigma = 1.0\n");
    assert_eq!(err_key(&text), "effects.viscous");
    let top = SPEC_EXAMPLE.split("[effects").next().unwrap_or("");
    let text = format!("{top}effects = 3\n");
    assert_eq!(err_key(&text), "effects");
}

#[test]
fn missing_keys_are_errors_naming_the_key() {
    for key in [
        "mass",
        "fc",
        "fs",
        "v_stribeck",
        "delta",
        "sigma",
        "z_max",
        "epsilon",
    ] {
        let text: String = SPEC_EXAMPLE
            .lines()
            .filter(|l| l.split('=').next().unwrap_or("").trim() != key)
            .map(|l| format!("{l}\n"))
            .collect();
        assert_eq!(err_key(&text), key);
    }
    let text = SPEC_EXAMPLE.replace("wavelength = 1e-3\n", "");
    assert_eq!(err_key(&text), "effects.position_ripple.wavelength");
    let text = SPEC_EXAMPLE.replace("gamma = 0.5\n", "");
    assert_eq!(err_key(&text), "effects.dwell_stiction.gamma");
}

#[test]
fn syntax_errors_are_one_line() {
    let e = Model::from_toml_str("mass = = 1").unwrap_err();
    assert!(e.key.is_empty());
    assert!(e.to_string().contains("line 1"), "{e}");
    assert!(!e.to_string().contains('\n'));
}

#[test]
fn load_and_save_name_the_file() {
    let dir = std::env::temp_dir().join(format!("breakaway-reference-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("model.toml");
    let mut m = paper();
    m.effects.drift = Some(Drift { beta: -1e-3 });
    m.save(&path).unwrap();
    assert_eq!(Model::load(&path).unwrap(), m);
    std::fs::write(&path, SPEC_EXAMPLE.replace("a = 0.1", "a = 2.0")).unwrap();
    let e = Model::load(&path).unwrap_err();
    assert_eq!(e.key, "effects.asymmetry.a");
    assert!(e.to_string().contains("model.toml"), "{e}");
    let missing = dir.join("nope.toml");
    let e = Model::load(&missing).unwrap_err();
    assert!(e.to_string().contains("nope.toml"), "{e}");
    let mut bad = paper();
    bad.mass = -1.0;
    assert_eq!(bad.save(&path).unwrap_err().key, "mass");
    std::fs::remove_dir_all(&dir).ok();
}

/// `nonlinear_viscous` in the friction of MODEL.md §5, by hand: in gross
/// sliding at v = ±0.04 m/s with Fc = Fs = 1 N, σ_n = 2 N·(s/m)^0.5, n = 0.5,
/// F = ±(1 + 2·√0.04) = ±1.4 N.
#[test]
fn nonlinear_viscous_adds_sigma_n_times_v_to_the_n() {
    let mut m = Model::from_toml_str(SPEC_EXAMPLE).unwrap();
    m.effects = Effects {
        nonlinear_viscous: Some(NonlinearViscous {
            sigma_n: 2.0,
            n: 0.5,
        }),
        ..Effects::default()
    };
    m.fs = m.fc;
    for sign in [1.0, -1.0] {
        let mut f = Friction::new(&m, 0.0, 0.0, 0.0);
        let mut last = 0.0;
        for i in 0..=100 {
            // 4 mm of travel at 0.04 m/s: far past z_max = 10 µm.
            let t = i as f64 * 1e-3;
            last = f.update(&m, t, sign * 0.04 * t, sign * 0.04);
        }
        assert!((last - sign * 1.4).abs() < 1e-12, "{last}");
    }
}
