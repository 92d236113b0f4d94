//! Report: the JSON report, the model in MODEL.md §7 names and the text a
//! user reads.

use super::*;
use crate::format::short;
use std::fmt::Write as _;

/// The model as a JSON object with the MODEL.md §7 names.
pub fn model_json(m: &Model) -> serde_json::Value {
    let mut o = serde_json::json!({
        "mass": m.mass, "fc": m.fc, "fs": m.fs, "v_stribeck": m.v_stribeck,
        "delta": m.delta, "sigma": m.sigma, "z_max": m.z_max, "epsilon": m.epsilon,
    });
    let e = effect_params_all(m);
    if !e.is_empty() {
        o["effects"] = serde_json::Value::Object(e);
    }
    o
}

/// The effects of `m` with a table under `[effects]` (MODEL.md §7; the
/// others are keys of the model itself), by name.
pub(super) fn effect_params_all(m: &Model) -> serde_json::Map<String, serde_json::Value> {
    let mut map = serde_json::Map::new();
    for effect in Effect::ALL {
        if effect.has_table() && fit::has_effect(m, effect) {
            map.insert(effect.name().into(), effect_params(m, effect));
        }
    }
    map
}

/// The fitted parameters of one effect (MODEL.md §7 names).
pub fn effect_params(m: &Model, effect: Effect) -> serde_json::Value {
    let e = &m.effects;
    use serde_json::json;
    match effect {
        Effect::Viscous => json!({"sigma": m.sigma}),
        Effect::Stribeck => json!({"fs": m.fs, "v_stribeck": m.v_stribeck, "delta": m.delta}),
        Effect::Presliding => json!({"z_max": m.z_max}),
        Effect::Offset => json!({"f0": e.offset.map(|o| o.f0)}),
        Effect::Asymmetry => json!({"a": e.asymmetry.map(|a| a.a)}),
        Effect::PositionRipple => e.position_ripple.map_or(
            json!({}),
            |r| json!({"amplitude": r.amplitude, "wavelength": r.wavelength, "phase": r.phase}),
        ),
        Effect::DwellStiction => e.dwell_stiction.map_or(
            json!({}),
            |d| json!({"delta_fs": d.delta_fs, "gamma": d.gamma, "v_rest": d.v_rest}),
        ),
        Effect::FrictionalLag => json!({"tau_l": e.frictional_lag.map(|l| l.tau_l)}),
        Effect::Drift => json!({"beta": e.drift.map(|d| d.beta)}),
        Effect::NonlinearViscous => e
            .nonlinear_viscous
            .map_or(json!({}), |nv| json!({"sigma_n": nv.sigma_n, "n": nv.n})),
    }
}

/// Candidates `(effect, held-out rms [N], BIC change)` as a JSON list of
/// objects (`effect`, `rms`, `score`), for the steps and the rejected list
/// of both reports.
pub fn candidates_json(
    candidates: impl IntoIterator<Item = (Effect, f64, f64)>,
) -> serde_json::Value {
    candidates
        .into_iter()
        .map(|(effect, rms, score)| serde_json::json!({"effect": effect.name(), "rms": rms, "score": score}))
        .collect()
}

/// The keys every accepted step has in both reports (dynamic and
/// steady-state): effect, its fitted parameters, model error before and
/// after [N], BIC change and the round's candidates `(effect, rms [N],
/// score)`.
pub fn step_json(
    effect: Effect,
    model: &Model,
    (rms_before, rms_after, score): (f64, f64, f64),
    candidates: impl IntoIterator<Item = (Effect, f64, f64)>,
) -> serde_json::Value {
    serde_json::json!({
        "effect": effect.name(),
        "params": effect_params(model, effect),
        "rms_before": rms_before,
        "rms_after": rms_after,
        "score": score,
        "candidates": candidates_json(candidates),
    })
}

