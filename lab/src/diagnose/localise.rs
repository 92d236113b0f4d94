//! Localise: where the residual lies (regimes, worst windows) and which
//! signal of the motion explains it (velocity, direction, position, time,
//! time since a turning point, rest time before motion).

use super::*;

/// The signal that localises each effect (for the report and the plot).
pub fn signal_of(effect: Effect) -> &'static str {
    match effect {
        Effect::Viscous
        | Effect::NonlinearViscous
        | Effect::Offset
        | Effect::Asymmetry
        | Effect::Stribeck
        | Effect::FrictionalLag => "velocity",
        Effect::PositionRipple => "position",
        Effect::DwellStiction => "rest time before motion",
        Effect::Drift => "time",
        Effect::Presliding => "time since turning point",
    }
}

/// Per-sample series of the localising signals: velocity, direction,
/// position, time, time since the last turning point, rest time before the
/// current motion (NaN where not defined).
pub fn signal_series(p: &Prepared, m: &Model) -> Vec<(String, Vec<f64>)> {
    let n = p.len();
    let mut dir = vec![0.0; n];
    let mut since_tp = vec![f64::NAN; n];
    let mut rest_before = vec![f64::NAN; n];
    let mut fr = Friction::new(m, p.t[0], p.x[0], p.v[0]);
    let mut last_d = 0i8;
    let mut t_tp = p.t[0];
    let mut rest_start: Option<f64> = Some(p.t[0]);
    let mut last_rest = 0.0;
    let mut t_motion = p.t[0];
    let rest_speed = p.v_rest;
    for i in 0..n {
        fr.update(m, p.t[i], p.x[i], p.model_velocity(i));
        let d = fr.direction();
        if d != last_d {
            t_tp = p.t[i];
            last_d = d;
        }
        dir[i] = f64::from(d);
        since_tp[i] = p.t[i] - t_tp;
        if p.model_velocity(i).abs() <= rest_speed {
            if rest_start.is_none() {
                rest_start = Some(p.t[i]);
            }
        } else if let Some(s) = rest_start.take() {
            last_rest = p.t[i] - s;
            t_motion = p.t[i];
        }
        if rest_start.is_none() && p.t[i] - t_motion < 0.15 {
            rest_before[i] = last_rest;
        }
    }
    vec![
        ("velocity".into(), p.v.clone()),
        ("direction".into(), dir),
        ("position".into(), p.x.clone()),
        ("time".into(), p.t.clone()),
        ("time since turning point".into(), since_tp),
        ("rest time before motion".into(), rest_before),
    ]
}

/// Fraction of the (weighted) residual power explained by binned means of
/// `r·d` (direction-signed where the effect scales friction) against `s`.
pub(super) fn explained(
    p: &Prepared,
    r: &[f64],
    s: &[f64],
    dir: &[f64],
    signed: bool,
    bins: usize,
) -> f64 {
    let idx: Vec<usize> = p.valid().filter(|&i| s[i].is_finite()).collect();
    let total: f64 = p.valid().map(|i| p.weight[i] * r[i] * r[i]).sum();
    if idx.len() < 2 * bins || total <= 0.0 {
        return 0.0;
    }
    let mut sorted: Vec<f64> = idx.iter().map(|&i| s[i]).collect();
    sorted.sort_by(f64::total_cmp);
    let edges: Vec<f64> = (1..bins)
        .map(|b| sorted[b * (sorted.len() - 1) / bins])
        .collect();
    let mut sum = vec![0.0; bins];
    let mut wsum = vec![0.0; bins];
    for &i in &idx {
        let b = edges.partition_point(|e| *e < s[i]);
        let y = if signed && dir[i] != 0.0 {
            r[i] * dir[i]
        } else {
            r[i]
        };
        sum[b] += p.weight[i] * y;
        wsum[b] += p.weight[i];
    }
    let ex: f64 = sum
        .iter()
        .zip(&wsum)
        .filter(|(_, w)| **w > 0.0)
        .map(|(s, w)| s * s / w)
        .sum();
    ex / total
}

/// How much of `r` each signal explains.
pub fn localise_signals(
    p: &Prepared,
    r: &[f64],
    series: &[(String, Vec<f64>)],
) -> Vec<(String, f64)> {
    let dir = &series[1].1;
    let mut out = Vec::new();
    for (name, s) in series {
        let f = match name.as_str() {
            "velocity" => explained(p, r, s, dir, false, 24),
            "direction" => explained(p, r, s, dir, false, 2),
            "position" => ripple_scan(p, r, false).3,
            "time" => explained(p, r, s, dir, true, 12),
            "time since turning point" => {
                let l: Vec<f64> = s.iter().map(|v| (v + 1e-4).ln()).collect();
                explained(p, r, &l, dir, true, 12)
            }
            _ => explained(p, r, s, dir, true, 6),
        };
        out.push((name.clone(), f));
    }
    out
}

