//! `breakaway-lab closed-loop`: a PID position loop tracking a sinusoid with
//! reversals, on two plants whose friction is not the compensator's own,
//! with five friction compensators.
//!
//! - Plants: `lugre` — the LuGre model of [`crate::lugre`] (Canudas de Wit
//!   et al. 1995 parameters), the compensator using the library predictor
//!   fitted to its break-away curve; `model` — the MODEL.md model (reference
//!   `Friction`, f64) with Fc +25 %, Fs +20 %, V +30 %, z_max +30 % against
//!   the compensator's parameters.
//! - Loop: period T = 1 ms, x_ref = A·(1 − cos 2πft) (A = 1 mm, f = 1 Hz:
//!   reversals every 0.5 s, peak speed 6.3 mm/s), u = PID(e) + m·a_ref + the
//!   compensation, ideal position and velocity measurement, zero-order hold.
//!   PID by pole placement at (s + ω)³ with ω = 125 rad/s on m = 1 kg.
//! - Compensators: `none`; `coulomb` Fc·sgn(v_ref); `stribeck` F_ss(v_ref)
//!   (MODEL.md §2); `presliding` the library's [`Feedforward`] (MODEL.md §3);
//!   `presliding_observer` the same plus the [`DisturbanceObserver`]'s
//!   residual and the [`LevelAdaptation`] of the level scale.
//! - Figures over the window [5 s, 8 s] (after the observer and adaptation
//!   have settled): RMS of e = x_ref − x, the peak |e| within 50 ms after
//!   each reversal of x_ref, RMS of the total force command u.
//! - Drift: the same runs with the plant's Fc stepped by +20 % at t = 2 s
//!   (plants `lugre_fc+20%`, `model_fc+20%`).
//!
//! Plants are integrated with fixed sub-steps inside each period: LuGre by
//! RK4 with h = 10 µs, the MODEL.md plant by semi-implicit Euler with
//! h = 5 µs, the friction memory updated at every sub-step (a sample in the
//! sense of MODEL.md §3). The firmware example `closed_loop` runs the
//! `model` plant with the same constants in f32 on the MCU.

use breakaway::compensation::{
    AdaptationConfig, DisturbanceObserver, Feedforward, FeedforwardConfig, LevelAdaptation,
    ObserverConfig,
};
use breakaway_reference as reference;

use crate::lugre::{self, LuGre};

/// Control period T [s].
pub const PERIOD: f64 = 1e-3;
/// Amplitude A [m] of x_ref = A·(1 − cos 2πft).
pub const AMPLITUDE: f64 = 1e-3;
/// Frequency f [Hz].
pub const FREQUENCY: f64 = 1.0;
/// Length of a run [s].
pub const DURATION: f64 = 8.0;
/// Start of the evaluation window [s].
pub const WINDOW_START: f64 = 5.0;
/// Time after a reversal [s] over which the peak error is taken.
pub const REVERSAL_WINDOW: f64 = 0.05;
/// Moving mass [kg] of both plants and of the controller's model.
pub const MASS: f64 = 1.0;
/// Closed-loop pole ω [rad/s]: (s + ω)³.
pub const OMEGA: f64 = 125.0;
/// Observer bandwidth [rad/s].
pub const OBSERVER_BANDWIDTH: f64 = 100.0;
/// Adaptation rate γ [1/s].
pub const ADAPTATION_RATE: f64 = 1.0;
/// Time [s] of the +20 % step of the plant's Fc in the drift runs.
pub const DRIFT_TIME: f64 = 2.0;
/// The drift factor: × 1.2.
pub const DRIFT: f64 = 1.2;

/// A step drift of the plant's friction levels at [`DRIFT_TIME`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Drift {
    /// No drift.
    None,
    /// Fc × 1.2 (Fs unchanged, raised to Fc where it would fall below).
    Coulomb,
    /// Fc and Fs × 1.2 (the `drift` effect of MODEL.md §5).
    Levels,
}

impl Drift {
    /// Suffix of the plant name in reports.
    pub fn suffix(self) -> &'static str {
        match self {
            Drift::None => "",
            Drift::Coulomb => "_fc+20%",
            Drift::Levels => "_fc,fs+20%",
        }
    }
}
/// MODEL.md plant sub-steps per period.
pub const MODEL_SUBSTEPS: usize = 200;
/// LuGre plant sub-steps per period.
pub const LUGRE_SUBSTEPS: usize = 100;