/// The JSON report (keys in lab/README.md).
pub fn report_json(rep: &Report) -> String {
    use serde_json::json;
    let steps: Vec<_> = rep
        .steps
        .iter()
        .map(|s| {
            let round = s.candidates.iter().map(Candidate::summary);
            let mut j = step_json(
                s.effect,
                &s.model,
                (s.rms_before, s.rms_after, s.score),
                round,
            );
            j["signal"] = json!(s.signal.0);
            j["signal_explained"] = json!(s.signal.1);
            j["tied_with"] = json!(tied_look_alike(s, rep.floor).map(|(e, _, _)| e.name()));
            j["joint_with"] = json!(s.joint.map(Effect::name));
            j["gain_where_acting"] = json!(s.where_acting);
            j
        })
        .collect();
    let mut v = json!({
        "effects_added": rep.effects_added().map(Effect::name).collect::<Vec<_>>(),
        "restored": rep.restored().map(Effect::name).collect::<Vec<_>>(),
        "metric": METRIC,
        "rms_before": rep.rms_before,
        "rms_after": rep.rms_after,
        "rms_given": rep.given,
        "rms_raw_before": rep.raw_before,
        "rms_raw_after": rep.raw_after,
        "floor": rep.floor,
        "floor_estimate": rep.floor_estimate,
        "judged": rep.judged,
        "moving_held_out": rep.moving_held_out,
        "noise_std": rep.sigma0,
        "floor_explains": if rep.raw_after > 0.0 { (rep.floor / rep.raw_after).powi(2).min(1.0) } else { 1.0 },
        "still_samples": rep.still.0,
        "bursts": {
            "samples": rep.bursts.samples,
            "moving_samples": rep.moving,
            "unweighted": rep.bursts.unweighted,
            "first_pass": rep.bursts.first_pass.as_ref().map(|f| json!({
                "effects_added": f.effects.iter().map(|e| e.name()).collect::<Vec<_>>(),
                "rms_before": f.rms_before,
                "rms_after": f.rms_after,
            })),
        },
        "valid_samples": rep.still.1,
        "mass_identified": !fit::mass_at_bound(&rep.model),
        "static_level": rep.static_level.map(|l| json!({"held": l.held, "fs_fitted": l.fitted, "fs_written": l.written, "raised": l.raised(), "dip_restored": l.restored})),
        "dwell_rests": dwell_rests_json(rep),
        "lost_motion": lost_motion(&rep.model).map(|z| json!({"z_max": z, "counts": z / rep.resolution})),
        "base_refit": rep.base_refit,
        "base_reshaped": rep.base_reshaped,
        "dropped": rep.dropped.iter().map(|(n, why)| json!({"part": n.name(), "reason": why})).collect::<Vec<_>>(),
        "regions": rep.regions.iter().map(|r| json!({"regime": r.regime, "t_start": r.t_start, "t_end": r.t_end, "rms": r.rms})).collect::<Vec<_>>(),
        "regimes": rep.regimes.iter().map(|r| json!({"regime": r.regime, "n": r.n, "rms": r.rms})).collect::<Vec<_>>(),
        "signals": rep.signals.iter().map(|(n, f)| json!({"signal": n, "explained": f})).collect::<Vec<_>>(),
        "steps": steps,
        "at_breakaways": rep.at_breakaways.iter().map(|(a, b, v)| json!({"effect": a.name(), "look_alike": b.name(), "departures": v.departures, "ramp_pairs": v.ramp_pairs, "lambda": v.lambda, "se": v.se, "decided": v.decided().map(|alt| if alt { b.name() } else { a.name() })})).collect::<Vec<_>>(),
        "swapped": rep.swapped.iter().map(|(a, b, before, after)| json!({"effect": a.name(), "replaced_by": b.name(), "rms_before": before, "rms_after": after})).collect::<Vec<_>>(),
        "pruned": rep.pruned.iter().map(|(n, without, with)| json!({"effect": n.name(), "rms_without": without, "rms_with": with})).collect::<Vec<_>>(),
        "rejected": candidates_json(rep.last_round.iter().map(Candidate::summary)),
        "accept_gain": ACCEPT_GAIN,
        "min_gap_share": MIN_GAP_SHARE,
        "start_model": model_json(&rep.start),
        "model": model_json(&rep.model),
        "samples": rep.n,
        "window": rep.half_width,
        "velocity_window": rep.velocity_half_width,
        "dt": rep.dt,
        "resolution": rep.resolution,
    });
    // Beside the object above, which is at `json!`'s recursion limit.
    v["version"] = json!(super::WORKFLOW_VERSION);
    v["kept_at_bound"] = rep
        .kept_at_bound
        .iter()
        .map(|(n, why, without)| json!({"part": n.name(), "reason": why, "rms_without": without}))
        .collect();
    let mut s = serde_json::to_string_pretty(&v).unwrap_or_else(|_| "{}".into());
    s.push('\n');
    s
}