/// Regime label of every sample under model `m`.
pub fn regimes(p: &Prepared, m: &Model) -> Vec<String> {
    let n = p.len();
    let mut fr = Friction::new(m, p.t[0], p.x[0], p.v[0]);
    let mut out = Vec::with_capacity(n);
    let mut rest_len = 0.0;
    let mut rest_start: Option<f64> = Some(p.t[0]);
    let mut breaking = false;
    let mut sliding: Vec<f64> = p
        .valid()
        .map(|i| p.v[i].abs())
        .filter(|s| *s >= 3.0 * m.v_stribeck)
        .collect();
    sliding.sort_by(f64::total_cmp);
    let band = |s: f64| -> String {
        if sliding.len() < 3 {
            return "sliding".into();
        }
        let q1 = sliding[sliding.len() / 3];
        let q2 = sliding[2 * sliding.len() / 3];
        let (a, b) = if s < q1 {
            (sliding[0], q1)
        } else if s < q2 {
            (q1, q2)
        } else {
            (q2, sliding[sliding.len() - 1])
        };
        // Two significant digits, more where they would print one number
        // for both ends of a narrow band.
        let (lo, hi) = (2..=6)
            .map(|sig| (crate::format::short(a, sig), crate::format::short(b, sig)))
            .find(|(lo, hi)| lo != hi)
            .unwrap_or_else(|| (crate::format::short(a, 6), crate::format::short(b, 6)));
        format!("sliding {lo}-{hi} m/s")
    };
    for i in 0..n {
        fr.update(m, p.t[i], p.x[i], p.v[i]);
        let s = p.v[i].abs();
        let d = if fr.direction() >= 0 { "+" } else { "-" };
        if s <= p.v_rest {
            if rest_start.is_none() {
                rest_start = Some(p.t[i]);
            }
            out.push("rest".to_string());
            continue;
        }
        if let Some(st) = rest_start.take() {
            rest_len = p.t[i] - st;
            breaking = rest_len >= 0.02;
        }
        if breaking && s >= 2.0 * m.v_stribeck {
            breaking = false;
        }
        let w = fr.presliding().travel(m.z_max, p.x[i]);
        let label = if w < 1.0 {
            "presliding".to_string()
        } else if breaking {
            "break-away".to_string()
        } else if s < 3.0 * m.v_stribeck {
            "low speed".to_string()
        } else {
            band(s)
        };
        out.push(format!("{label} {d}"));
    }
    let _ = rest_len;
    out
}

/// RMS of `r` per regime label, largest first.
pub fn regime_stats(p: &Prepared, r: &[f64], labels: &[String]) -> Vec<RegimeStat> {
    let mut names: Vec<String> = Vec::new();
    let mut acc: Vec<(usize, f64)> = Vec::new();
    for i in p.valid() {
        let k = match names.iter().position(|n| *n == labels[i]) {
            Some(k) => k,
            None => {
                names.push(labels[i].clone());
                acc.push((0, 0.0));
                names.len() - 1
            }
        };
        acc[k].0 += 1;
        acc[k].1 += r[i] * r[i];
    }
    let mut out: Vec<RegimeStat> = names
        .into_iter()
        .zip(acc)
        .map(|(regime, (n, s))| RegimeStat {
            regime,
            n,
            rms: (s / n.max(1) as f64).sqrt(),
        })
        .collect();
    out.sort_by(|a, b| b.rms.total_cmp(&a.rms));
    out
}

/// Contiguous stretches of one regime, the largest residual first.
pub(super) fn regions_of(p: &Prepared, r: &[f64], labels: &[String], count: usize) -> Vec<Region> {
    let min_len = ((0.01 / p.dt).ceil() as usize).max(3);
    let mut runs = Vec::new();
    let valid = p.valid();
    let mut i = valid.start;
    while i < valid.end {
        let mut j = i;
        let mut s = 0.0;
        while j < valid.end && labels[j] == labels[i] {
            s += r[j] * r[j];
            j += 1;
        }
        if j - i >= min_len {
            runs.push(Region {
                regime: labels[i].clone(),
                t_start: p.t[i],
                t_end: p.t[j - 1],
                rms: (s / (j - i) as f64).sqrt(),
            });
        }
        i = j;
    }
    runs.sort_by(|a, b| b.rms.total_cmp(&a.rms));
    runs.truncate(count);
    runs
}