/// PID gains (Kp [N/m], Ki [N/(m·s)], Kd [N·s/m]) for (s + ω)³ on m.
pub fn gains() -> (f64, f64, f64) {
    (
        3.0 * MASS * OMEGA * OMEGA,
        MASS * OMEGA.powi(3),
        3.0 * MASS * OMEGA,
    )
}

/// The compensator's parameters for the MODEL.md plant (the paper's Fig. 5
/// setting).
pub const MODEL_COMPENSATOR: breakaway::Params = breakaway::Params {
    fc: 1.0,
    fs: 1.5,
    v_stribeck: 1e-3,
    delta: 1.0,
    sigma: 0.0,
    z_max: 1e-5,
    epsilon: 0.0,
};

/// The MODEL.md plant: Fc +25 %, Fs +20 %, V +30 %, z_max +30 % against
/// [`MODEL_COMPENSATOR`].
pub const MODEL_PLANT: breakaway::Params = breakaway::Params {
    fc: 1.25,
    fs: 1.8,
    v_stribeck: 1.3e-3,
    delta: 1.0,
    sigma: 0.0,
    z_max: 1.3e-5,
    epsilon: 0.0,
};

/// The compensators, in table order.
pub const COMPENSATORS: [Compensator; 5] = [
    Compensator::None,
    Compensator::Coulomb,
    Compensator::Stribeck,
    Compensator::Presliding,
    Compensator::PreslidingObserver,
];

/// A friction compensator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compensator {
    /// No friction compensation.
    None,
    /// Fc·sgn(v_ref).
    Coulomb,
    /// F_ss(v_ref) (MODEL.md §2).
    Stribeck,
    /// The presliding feedforward (MODEL.md §3).
    Presliding,
    /// Presliding feedforward + disturbance observer + level adaptation.
    PreslidingObserver,
}

impl Compensator {
    /// The name used in reports.
    pub fn name(self) -> &'static str {
        match self {
            Compensator::None => "none",
            Compensator::Coulomb => "coulomb",
            Compensator::Stribeck => "stribeck",
            Compensator::Presliding => "presliding",
            Compensator::PreslidingObserver => "presliding_observer",
        }
    }
}

/// Which plant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlantKind {
    /// LuGre, [`LuGre::CANUDAS_1995`].
    LuGre,
    /// MODEL.md, [`MODEL_PLANT`].
    Model,
}

/// A plant integrated inside one control period.
trait Plant {
    fn step(&mut self, u: f64);
    fn position(&self) -> f64;
    fn velocity(&self) -> f64;
    /// Scales the plant's Fc and Fs (drift).
    fn scale_levels(&mut self, fc: f64, fs: f64);
}

struct LuGrePlant(lugre::Plant);

impl Plant for LuGrePlant {
    fn step(&mut self, u: f64) {
        let h = PERIOD / LUGRE_SUBSTEPS as f64;
        for _ in 0..LUGRE_SUBSTEPS {
            self.0.step(&|_| u, 0.0, h);
        }
    }
    fn position(&self) -> f64 {
        self.0.x
    }
    fn velocity(&self) -> f64 {
        self.0.v
    }
    fn scale_levels(&mut self, fc: f64, fs: f64) {
        self.0.model.fc *= fc;
        self.0.model.fs *= fs;
    }
}

struct ModelPlant {
    model: reference::Model,
    friction: reference::Friction,
    x: f64,
    v: f64,
}

impl ModelPlant {
    fn new(p: &breakaway::Params) -> Self {
        let model = reference::Model {
            mass: MASS,
            fc: f64::from(p.fc),
            fs: f64::from(p.fs),
            v_stribeck: f64::from(p.v_stribeck),
            delta: f64::from(p.delta),
            sigma: f64::from(p.sigma),
            z_max: f64::from(p.z_max),
            epsilon: f64::from(p.epsilon),
            effects: reference::Effects::default(),
        };
        let friction = reference::Friction::new(&model, 0.0, 0.0, 0.0);
        ModelPlant {
            model,
            friction,
            x: 0.0,
            v: 0.0,
        }
    }
}

impl Plant for ModelPlant {
    fn step(&mut self, u: f64) {
        let h = PERIOD / MODEL_SUBSTEPS as f64;
        for _ in 0..MODEL_SUBSTEPS {
            // Time only matters for effects; the plant has none.
            let f = self.friction.update(&self.model, 0.0, self.x, self.v);
            self.v += h * (u - f) / self.model.mass;
            self.x += h * self.v;
        }
    }
    fn position(&self) -> f64 {
        self.x
    }
    fn velocity(&self) -> f64 {
        self.v
    }
    fn scale_levels(&mut self, fc: f64, fs: f64) {
        self.model.fc *= fc;
        self.model.fs = (self.model.fs * fs).max(self.model.fc);
    }
}