/// The static level the still samples show against the fitted `Fs`.
fn write_static_level(rep: &Report, s: &mut String) {
    let Some(l) = rep.static_level else {
        return;
    };
    if !l.held.iter().any(|h| h.is_finite()) {
        let _ = writeln!(s, "static level: no still samples to read it from");
        return;
    }
    let [up, down] = l.held.map(|h| {
        if h.is_finite() {
            format!("{} N", short(h, 4))
        } else {
            "nothing".into()
        }
    });
    let _ = if l.restored {
        writeln!(
            s,
            "static level: the still axis held {up} (+) and {down} (-) where the model had no Stribeck dip (Fs = Fc = {} N); a dip restored from the held level (Fs - Fc fixed there, the rest refitted), Fs written {} N (the held-out model error no higher than without it; where the motion does not resolve the dip, V and delta are only the best of the starts)",
            short(l.fitted, 4),
            short(l.written, 4)
        )
    } else if l.raised() {
        writeln!(
            s,
            "static level: the still axis held {up} (+) and {down} (-) where the fit put Fs at {} N; Fs written at the held level, {} N, the rest refitted (the residual does not weigh still samples, so nothing else bounds Fs from below)",
            short(l.fitted, 4),
            short(l.written, 4)
        )
    } else {
        // Not raised: within Fs, or above it where `pin` leaves Fs as
        // fitted; the line says which.
        let fs = short(l.fitted, 4);
        let above = l
            .held
            .map(|h| h.is_finite() && h > l.fitted * (1.0 + super::held::MIN_RAISE));
        let how = match above {
            [false, false] if l.held.iter().all(|&h| h <= l.fitted) => format!("within Fs = {fs} N"),
            [false, false] => format!(
                "within {:.0} % of Fs = {fs} N",
                100.0 * super::held::MIN_RAISE
            ),
            [true, true] if !fit::has_effect(&rep.model, Effect::Stribeck) => format!(
                "above the fitted Fs = {fs} N in both directions; Fs left as fitted: the model has no Stribeck dip, and one restored at the held level was not sound or raised the held-out model error"
            ),
            [true, true] => format!(
                "above the fitted Fs = {fs} N in both directions; Fs left as fitted: no sound refit with Fs at the held level"
            ),
            _ => format!(
                "above the fitted Fs = {fs} N in one direction only; Fs is raised where both directions hold above it"
            ),
        };
        writeln!(
            s,
            "static level: the still axis held {up} (+) and {down} (-), {how}"
        )
    };
}

/// The rests behind a named `dwell_stiction` and whether the record shows
/// its rise saturate (γ within the longest rest) or only its start, where
/// `ΔFs` and `γ` are resolved mostly as their ratio, the rise rate.
fn dwell_rests_json(rep: &Report) -> serde_json::Value {
    match (rep.dwell_rests, rep.model.effects.dwell_stiction) {
        (Some((shortest, longest, count)), Some(d)) => serde_json::json!({
            "shortest": shortest,
            "longest": longest,
            "count": count,
            "rise_rate": d.delta_fs / d.gamma,
            "saturation_seen": d.gamma <= longest,
            "gamma_at_cap": gamma_at_cap(d.gamma, longest),
        }),
        _ => serde_json::Value::Null,
    }
}

