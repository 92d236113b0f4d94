//! The quasi-static break-away predictor (MODEL.md §4).

mod common;
use breakaway_reference::*;
use common::paper;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn variant_names() {
    let names: Vec<&str> = Variant::ALL.iter().map(|v| v.name()).collect();
    assert_eq!(names, ["coulomb", "stiction", "mean", "consistent"]);
    for v in Variant::ALL {
        assert_eq!(Variant::parse(v.name()), Some(v));
        assert_eq!(v.to_string(), v.name());
    }
    assert_eq!(Variant::parse("Mean"), None);
    assert_eq!(Variant::parse(""), None);
}

#[test]
fn closed_forms_in_the_paper_setting() {
    // Hand-computed (independent script) for Fc = 1, Fs = 1.5, σ = 0,
    // V = 1e-3, δ = 1, z_max = 1e-5, w_b = 0.95: (k, variant, v_b, F_ba, t_ba).
    let table: &[(f64, Variant, f64, f64, f64)] = &[
        (
            0.1,
            Variant::Coulomb,
            1.9495725746223676e-05,
            1.490346543455419,
            14.88451761075929,
        ),
        (
            0.1,
            Variant::Stiction,
            1.299715049748245e-05,
            1.4935434738615114,
            14.9164462699955,
        ),
        (
            0.1,
            Variant::Mean,
            1.559658059697894e-05,
            1.4922622081019994,
            14.903649902033118,
        ),
        (
            0.1,
            Variant::Consistent,
            1.3053580043056069e-05,
            1.4935156242133394,
            14.916168127585944,
        ),
        (
            1.0,
            Variant::Coulomb,
            0.00019495725746223675,
            1.4114349144245513,
            1.4096404579490471,
        ),
        (
            1.0,
            Variant::Stiction,
            0.0001299715049748245,
            1.4390602263142336,
            1.4372306478367853,
        ),
        (
            1.0,
            Variant::Mean,
            0.0001559658059697894,
            1.4277942229440002,
            1.4259789677289951,
        ),
        (
            1.0,
            Variant::Consistent,
            0.00013571242676471609,
            1.4365468373816137,
            1.434720454352287,
        ),
        (
            10.0,
            Variant::Coulomb,
            0.0019495725746223674,
            1.0711674480666702,
            0.10698055975527794,
        ),
        (
            10.0,
            Variant::Stiction,
            0.001299715049748245,
            1.1363047310512169,
            0.11348600669282435,
        ),
        (
            10.0,
            Variant::Mean,
            0.001559658059697894,
            1.1051039687393613,
            0.11036989723399218,
        ),
        (
            10.0,
            Variant::Consistent,
            0.001800860475595649,
            1.082578356869946,
            0.10812019988651436,
        ),
    ];
    let m = paper();
    for &(k, variant, v_b, f_ba, t_ba) in table {
        let p = predict_break_away(&m, variant, k, 0.95).unwrap();
        assert!(
            rel(p.v_b, v_b) < 1e-12,
            "{variant} k={k}: v_b {:?} vs {v_b:?}",
            p.v_b
        );
        assert!(
            rel(p.f_ba, f_ba) < 1e-12,
            "{variant} k={k}: F_ba {:?} vs {f_ba:?}",
            p.f_ba
        );
        assert!(
            rel(p.t_ba, t_ba) < 1e-12,
            "{variant} k={k}: t_ba {:?} vs {t_ba:?}",
            p.t_ba
        );
        // phase_velocity at w_b is v_b.
        let v = phase_velocity(&m, variant, k, 0.95).unwrap();
        assert!(rel(v, p.v_b) < 1e-15);
    }
}

#[test]
fn viscous_term_enters_f_ba_and_t_ba() {
    let mut m = paper();
    m.sigma = 2.0;
    let k = 1.0;
    let p = predict_break_away(&m, Variant::Stiction, k, 0.95).unwrap();
    let v_b = 0.0001299715049748245;
    let s = 1.4390602263142336;
    assert!(rel(p.f_ba, s + 2.0 * v_b) < 1e-12);
    assert!(rel(p.t_ba, (s * shape(0.95) + 2.0 * v_b) / k) < 1e-12);
}

#[test]
fn f_ba_falls_from_fs_to_fc_with_k() {
    let m = paper();
    for variant in Variant::ALL {
        let mut prev = f64::INFINITY;
        let n = 400;
        for i in 0..=n {
            // k from 0.01 to 30, log-spaced.
            let k = 0.01 * (3000.0f64).powf(f64::from(i) / f64::from(n));
            let f = predict_break_away(&m, variant, k, 0.95).unwrap().f_ba;
            assert!(f <= prev, "{variant}: F_ba increased at k = {k}");
            assert!(f > m.fc && f < m.fs);
            prev = f;
        }
        let lo = predict_break_away(&m, variant, 0.01, 0.95).unwrap().f_ba;
        let hi = predict_break_away(&m, variant, 30.0, 0.95).unwrap().f_ba;
        assert!(rel(lo, m.fs) < 0.002, "{variant}: F_ba(0.01) = {lo}");
        assert!(rel(hi, m.fc) < 0.02, "{variant}: F_ba(30) = {hi}");
    }
}