/// The figures of one run.
#[derive(Clone, Debug, PartialEq)]
pub struct Figures {
    /// Plant name (`lugre`, `model`, `lugre_fc+20%`, `model_fc+20%`).
    pub plant: String,
    /// Compensator name.
    pub compensator: &'static str,
    /// RMS tracking error [m] over the window.
    pub rms_error: f64,
    /// Peak |e| [m] within 50 ms after a reversal, over the window.
    pub peak_reversal_error: f64,
    /// RMS force command [N] over the window.
    pub rms_effort: f64,
    /// (t [s], e [m]) of every period (for plots).
    pub trace: Vec<(f64, f64)>,
}

/// The reference x_ref [m], v_ref [m/s], a_ref [m/s²] at `t` [s].
pub fn reference_at(t: f64) -> (f64, f64, f64) {
    let w = 2.0 * std::f64::consts::PI * FREQUENCY;
    (
        AMPLITUDE * (1.0 - (w * t).cos()),
        AMPLITUDE * w * (w * t).sin(),
        AMPLITUDE * w * w * (w * t).cos(),
    )
}

/// The compensator's model parameters for a plant: for the LuGre plant the
/// library predictor fitted to the LuGre break-away curve
/// ([`lugre::fit_predictor`] on Fc, Fs, σ2 and z_max = 2·Fs/σ0, the bristle
/// travel from −Fs to +Fs).
pub fn compensator_params(plant: PlantKind) -> breakaway::Params {
    match plant {
        PlantKind::Model => MODEL_COMPENSATOR,
        PlantKind::LuGre => {
            let m = LuGre::CANUDAS_1995;
            let base = breakaway::Params {
                z_max: (2.0 * m.fs / m.sigma0) as f32,
                ..lugre::lugre_base()
            };
            let fit = lugre::fit_predictor(&base, &lugre::PUBLISHED_BREAK_AWAY);
            breakaway::Params {
                v_stribeck: fit.v_stribeck as f32,
                delta: fit.delta as f32,
                ..base
            }
        }
    }
}