/// Whether `gamma` [s] sits at the top of its range on a record whose
/// longest rest is `longest` [s] ([`fit::dwell_gamma_cap`]).
fn gamma_at_cap(gamma: f64, longest: f64) -> bool {
    gamma >= fit::gamma_cap_of(longest) * (1.0 - 1e-9)
}

/// The text line of [`dwell_rests_json`].
fn write_dwell_rests(rep: &Report, s: &mut String) {
    let (Some((shortest, longest, count)), Some(d)) =
        (rep.dwell_rests, rep.model.effects.dwell_stiction)
    else {
        return;
    };
    let _ = write!(
        s,
        "dwell: {count} rests of {} s or more end in motion, {} to {} s; γ = {} s",
        super::selection::MIN_DWELL_REST,
        short(shortest, 3),
        short(longest, 3),
        short(d.gamma, 3)
    );
    let _ = if d.gamma <= longest {
        writeln!(s)
    } else {
        writeln!(
            s,
            ", longer than every rest{}: the record shows the rise before it saturates, so ΔFs and γ are resolved mostly as their ratio ΔFs/γ = {} N/s",
            if gamma_at_cap(d.gamma, longest) {
                format!(
                    " (at the top of its range, {} times the longest rest)",
                    fit::GAMMA_CAP_RESTS
                )
            } else {
                String::new()
            },
            short(d.delta_fs / d.gamma, 3)
        )
    };
}

pub(super) fn pct(before: f64, after: f64) -> String {
    format!("{:.0} %", 100.0 * (before - after) / before)
}

/// The terminal text.
pub fn report_text(rep: &Report, source: &str) -> String {
    let mut s = String::new();
    write_measurement(rep, source, &mut s);
    write_start(rep, &mut s);
    for (k, st) in rep.steps.iter().enumerate() {
        write_step(rep, k, st, &mut s);
    }
    write_outcome(rep, &mut s);
    write_static_level(rep, &mut s);
    write_dwell_rests(rep, &mut s);
    write_model(&rep.model, &mut s);
    s
}