#[test]
fn phase_velocity_grows_towards_w_1() {
    let m = paper();
    let mut prev = 0.0;
    for i in 1..100 {
        let w = f64::from(i) / 100.0;
        let v = phase_velocity(&m, Variant::Mean, 1.0, w).unwrap();
        assert!(v > prev);
        // eq. 12 with z_max.
        assert!(rel(v, -1e-5 / (1.25 * w.ln())) < 1e-14);
        prev = v;
    }
}

fn g_of(m: &Model, v: f64) -> f64 {
    v * stribeck(m, v)
}

#[test]
fn consistent_root_solves_its_equation_in_the_monotone_case() {
    let m = paper();
    for i in 0..200 {
        let c = 1e-9 * (1e7f64).powf(f64::from(i) / 200.0);
        let v = consistent_root(&m, c);
        assert!(rel(g_of(&m, v), c) < 1e-12, "c = {c}");
        assert!(v >= c / m.fs && v <= c / m.fc);
    }
    assert_eq!(consistent_root(&m, 0.0), 0.0);
    assert_eq!(consistent_root(&m, -1.0), 0.0);
    assert!(consistent_root(&m, f64::NAN).is_nan());
}

#[test]
fn consistent_root_is_the_smallest_root_when_v_s_is_not_monotone() {
    // Fs = 5·Fc, δ = 2: G(v) = v·S(v) has a local max and a local min.
    let mut m = paper();
    m.fs = 5.0;
    m.delta = 2.0;
    let vs = m.v_stribeck;
    // Locate the local max / min by a fine scan.
    let n = 200_000;
    let grid: Vec<f64> = (0..=n)
        .map(|i| 4.0 * vs * f64::from(i) / f64::from(n))
        .collect();
    let gs: Vec<f64> = grid.iter().map(|&v| g_of(&m, v)).collect();
    let imax = (1..n as usize)
        .find(|&i| gs[i] > gs[i - 1] && gs[i] >= gs[i + 1])
        .unwrap();
    let imin = (imax + 1..n as usize)
        .find(|&i| gs[i] < gs[i - 1] && gs[i] <= gs[i + 1])
        .unwrap();
    let (gmax, gmin) = (gs[imax], gs[imin]);
    assert!(gmin < 0.9 * gmax, "not clearly non-monotone: {gmax} {gmin}");
    let mut three_roots = 0;
    for j in 1..400 {
        let c = gmax * 1.5 * f64::from(j) / 400.0;
        let v = consistent_root(&m, c);
        assert!(
            rel(g_of(&m, v), c) < 1e-12,
            "c = {c}: G(v) = {}",
            g_of(&m, v)
        );
        // Fine scan: G < c everywhere below the root.
        let scan = 20_000;
        for i in 0..scan {
            let u = v * f64::from(i) / f64::from(scan) * (1.0 - 1e-9);
            assert!(g_of(&m, u) < c, "c = {c}: G({u}) >= c below root {v}");
        }
        if c > gmin && c < gmax {
            // A larger root exists beyond the local maximum, the smallest is before it.
            assert!(v <= grid[imax] * (1.0 + 1e-4), "c = {c}: v = {v}");
            let larger = grid[imax..]
                .windows(2)
                .filter(|w| (g_of(&m, w[0]) - c) * (g_of(&m, w[1]) - c) <= 0.0)
                .count();
            assert!(larger >= 2, "c = {c}");
            three_roots += 1;
        } else if c > gmax {
            assert!(v > grid[imin] * (1.0 - 1e-4));
        }
    }
    assert!(three_roots > 10);
    // Just above the local maximum the root jumps beyond the local minimum.
    let below = consistent_root(&m, gmax * (1.0 - 1e-9));
    let above = consistent_root(&m, gmax * (1.0 + 1e-6));
    assert!(above > 1.5 * below, "{below} {above}");
    // predict_break_away uses the same root.
    let k = 1.0;
    let c = -k * m.z_max / 0.95f64.ln();
    let p = predict_break_away(&m, Variant::Consistent, k, 0.95).unwrap();
    assert_eq!(p.v_b, consistent_root(&m, c));
}

#[test]
fn invalid_arguments_name_the_argument() {
    let m = paper();
    let name = |r: Result<BreakAway, PredictError>| match r {
        Err(PredictError::Argument(e)) => e.name,
        other => panic!("{other:?}"),
    };
    for k in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(name(predict_break_away(&m, Variant::Mean, k, 0.95)), "k");
    }
    for w in [0.0, 1.0, -0.5, 1.5, f64::NAN] {
        assert_eq!(name(predict_break_away(&m, Variant::Mean, 1.0, w)), "w_b");
    }
    let mut m0 = paper();
    m0.z_max = 0.0;
    assert_eq!(
        name(predict_break_away(&m0, Variant::Mean, 1.0, 0.95)),
        "z_max"
    );
    let e = predict_break_away(&m, Variant::Mean, 1.0, 1.0).unwrap_err();
    assert!(e.to_string().starts_with("w_b:"), "{e}");
    let e = phase_velocity(&m, Variant::Mean, 1.0, 0.0).unwrap_err();
    assert!(e.to_string().starts_with("w:"), "{e}");
    let mut bad = paper();
    bad.fs = 0.5;
    match predict_break_away(&bad, Variant::Mean, 1.0, 0.95) {
        Err(PredictError::Model(e)) => assert_eq!(e.key, "fs"),
        other => panic!("{other:?}"),
    }
}
