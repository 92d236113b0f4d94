//! Writing a record: `data.csv` (MODEL.md §6), `truth.toml` (MODEL.md §7,
//! with a first comment line) and `truth.json` (machine-readable).

use crate::excite::Family;
use crate::friction::{Effects, Model};
use crate::plants::{PlantSpec, DT};
use crate::record::{Data, Generated};
use serde::Serialize;
use serde_json::{json, Map, Value};
use std::fmt::Write as _;
use std::path::Path;

/// The §7 layout: the base keys in order, then the effect tables.
#[derive(Serialize)]
struct TomlModel {
    mass: f64,
    fc: f64,
    fs: f64,
    v_stribeck: f64,
    delta: f64,
    sigma: f64,
    z_max: f64,
    epsilon: f64,
    #[serde(skip_serializing_if = "Effects::is_empty")]
    effects: Effects,
}

/// The CSV text of the record. Time records: `t,u,x` with `t = k·1e-3` s;
/// steady records: `v,u` after a comment line.
pub fn csv(g: &Generated) -> String {
    let mut s = String::new();
    match &g.data {
        Data::Time { u, x, .. } => {
            s.reserve(u.len() * 48);
            s.push_str("t,u,x\n");
            for (k, (u, x)) in u.iter().zip(x).enumerate() {
                let t = k as f64 / (1.0 / DT).round();
                let _ = writeln!(s, "{t},{u},{x}");
            }
        }
        Data::Steady { v, u } => {
            let _ = writeln!(
                s,
                "# {}: steady-state record, one mean force per constant-velocity run; v [m/s], u [N]",
                g.name()
            );
            s.push_str("v,u\n");
            for (v, u) in v.iter().zip(u) {
                let _ = writeln!(s, "{v},{u}");
            }
        }
    }
    s
}

fn short(x: f64) -> String {
    format!("{x:.3e}")
}