/// The record, the residual and its floor, and what was dropped or
/// refitted before the candidates.
fn write_measurement(rep: &Report, source: &str, s: &mut String) {
    let _ = writeln!(
        s,
        "{source}: {} samples, dt = {} s, position resolution {} m, window ±{} samples",
        rep.n,
        short(rep.dt, 4),
        short(rep.resolution, 3),
        rep.half_width
    );
    let _ = writeln!(s, "residual: force along the measured motion (MODEL.md §8: compared locally), held-out blocks 2, 5, ..., 29 of 30 (every third; consecutive blocks with equal numbers of moving samples)");
    let _ = writeln!(
        s,
        "measurement floor: {} N of the held-out rms is force noise (σ0 = {} N) and encoder resolution; {} of {} samples are still (friction = measured force, not scored); figures below are model error above that floor",
        short(rep.floor, 3),
        short(rep.sigma0, 3),
        rep.still.0,
        rep.still.1
    );
    if let Some(f) = &rep.bursts.first_pass {
        let named: Vec<&str> = f.effects.iter().map(|e| e.name()).collect();
        let _ = writeln!(
            s,
            "        {} of {} moving samples lie within the kernel of a burst (the axis sticks and slips faster than the sampling): not scored here, as weighed they left the gap at {} N of {} N (named: [{}])",
            rep.bursts.samples,
            rep.moving,
            short(f.rms_after, 3),
            short(f.rms_before, 3),
            named.join(", ")
        );
    } else if rep.bursts.samples > 0 {
        let _ = writeln!(
            s,
            "        {} of {} moving samples lie within the kernel of a burst (the axis sticks and slips faster than the sampling); weighed as any moving sample",
            rep.bursts.samples,
            rep.moving
        );
    }
    if let Some(est) = rep.floor_estimate {
        let _ = writeln!(
            s,
            "        (estimated from the start model's residual: {} N; a first-round candidate's held-out rms came out below that, so the floor is taken as that rms)",
            short(est, 3)
        );
    }
    for (part, why) in &rep.dropped {
        let _ = writeln!(s, "not identifiable here, dropped: `{part}` ({why})");
    }
    if let Some(why) = &rep.base_refit {
        let _ = writeln!(s, "presliding first fitted into a local minimum, fitted again before the candidates: {why}");
    }
    if let Some(why) = &rep.base_reshaped {
        let _ = writeln!(
            s,
            "base shape identified again with the named effects in place: {why}"
        );
    }
    for (part, why, without) in &rep.kept_at_bound {
        let _ = writeln!(
            s,
            "kept at a bound: `{part}` ({why}); without it the held-out model error is {} N against {} N with it, so the record needs the shape, but not at a value inside its range: the named effects may stand in for others (a look-alike, or an effect the catalogue lacks)",
            short(*without, 4),
            short(rep.rms_after, 4)
        );
    }
    if fit::mass_at_bound(&rep.model) {
        let _ = writeln!(
            s,
            "not identifiable here: the mass ran to its lower limit ({:e} kg); the record's accelerations do not resolve the inertia, and the mass written below is not a value of the axis",
            fit::MASS_MIN
        );
    }
}

/// The start model's gap and where it lies.
fn write_start(rep: &Report, s: &mut String) {
    if let Some(g) = rep.given {
        let _ = writeln!(
            s,
            "given model: held-out model error {} N as given, {} N refitted",
            short(g, 4),
            short(rep.rms_before, 4)
        );
    } else {
        let _ = writeln!(
            s,
            "start: base model (Coulomb + Stribeck + presliding) identified from the data, held-out model error {} N",
            short(rep.rms_before, 4)
        );
    }
    if let Some(top) = rep.regimes.first() {
        let _ = writeln!(
            s,
            "largest disagreement: {} (rms {} N over {} samples)",
            top.regime,
            short(top.rms, 3),
            top.n
        );
    }
    if let Some(r) = rep.regions.first() {
        let _ = writeln!(
            s,
            "worst window: {} at t = {}-{} s (rms {} N)",
            r.regime,
            short(r.t_start, 5),
            short(r.t_end, 5),
            short(r.rms, 3)
        );
    }
    let mut sig = rep.signals.clone();
    sig.sort_by(|a, b| b.1.total_cmp(&a.1));
    let list: Vec<String> = sig
        .iter()
        .map(|(n, f)| format!("{n} {:.0} %", 100.0 * f))
        .collect();
    let _ = writeln!(s, "residual explained by: {}", list.join(", "));
}