/// Runs one closed loop with a step `drift` of the plant's levels at
/// [`DRIFT_TIME`].
pub fn run(
    plant_kind: PlantKind,
    compensator: Compensator,
    drift: Drift,
) -> Result<Figures, String> {
    let params = compensator_params(plant_kind);
    let model = breakaway::Model::<f32>::new(params).map_err(|e| e.to_string())?;
    let mut plant: Box<dyn Plant> = match plant_kind {
        PlantKind::LuGre => Box::new(LuGrePlant(lugre::Plant::new(LuGre::CANUDAS_1995))),
        PlantKind::Model => Box::new(ModelPlant::new(&MODEL_PLANT)),
    };
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let mut ff =
        Feedforward::<f32>::new(FeedforwardConfig::default(), 0.0, 1.0).map_err(|e| err(&e))?;
    let mut observer = DisturbanceObserver::new(ObserverConfig {
        mass: MASS as f32,
        bandwidth: OBSERVER_BANDWIDTH as f32,
        period: PERIOD as f32,
    })
    .map_err(|e| err(&e))?;
    let mut adaptation = LevelAdaptation::new(AdaptationConfig {
        rate: ADAPTATION_RATE as f32,
        min_scale: 0.5,
        max_scale: 2.0,
        min_speed: params.v_stribeck,
        period: PERIOD as f32,
    })
    .map_err(|e| err(&e))?;
    let (kp, ki, kd) = gains();
    let steps = (DURATION / PERIOD).round() as usize;
    let (mut integral, mut u, mut u_ff) = (0.0f64, 0.0f64, 0.0f32);
    let (mut sum_e2, mut sum_u2, mut count) = (0.0, 0.0, 0usize);
    let mut trace = Vec::with_capacity(steps);
    let mut drifted = false;
    for n in 0..steps {
        let t = n as f64 * PERIOD;
        if !drifted && t >= DRIFT_TIME {
            match drift {
                Drift::None => {}
                Drift::Coulomb => plant.scale_levels(DRIFT, 1.0),
                Drift::Levels => plant.scale_levels(DRIFT, DRIFT),
            }
            drifted = true;
        }
        let (x_ref, v_ref, a_ref) = reference_at(t);
        let (x, v) = (plant.position(), plant.velocity());
        let e = x_ref - x;
        trace.push((t, e));
        let compensation = match compensator {
            Compensator::None => 0.0,
            Compensator::Coulomb => {
                f64::from(params.fc)
                    * if v_ref > 0.0 {
                        1.0
                    } else if v_ref < 0.0 {
                        -1.0
                    } else {
                        0.0
                    }
            }
            Compensator::Stribeck => f64::from(model.steady_state(v_ref as f32)),
            Compensator::Presliding => f64::from(
                ff.update(&model, x_ref as f32, v_ref as f32)
                    .map_err(|e| err(&e))?,
            ),
            Compensator::PreslidingObserver => {
                let r = observer
                    .update(u as f32, v as f32, u_ff)
                    .map_err(|e| err(&e))?;
                let theta = adaptation
                    .update(r, ff.dry(), v_ref as f32, ff.is_sliding())
                    .map_err(|e| err(&e))?;
                ff.set_level_scale(theta);
                u_ff = ff
                    .update(&model, x_ref as f32, v_ref as f32)
                    .map_err(|e| err(&e))?;
                f64::from(u_ff) + f64::from(r)
            }
        };
        integral += e * PERIOD;
        u = kp * e + ki * integral + kd * (v_ref - v) + MASS * a_ref + compensation;
        if t >= WINDOW_START - 1e-9 {
            sum_e2 += e * e;
            sum_u2 += u * u;
            count += 1;
        }
        plant.step(u);
    }
    let half = 0.5 / FREQUENCY;
    let mut peak = 0.0f64;
    for &(t, e) in &trace {
        let since = t - (t / half).floor() * half;
        let reversal = t - since;
        if reversal >= WINDOW_START - 1e-9
            && since <= REVERSAL_WINDOW + 1e-9
            && reversal + REVERSAL_WINDOW < DURATION
        {
            peak = peak.max(e.abs());
        }
    }
    let name = match plant_kind {
        PlantKind::LuGre => "lugre",
        PlantKind::Model => "model",
    };
    Ok(Figures {
        plant: format!("{name}{}", drift.suffix()),
        compensator: compensator.name(),
        rms_error: (sum_e2 / count.max(1) as f64).sqrt(),
        peak_reversal_error: peak,
        rms_effort: (sum_u2 / count.max(1) as f64).sqrt(),
        trace,
    })
}

/// Every run of the benchmark, in table order: both plants with all
/// compensators, then the drift runs with `presliding` and
/// `presliding_observer`.
pub fn benchmark() -> Result<Vec<Figures>, String> {
    let mut jobs = Vec::new();
    for plant in [PlantKind::LuGre, PlantKind::Model] {
        for c in COMPENSATORS {
            jobs.push((plant, c, Drift::None));
        }
    }
    for plant in [PlantKind::LuGre, PlantKind::Model] {
        for drift in [Drift::Coulomb, Drift::Levels] {
            for c in [Compensator::Presliding, Compensator::PreslidingObserver] {
                jobs.push((plant, c, drift));
            }
        }
    }
    std::thread::scope(|scope| {
        let handles: Vec<_> = jobs
            .chunks(jobs.len().div_ceil(2))
            .map(|chunk| {
                scope.spawn(move || {
                    chunk
                        .iter()
                        .map(|&(p, c, d)| run(p, c, d))
                        .collect::<Result<Vec<_>, String>>()
                })
            })
            .collect();
        let mut all = Vec::new();
        for h in handles {
            all.extend(
                h.join()
                    .map_err(|_| "benchmark thread panicked".to_string())??,
            );
        }
        Ok(all)
    })
}

/// The JSON array of the figures (keys `plant`, `compensator`, `rms_error`,
/// `peak_reversal_error`, `rms_effort`; SI units).
pub fn to_json(rows: &[Figures]) -> String {
    let array: Vec<serde_json::Value> = rows
        .iter()
        .map(|r| {
            serde_json::json!({
                "plant": r.plant,
                "compensator": r.compensator,
                "rms_error": r.rms_error,
                "peak_reversal_error": r.peak_reversal_error,
                "rms_effort": r.rms_effort,
            })
        })
        .collect();
    let mut text = serde_json::to_string_pretty(&array).unwrap_or_default();
    text.push('\n');
    text
}