/// The first comment line of `truth.toml`.
pub fn comment(g: &Generated) -> String {
    let d = &g.draw;
    let hidden = if d.hidden.is_empty() {
        "none".to_string()
    } else {
        d.hidden
            .iter()
            .map(|e| e.name())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let absent = if d.stribeck_absent {
        "; stribeck absent (fs = fc)"
    } else {
        ""
    };
    let plant = match &d.spec {
        PlantSpec::Model => "model".to_string(),
        PlantSpec::Lugre { sigma0, sigma1 } => {
            format!(
                "lugre (sigma0 {} N/m, sigma1 {} N·s/m)",
                short(*sigma0),
                short(*sigma1)
            )
        }
        PlantSpec::MaxwellSlip { stiffness, .. } => {
            format!("maxwell_slip ({} elements)", stiffness.len())
        }
        PlantSpec::Compliant {
            m1,
            m2,
            resonance_hz,
            ..
        } => format!(
            "compliant (motor {} kg, load {} kg, resonance {:.1} Hz; encoder on the motor)",
            short(*m1),
            short(*m2),
            resonance_hz
        ),
        PlantSpec::NoisyVelocity { jitter_prob } => format!(
            "noisy_velocity (±1-count encoder jitter, p = {:.3})",
            jitter_prob
        ),
    };
    let vis = g.visibilities(", ").unwrap_or_else(|| "none".to_string());
    format!(
        "# {}: hidden effects: {hidden}{absent}; plant: {plant}; family: {}; force noise std {:.3e} N; encoder {:e} m; visibility: {vis}",
        g.name(),
        d.family.name(),
        d.noise_std,
        d.q
    )
}

/// The §7 TOML of `model` (no comment).
pub fn model_toml(model: &Model) -> Result<String, String> {
    let t = TomlModel {
        mass: model.p.mass,
        fc: model.p.fc,
        fs: model.p.fs,
        v_stribeck: model.p.v_stribeck,
        delta: model.p.delta,
        sigma: model.p.sigma,
        z_max: model.p.z_max,
        epsilon: 0.0,
        effects: model.e,
    };
    toml::to_string(&t).map_err(|e| format!("cannot write TOML: {e}"))
}

/// `truth.toml`: the comment line, then the §7 model.
pub fn truth_toml(g: &Generated) -> Result<String, String> {
    Ok(format!("{}\n{}", comment(g), model_toml(&g.model)?))
}

/// Robust sample-to-sample scatter of the logged force over the noise std:
/// `median(|Δu|)/(0.6745·√2)/noise_std`. About 1 when the only scatter is
/// the Gaussian noise; well above 1 when the loop chatters (a limit cycle).
pub fn u_chatter(u: &[f64], noise_std: f64) -> f64 {
    let mut d: Vec<f64> = u.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    if d.is_empty() || noise_std.is_nan() || noise_std <= 0.0 {
        return f64::NAN;
    }
    let mid = d.len() / 2;
    let (_, m, _) = d.select_nth_unstable_by(mid, f64::total_cmp);
    *m / (0.6745 * std::f64::consts::SQRT_2) / noise_std
}

/// `truth.json`: name, seed, family, plant, hidden, accept_extra,
/// visibility (effect RMS / noise std), noise_std [N], encoder [m], mass
/// [kg], pi, duration [s], u_chatter, and the details.
pub fn truth_json(g: &Generated) -> Value {
    let d = &g.draw;
    let mut vis = Map::new();
    let mut target = Map::new();
    let mut clamped = Vec::new();
    for (j, e) in d.hidden.iter().enumerate() {
        vis.insert(e.name().into(), json!(g.visibility[j]));
        target.insert(e.name().into(), json!(d.targets[j]));
        if g.clamped[j] {
            clamped.push(e.name());
        }
    }
    let model_toml_value: Value = model_toml(&g.model)
        .ok()
        .and_then(|s| toml::from_str::<toml::Value>(&s).ok())
        .and_then(|v| serde_json::to_value(v).ok())
        .unwrap_or(Value::Null);
    let (samples, u_noise_rms, chatter) = match &g.data {
        Data::Time { u, u_clean, .. } => {
            let ss: f64 = u.iter().zip(u_clean).map(|(a, b)| (a - b).powi(2)).sum();
            (
                u.len(),
                (ss / u.len().max(1) as f64).sqrt(),
                u_chatter(u, d.noise_std),
            )
        }
        Data::Steady { v, .. } => (v.len(), d.noise_std, 1.0),
    };
    let absent: Vec<&str> = if d.stribeck_absent {
        vec!["stribeck"]
    } else {
        Vec::new()
    };
    let duration = if d.family == Family::Steady {
        0.0
    } else {
        d.duration
    };
    json!({
        "name": g.name(),
        "seed": d.seed,
        "family": d.family.name(),
        "plant": d.plant.name(),
        "hidden": d.hidden.iter().map(|e| e.name()).collect::<Vec<_>>(),
        "absent": absent,
        "accept_extra": d.plant.accept_extra(),
        "visibility": vis,
        "target_visibility": target,
        "clamped": clamped,
        "noise_std": d.noise_std,
        "u_noise_rms": u_noise_rms,
        "u_chatter": chatter,
        "encoder": d.q,
        "mass": d.model.p.mass,
        "pi": d.pi(),
        "duration": duration,
        "samples": samples,
        "attempt": d.attempt,
        "redraws": g.redraws,
        "simulations": g.sims,
        "controller": {
            "kind": if d.family == Family::VelocityLoop { "pi_velocity" } else { "pid_position" },
            "bandwidth_hz": d.bandwidth_hz,
            "u_max": d.ctx.u_max,
            "ramp_pause": d.ctx.ramp_pause,
            "gains_position": [d.ctx.gains.0, d.ctx.gains.1, d.ctx.gains.2],
            "gains_velocity": [d.ctx.vgains.0, d.ctx.vgains.1],
        },
        "plant_params": d.spec,
        "model": model_toml_value,
        "dwell_clock": dwell_clock(&g.rest_log),
    })
}

/// Least rest [s] before a departure that [`dwell_clock`] counts, and the
/// window [s] after it within which a new rest counts as a restart.
pub const CLOCK_REST: f64 = 0.05;

/// What the dwell clock of the record's simulation did as the axis left
/// its rests (`null` without `dwell_stiction`): the departures from rests
/// of at least [`CLOCK_REST`], and how many of them were followed by a new
/// rest (a dip of `|v|` below `v_rest`, which restarts `t_d`) within
/// [`CLOCK_REST`]. The record's counts cannot show such a dip; see
/// `rest_log.csv` for every change.
pub fn dwell_clock(log: &[(f64, bool)]) -> Value {
    if log.is_empty() {
        return Value::Null;
    }
    let mut rest_start = Some(0.0);
    let (mut departures, mut restarted) = (0, 0);
    for (k, &(t, rest)) in log.iter().enumerate() {
        if rest {
            rest_start = Some(t);
        } else if let Some(s) = rest_start.take() {
            if t - s >= CLOCK_REST {
                departures += 1;
                if log
                    .get(k + 1)
                    .is_some_and(|&(t2, r2)| r2 && t2 - t < CLOCK_REST)
                {
                    restarted += 1;
                }
            }
        }
    }
    json!({
        "departures": departures,
        "restarted_within": CLOCK_REST,
        "restarted": restarted,
    })
}

/// `rest_log.csv`: the dwell clock's changes, `t` [s] and `rest` (1 where
/// a rest begins, 0 where it ends).
pub fn rest_log_csv(log: &[(f64, bool)]) -> String {
    let mut s = String::from("t,rest\n");
    for &(t, rest) in log {
        s.push_str(&format!("{t},{}\n", u8::from(rest)));
    }
    s
}

/// Writes `dir/data.csv`, `dir/truth.toml` and `dir/truth.json`, and with
/// `dwell_stiction` hidden `dir/rest_log.csv`.
pub fn write(g: &Generated, dir: &Path) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: cannot create: {e}", dir.display()))?;
    let put = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(|e| format!("{}: cannot write: {e}", p.display()))
    };
    put("data.csv", &csv(g))?;
    if g.rest_log.is_empty() {
        // Not another record's, left from before.
        let stale = dir.join("rest_log.csv");
        if stale.is_file() {
            std::fs::remove_file(&stale)
                .map_err(|e| format!("{}: cannot remove: {e}", stale.display()))?;
        }
    } else {
        put("rest_log.csv", &rest_log_csv(&g.rest_log))?;
    }
    put("truth.toml", &truth_toml(g)?)?;
    let json = serde_json::to_string_pretty(&truth_json(g))
        .map_err(|e| format!("cannot write JSON: {e}"))?;
    put("truth.json", &(json + "\n"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dwell_clock_counts_departures_and_quick_restarts() {
        // Rest from 0 to 0.2 s, a dip 3 ms after the departure; rest from
        // 0.5 s to 0.52 s (too short to count); rest from 1.0 s to 1.6 s,
        // no new rest within 50 ms; a departure at 2.0 s after a rest of
        // 0.3 s, the log ending in motion.
        let log = [
            (0.2, false),
            (0.203, true),
            (0.204, false),
            (0.5, true),
            (0.52, false),
            (1.0, true),
            (1.6, false),
            (1.7, true),
            (2.0, false),
        ];
        let v = dwell_clock(&log);
        assert_eq!(v["departures"], 3);
        assert_eq!(v["restarted"], 1);
        assert_eq!(dwell_clock(&[]), Value::Null);
        assert_eq!(rest_log_csv(&log[..2]), "t,rest\n0.2,0\n0.203,1\n");
    }
}