/// Step `k` (from 0): the effect, the gap before and after, ties, the
/// break-away verdict, the runner-ups and the fitted parameters.
fn write_step(rep: &Report, k: usize, st: &Step, s: &mut String) {
    let _ = writeln!(
        s,
        "step {}: missing effect `{}` (lines up with {}, {:.0} % explained); adding it shrinks the gap from {} N to {} N ({}), ΔBIC {}",
        k + 1,
        st.effect,
        st.signal.0,
        100.0 * st.signal.1,
        short(st.rms_before, 4),
        short(st.rms_after, 4),
        pct(st.rms_before, st.rms_after),
        short(st.score, 4)
    );
    if let Some(other) = st.joint {
        let alone: Vec<String> = [st.effect, other]
            .iter()
            .filter_map(|&e| st.candidates.iter().find(|c| c.effect == e))
            .map(|c| {
                format!(
                    "{} {} N",
                    c.effect,
                    short(residual::model_error(c.rms, rep.floor), 3)
                )
            })
            .collect();
        let _ = writeln!(
            s,
            "        fitted together with `{other}`: neither passed alone (model error alone: {}; the step's figures are the pair's)",
            alone.join(", ")
        );
    }
    if let Some(g) = st.where_acting {
        let _ = writeln!(
            s,
            "        named on its gain where it acts: {:.0} % above the floor there, on the held-out moves where it changes the force by more than the noise (over all moves its gain is diluted below {:.1} %)",
            100.0 * g,
            100.0 * required_gain(st.effect)
        );
    }
    if let Some((other, mine, theirs)) = tied_look_alike(st, rep.floor) {
        let _ = writeln!(
            s,
            "        `{other}` fits as well (model error {} vs {} N): the weighted residual does not tell them apart (they differ only in the Stribeck dip and at break-away)",
            short(theirs, 4),
            short(mine, 4)
        );
    }
    let checked = rep
        .at_breakaways
        .iter()
        .find(|(a, b, _)| *a == st.effect || *b == st.effect);
    if let Some((a, b, v)) = checked {
        let swapped = rep.swapped.iter().any(|(x, y, _, _)| (x, y) == (a, b));
        let said = match v.decided() {
            Some(true) if !swapped => {
                format!("follow `{b}`, but sample by sample `{a}` fits clearly better and is kept")
            }
            Some(true) => format!("follow `{b}`"),
            Some(false) => format!("follow `{a}`"),
            None if !v.consistent() => "follow neither model".to_string(),
            None => "do not decide".to_string(),
        };
        let compared = if v.ramp_pairs > 0 {
            format!("{} pairs of force ramps at matched rates", v.ramp_pairs)
        } else {
            format!("{} departures after reversals and rests", v.departures)
        };
        let _ = writeln!(
            s,
            "        at the break-aways ({compared}) the friction peaks {said}: lambda {} +- {} (0 `{a}`, 1 `{b}`)",
            short(v.lambda, 3),
            short(v.se, 2)
        );
    }
    let others: Vec<String> = st
        .candidates
        .iter()
        .skip(1)
        .take(3)
        .map(|c| format!("{} {} N", c.effect, short(c.rms, 3)))
        .collect();
    if !others.is_empty() {
        let _ = writeln!(s, "        next best: {}", others.join(", "));
    }
    // A closer general form left behind by the nested rule, said where it
    // shows (the list is in the order the round took, not by rms).
    let general = st
        .candidates
        .iter()
        .find(|c| c.effect == Effect::NonlinearViscous);
    if let (Effect::Viscous, Some(g)) = (st.effect, general) {
        let taken = st.candidates.first().map_or(f64::NAN, |c| c.rms);
        if g.rms < taken {
            let _ = writeln!(
                s,
                "        (`nonlinear_viscous` fits closer, but the general form is named only where its model error is {} % below that of `viscous`: lab/README.md, *Candidates and selection*)",
                short(100.0 * super::selection::NESTED_GAP_GAIN, 2)
            );
        }
    }
    let _ = writeln!(s, "        fitted: {}", effect_params(&st.model, st.effect));
}