/// The text table (errors in µm) with the target ratios.
pub fn to_table(rows: &[Figures]) -> String {
    let mut text = format!(
        "{:<16} {:<20} {:>12} {:>18} {:>12}\n",
        "plant", "compensator", "rms_error_um", "peak_reversal_um", "rms_effort_N"
    );
    for r in rows {
        text.push_str(&format!(
            "{:<16} {:<20} {:>12.3} {:>18.3} {:>12.4}\n",
            r.plant,
            r.compensator,
            r.rms_error * 1e6,
            r.peak_reversal_error * 1e6,
            r.rms_effort
        ));
    }
    let peak = |plant: &str, c: &str| {
        rows.iter()
            .find(|r| r.plant == plant && r.compensator == c)
            .map(|r| r.peak_reversal_error)
    };
    text.push_str("\ntargets (peak reversal error):\n");
    for plant in ["lugre", "model"] {
        if let (Some(none), Some(coulomb), Some(pre)) = (
            peak(plant, "none"),
            peak(plant, "coulomb"),
            peak(plant, "presliding"),
        ) {
            text.push_str(&format!(
                "  {plant}: none/presliding = {:.2} (target >= 5), coulomb/presliding = {:.2} (target >= 2)\n",
                none / pre,
                coulomb / pre
            ));
        }
        if let Some(tuned) = peak(plant, "presliding_observer") {
            for drift in [Drift::Coulomb, Drift::Levels] {
                if let Some(after) =
                    peak(&format!("{plant}{}", drift.suffix()), "presliding_observer")
                {
                    text.push_str(&format!(
                        "  {plant}{}: presliding_observer {:.3} um vs tuned {:.3} um: {:+.1} % (target within 10 %)\n",
                        drift.suffix(),
                        after * 1e6,
                        tuned * 1e6,
                        (after / tuned - 1.0) * 100.0
                    ));
                }
            }
        }
    }
    text
}

/// Time [s] of the reversal shown in the SVG plot.
pub const PLOT_REVERSAL: f64 = 6.0;

/// An SVG plot of e(t) around the reversal at [`PLOT_REVERSAL`], one panel
/// per plant, one curve per compensator (no drift).
pub fn to_svg(rows: &[Figures]) -> String {
    const COLOURS: [&str; 5] = ["#7f7f7f", "#d62728", "#ff7f0e", "#1f77b4", "#2ca02c"];
    let (t0, t1) = (PLOT_REVERSAL - 0.02, PLOT_REVERSAL + 0.1);
    let (w, h, margin) = (460.0, 300.0, 55.0);
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
        2.0 * w,
        h + 40.0
    );
    for (panel, plant) in ["lugre", "model"].iter().enumerate() {
        let x0 = panel as f64 * w;
        let curves: Vec<(&Figures, Vec<(f64, f64)>)> = COMPENSATORS
            .iter()
            .filter_map(|c| {
                rows.iter()
                    .find(|r| r.plant == *plant && r.compensator == c.name())
            })
            .map(|r| {
                let pts = r
                    .trace
                    .iter()
                    .filter(|(t, _)| *t >= t0 - 1e-9 && *t <= t1 + 1e-9)
                    .map(|&(t, e)| (t, e * 1e6))
                    .collect();
                (r, pts)
            })
            .collect();
        let limit = curves
            .iter()
            .flat_map(|(_, p)| p.iter().map(|(_, e)| e.abs()))
            .fold(1.0f64, f64::max)
            * 1.1;
        let px = |t: f64| x0 + margin + (t - t0) / (t1 - t0) * (w - 1.5 * margin);
        let py = |e: f64| 20.0 + (1.0 - (e + limit) / (2.0 * limit)) * (h - margin);
        svg.push_str(&format!(
            "<text x=\"{:.1}\" y=\"14\" font-size=\"13\">{plant} plant: e = x_ref − x [µm] around the reversal at t = {PLOT_REVERSAL} s</text>\n",
            x0 + margin
        ));
        svg.push_str(&format!(
            "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"black\"/>\n",
            px(t0),
            py(0.0),
            px(t1),
            py(0.0)
        ));
        svg.push_str(&format!(
            "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"black\"/>\n",
            px(t0),
            py(limit),
            px(t0),
            py(-limit)
        ));
        svg.push_str(&format!(
            "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"#aaa\" stroke-dasharray=\"3,3\"/>\n",
            px(PLOT_REVERSAL), py(limit), px(PLOT_REVERSAL), py(-limit)
        ));
        for (value, anchor) in [(limit / 1.1, "end"), (0.0, "end"), (-limit / 1.1, "end")] {
            svg.push_str(&format!(
                "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"{anchor}\">{value:.1}</text>\n",
                px(t0) - 4.0,
                py(value) + 4.0
            ));
        }
        for ms in [-20, 0, 20, 40, 60, 80, 100] {
            let t = PLOT_REVERSAL + f64::from(ms) * 1e-3;
            svg.push_str(&format!(
                "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{ms} ms</text>\n",
                px(t),
                h - margin + 38.0
            ));
        }
        for (i, (r, pts)) in curves.iter().enumerate() {
            let colour = COLOURS[i % COLOURS.len()];
            let path: Vec<String> = pts
                .iter()
                .map(|&(t, e)| format!("{:.1},{:.1}", px(t), py(e)))
                .collect();
            svg.push_str(&format!(
                "<polyline fill=\"none\" stroke=\"{colour}\" stroke-width=\"1.5\" points=\"{}\"/>\n",
                path.join(" ")
            ));
            svg.push_str(&format!(
                "<text x=\"{:.1}\" y=\"{:.1}\" fill=\"{colour}\">{}</text>\n",
                x0 + w - 1.5 * margin - 60.0,
                40.0 + 14.0 * i as f64,
                r.compensator
            ));
        }
    }
    svg.push_str("</svg>\n");
    svg
}

/// `breakaway-lab closed-loop`: the benchmark as a table or JSON, and
/// optionally the SVG plot.
pub fn command(
    args: &crate::cli::ClosedLoopArgs,
    out: &mut dyn std::io::Write,
) -> Result<(), crate::Error> {
    use crate::Error;
    let rows = benchmark().map_err(Error::Runtime)?;
    if let Some(path) = &args.svg {
        std::fs::write(path, to_svg(&rows))
            .map_err(|e| Error::Runtime(format!("writing {}: {e}", path.display())))?;
    }
    let text = if args.json {
        to_json(&rows)
    } else {
        to_table(&rows)
    };
    crate::emit(out, &text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_loop_json_and_measured_ratios() {
        let mut out = Vec::new();
        crate::run(&["closed-loop".to_string(), "--json".to_string()], &mut out).unwrap();
        let rows: Vec<serde_json::Value> = serde_json::from_slice(&out).unwrap();
        assert_eq!(rows.len(), 18);
        let keys = [
            "compensator",
            "peak_reversal_error",
            "plant",
            "rms_effort",
            "rms_error",
        ];
        for row in &rows {
            let mut got: Vec<&str> = row
                .as_object()
                .unwrap()
                .keys()
                .map(String::as_str)
                .collect();
            got.sort_unstable();
            assert_eq!(got, keys);
        }
        let peak = |plant: &str, c: &str| {
            rows.iter()
                .find(|r| r["plant"] == plant && r["compensator"] == c)
                .and_then(|r| r["peak_reversal_error"].as_f64())
                .unwrap()
        };
        for plant in ["lugre", "model"] {
            let none = peak(plant, "none");
            let coulomb = peak(plant, "coulomb");
            let pre = peak(plant, "presliding");
            let obs = peak(plant, "presliding_observer");
            // Measured (see COMPENSATION.md): none/presliding 3.1 (lugre),
            // 3.3 (model), below the 5; coulomb/presliding 1.4, 1.65,
            // below its 2. Observer + adaptation: 20× and 26×.
            assert!(none / pre > 3.0, "{plant}: {none} / {pre}");
            assert!(coulomb / pre > 1.3, "{plant}: {coulomb} / {pre}");
            assert!(none / obs > 15.0 && coulomb / obs > 5.0, "{plant}: {obs}");
            // After a drift the observer + adaptation stays well below the
            // plain presliding feedforward.
            for drift in [Drift::Coulomb, Drift::Levels] {
                let name = format!("{plant}{}", drift.suffix());
                assert!(peak(&name, "presliding_observer") < 0.6 * peak(&name, "presliding"));
            }
        }
        // A drift of both levels (what the single scale θ models) on the
        // MODEL.md plant: back to within 20 % of the tuned figure (measured
        // +17 %; the target of 10 % is missed, see COMPENSATION.md).
        let tuned = peak("model", "presliding_observer");
        assert!(peak("model_fc,fs+20%", "presliding_observer") < 1.2 * tuned);
    }
}