/// Why the search stopped, the swaps and drops after it, the best
/// rejected candidate and the effects named.
fn write_outcome(rep: &Report, s: &mut String) {
    if !rep.judged {
        let _ = writeln!(
            s,
            "too still to judge: {} moving samples in the held-out blocks (fewer than {}: {} force windows of motion), so no effect is named; a record with more motion is needed",
            rep.moving_held_out,
            min_moving_held_out(rep.half_width),
            MIN_HELD_OUT_WINDOWS
        );
    } else if rep.steps.is_empty() {
        let _ = writeln!(s, "no effect is missing: no candidate lowers the held-out rms by {:.0} % above the floor and removes {:.0} % of the gap with a better BIC", 100.0 * ACCEPT_GAIN, 100.0 * MIN_GAP_SHARE);
    } else {
        let _ = writeln!(
            s,
            "done: no further candidate lowers the held-out rms by {:.0} % above the floor and removes {:.0} % of the gap; gap {} N -> {} N ({}); the remaining rms {} N is {:.0} % noise and resolution",
            100.0 * ACCEPT_GAIN,
            100.0 * MIN_GAP_SHARE,
            short(rep.rms_before, 4),
            short(rep.rms_after, 4),
            pct(rep.rms_before, rep.rms_after),
            short(rep.raw_after, 3),
            100.0 * (rep.floor / rep.raw_after.max(1e-300)).powi(2).min(1.0)
        );
    }
    for (a, b, before, after) in &rep.swapped {
        let at_breakaways = rep
            .at_breakaways
            .iter()
            .any(|(x, y, v)| (x, y) == (a, b) && v.decided() == Some(true));
        let why = if at_breakaways {
            "a tie sample by sample, decided at the break-aways"
        } else if nested(*a, *b) {
            "the nested pair's rule: the general form at a tenth less model error"
        } else {
            "lower held-out BIC"
        };
        let _ = writeln!(
            s,
            "swap check: `{a}` replaced by `{b}` (model error {} N -> {} N, {why})",
            short(*before, 4),
            short(*after, 4)
        );
    }
    for (n, without, with) in &rep.pruned {
        let _ = writeln!(
            s,
            "backward check: `{n}`, named in one of the rounds, dropped again (held-out rms {} N without it, {} N with it; the steps above are those kept)",
            short(*without, 4),
            short(*with, 4)
        );
    }
    if let Some(c) = rep.last_round.first() {
        let _ = writeln!(
            s,
            "best rejected candidate: {} (held-out rms {} N, ΔBIC {})",
            c.effect,
            short(c.rms, 4),
            short(c.score, 4)
        );
    }
    let added: Vec<&str> = rep.effects_added().map(Effect::name).collect();
    let _ = writeln!(s, "effects added: [{}]", added.join(", "));
    if let Some(z) = lost_motion(&rep.model) {
        let _ = writeln!(
            s,
            "lost motion: the fitted presliding distance z_max = {} (m, or rad on a rotary axis; {:.0} encoder counts) exceeds {}, beyond a contact's presliding (1-100 µm) or a gear stage's lost motion (about 3e-4 rad): backlash or a compliant transmission between the encoder and the friction, which the catalogue does not model and the names above may stand in for",
            short(z, 3),
            z / rep.resolution,
            short(LOST_MOTION, 1)
        );
    }
    let restored: Vec<&str> = rep.restored().map(Effect::name).collect();
    if !restored.is_empty() {
        let _ = writeln!(
            s,
            "base parts restored: [{}] (lost by the base fit, part of the base model)",
            restored.join(", ")
        );
    }
}

/// The final model by its MODEL.md §7 names.
fn write_model(m: &Model, s: &mut String) {
    // The base parameters by their MODEL.md §7 names, each to its digits.
    let base = [
        ("mass", m.mass, 5),
        ("fc", m.fc, 5),
        ("fs", m.fs, 5),
        ("v_stribeck", m.v_stribeck, 4),
        ("delta", m.delta, 3),
        ("sigma", m.sigma, 5),
        ("z_max", m.z_max, 3),
    ];
    s.push_str("model:");
    for (name, value, digits) in base {
        let _ = write!(s, " {name} {}", short(value, digits));
    }
    let effects = effect_params_all(m);
    if !effects.is_empty() {
        let _ = write!(s, " effects {}", serde_json::Value::Object(effects));
    }
    s.push('\n');
}

/// Parameter list for `fit` output.
pub fn params_json(params: &[Param]) -> Vec<String> {
    params.iter().map(|p| format!("{p:?}")).collect()
}
