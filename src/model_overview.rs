//! The friction model this crate computes: every equation, with its units.
//!
//! This page holds no code. It is the reference the rest of the
//! documentation points to: each module names the section below that it
//! implements. The model is the one of M. Ruderman, "On break-away forces in
//! actuated motion systems with nonlinear friction" (Mechatronics); where the
//! paper leaves a choice open (signs, scaling, the deadband, the start from
//! rest) the rule chosen here is stated and marked *choice*.
//!
//! Units are SI. A rotary axis reads rad, rad/s, N·m and kg·m² wherever this
//! page writes m, m/s, N and kg.
//!
//! # Plant
//!
//! ```text
//! m·ẍ = u − F
//! ```
//!
//! | symbol | meaning | unit |
//! |---|---|---|
//! | x | position | m |
//! | v = ẋ | velocity | m/s |
//! | u | actuation force (the controller's command) | N |
//! | F | friction force, opposing the motion | N |
//! | m | moving mass | kg |
//!
//! The library computes F from samples of x and v; it never integrates the
//! plant. The mass enters only the disturbance observer (as the nominal
//! mass m_n, [`DisturbanceObserver`](crate::compensation::DisturbanceObserver))
//! and the validity bound of the [break-away predictor](#break-away-predictor).
//!
//! # Stribeck curve
//!
//! The friction of steady sliding at velocity v:
//!
//! ```text
//! S(v)    = Fc + (Fs − Fc)·exp(−(|v|/V)^δ)        [N]  magnitude, Fc ≤ S ≤ Fs
//! F_ss(v) = sgn(v)·S(v) + σ·v                     [N]
//! ```
//!
//! | symbol | field of [`Params`](crate::Params) | meaning | unit | rule |
//! |---|---|---|---|---|
//! | Fc | `fc` | Coulomb level, reached at high speed | N | > 0 |
//! | Fs | `fs` | stiction level, S(0) | N | ≥ Fc |
//! | V | `v_stribeck` | Stribeck velocity: where the fall from Fs to Fc happens | m/s | > 0 |
//! | δ | `delta` | shape exponent of the fall | – | > 0, usually 0.5 … 2 |
//! | σ | `sigma` | viscous coefficient | N·s/m | ≥ 0 |
//!
//! S(0) = Fs: at rest, the level in the direction of the coming motion is the
//! stiction level. S falls monotonically towards Fc as |v| grows (velocity
//! weakening); σ·v grows with v. [`Model::stribeck`](crate::Model::stribeck)
//! and [`Model::steady_state`](crate::Model::steady_state) evaluate S and
//! F_ss (with F_ss(0) = 0). The paper writes δ for both the exponent and the
//! viscous coefficient; here the viscous coefficient is σ.
//!
//! # Presliding
//!
//! Before an axis slides, the contact deforms: friction builds up over a
//! small travel, the presliding distance z_max, and falls back along a
//! different path when the motion reverses (a hysteresis). The model is
//! *rate independent*: H depends on the path travelled, not on how fast
//! (except through S(v)). The shape of each branch is
//!
//! ```text
//! g(w) = w·(1 − ln w)      for 0 < w ≤ 1,    g(0) = 0,  g(1) = 1,  g′(1) = 0      [–]
//! ```
//!
//! which rises with infinite slope at w = 0 and joins 1 with zero slope (the
//! area of a hysteresis loop grows with the square of its travel). The
//! state of one axis is the direction d ∈ {−1, 0, +1}, the last turning point
//! x_r [m] and the dry friction H_r [N] there. The normalised travel and the
//! friction are
//!
//! ```text
//! w = min(1, |x − x_r| / z_max)                    [–]
//! H = H_r + (d·S(v) − H_r)·g(w)                    [N]  dry (hysteretic) friction
//! F = H + σ·v                                      [N]
//! ```
//!
//! with z_max [m] > 0 (`z_max` of [`Params`](crate::Params); the paper's
//! scale s is 1/z_max). At w = 1 the axis slides: H = d·S(v), F = F_ss(v).
//! The paper states the branch for positive motion only,
//! |F_ss − F_r|·z·(1 − ln z) + F_r; the signed form above is the same
//! branch for both directions (*choice*). [`Presliding`](crate::Presliding)
//! is this state machine; [`shape_f32`](crate::shape_f32) and
//! [`Model::shape`](crate::Model::shape) evaluate g.
//!
//! ## Idle start
//!
//! A new or [`reset`](crate::Presliding::reset) state is idle: d = 0,
//! H_r = 0, x_r the start position, H = 0 (the paper's zero initial state).
//! The first sample with x ≠ x_r sets d = sgn(x − x_r); the deadband does not
//! apply to this first motion.
//!
//! ## Turning points and deadband
//!
//! The state keeps the extremum x_ext reached in direction d. The motion has
//! reversed once it has come back from the extremum by more than the
//! deadband ε [m] ≥ 0 (`epsilon`):
//!
//! ```text
//! d·(x_ext − x) > ε    ⇒    d ← −d,   x_r ← x_ext,   H_r ← H at x_ext
//! ```
//!
//! "H at x_ext" is the dry friction (without σ·v) of the latest sample at the
//! extremum, so H stays continuous through the reversal even when the
//! velocity changed while the axis stood there (*choice*). While a reversal
//! is pending, 0 < d·(x_ext − x) ≤ ε, H is held at its value at x_ext. Once
//! it is confirmed, H follows the new branch from w = ε/z_max already: a step
//! of up to |d·S − H_r|·g(ε/z_max) (g(0.15) = 0.43). Keep ε ≪ z_max, or filter
//! the position instead; ε = 0 for clean data.
//!
//! ## Minor loops
//!
//! With only the last turning point remembered (the rule above, and
//! `Presliding<P, T, 0>`), a small back-and-forth inside presliding does not
//! return to where it started. `Presliding<P, T, N>` with N > 0 also keeps a
//! stack of up to N earlier turning points and closes minor loops: a branch
//! heading back to the previous turning point reaches that point's friction
//! exactly there, with no jump in H, and past it the older branch resumes.
//! This goes beyond the paper; the [`presliding`](crate::presliding) module
//! describes the rule and what happens when the stack overflows. It also
//! stops the creep described under [known limits](#known-limits).
//!
//! # Break-away predictor
//!
//! Under a force ramp u = k·t from the idle state at rest (k [N/s] > 0, the
//! force rate), neglecting inertia during presliding (H ≈ k·t) and the
//! velocity dependence of H (∂H/∂v ≈ 0):
//!
//! ```text
//! dH/dt = −F̂·ln(w)·v / z_max = k
//! v(w)  = −k·z_max / (F̂·ln w)                     [m/s]  (paper eq. 12, with z_max)
//! ```
//!
//! Break-away is placed where the normalised travel reaches the boundary w_b
//! (default [`DEFAULT_BOUNDARY`](crate::DEFAULT_BOUNDARY) = 0.95, the paper's
//! z_0.95):
//!
//! ```text
//! v_b  = −k·z_max / (F̂·ln w_b)                    [m/s]  velocity at break-away
//! F_ba = S(v_b) + σ·v_b                           [N]    break-away force (paper eq. 13)
//! t_ba = (S(v_b)·g(w_b) + σ·v_b) / k              [s]    time of break-away after the ramp starts
//! ```
//!
//! The level F̂ [N] comes in four [`Variant`](crate::Variant)s:
//!
//! | variant | F̂ |
//! |---|---|
//! | `coulomb` | Fc |
//! | `stiction` | Fs |
//! | `mean` | (Fc + Fs)/2, the paper's F̂_ss |
//! | `consistent` | S(v_b): the smallest positive root of v_b·S(v_b) = −k·z_max/ln w_b (beyond the paper) |
//!
//! With σ = 0, F_ba(k) falls from Fs at small k towards Fc at large k; with
//! σ > 0 the term σ·v_b grows with k.
//! [`BreakAwayPredictor`](crate::BreakAwayPredictor) computes (v_b, F_ba,
//! t_ba); the [`predictor`](crate::predictor) module shows how `consistent`
//! is solved.
//!
//! **Validity.** The quasi-static step needs inertia to be negligible during
//! presliding:
//!
//! ```text
//! Λ = m·k²·z_max / (F̂³·w_b·|ln w_b|³) ≪ 1          [–]
//! ```
//!
//! (with m = 1 kg, z_max = 10 µm and F̂ = Fc = 1 N: k ≪ 3.6 N/s). Beyond it
//! the full dynamics m·ẍ = k·t − F, integrated from rest up to the instant w
//! reaches w_b, give a different break-away; the measured map is in
//! [docs/accuracy.md](https://github.com/breakaway-rs/breakaway/blob/main/docs/accuracy.md).
//!
//! # Parameters
//!
//! [`Params`](crate::Params) holds the seven numbers of the sections above,
//! in SI units; [`Model::new`](crate::Model::new) checks them once:
//!
//! | field | symbol | unit | rule | section |
//! |---|---|---|---|---|
//! | `fc` | Fc | N | finite, > 0 | [Stribeck curve](#stribeck-curve) |
//! | `fs` | Fs | N | finite, ≥ Fc | [Stribeck curve](#stribeck-curve) |
//! | `v_stribeck` | V | m/s | finite, > 0 | [Stribeck curve](#stribeck-curve) |
//! | `delta` | δ | – | finite, > 0 | [Stribeck curve](#stribeck-curve) |
//! | `sigma` | σ | N·s/m | finite, ≥ 0 | [Stribeck curve](#stribeck-curve) |
//! | `z_max` | z_max | m | finite, > 0 | [Presliding](#presliding) |
//! | `epsilon` | ε | m | finite, ≥ 0 | [Turning points](#turning-points-and-deadband) |
//!
//! A parameter set that breaks a rule is rejected with a
//! [`ParamError`](crate::ParamError) naming the parameter; a valid value that
//! the number type cannot carry is [`ParamError::OutOfRange`](crate::ParamError::OutOfRange).
//! The field names are also the keys of the TOML model files that the
//! project's tools read and write ([`Param::key`](crate::Param::key)); the
//! mass is stored there as `mass` [kg]. In such a file `fs = fc` marks a
//! model without Stribeck fall and `z_max = 0` one without presliding; the
//! library itself requires z_max > 0.
//!
//! # Fixed-point units
//!
//! [`Model<Q16>`](crate::Q16) carries every quantity per unit of the model
//! itself ([`Units`](crate::Units)), so that Q16.16 numbers (range ±32768,
//! resolution 2⁻¹⁶ ≈ 1.5e-5) cover the useful range of any axis:
//!
//! | quantity | unit in `Model<Q16>` | range |
//! |---|---|---|
//! | force (F, H, S, Fc, the command u) | Fs | ±32768·Fs; H and S within [−1, 1] |
//! | velocity | V | ±32768·V, resolution 1.5e-5·V |
//! | viscous coefficient σ | Fs/V | below 32768 |
//! | length (travel, ε) | z_max/256 | ±128·z_max per difference |
//! | force rate k | Fs/s | (0, 32768) |
//! | time t_ba | s | below 32768 s |
//!
//! The equations above hold unchanged in these units. Convert at the
//! boundary with [`Model::velocity`](crate::Model::velocity),
//! [`Model::position_scale`](crate::Model::position_scale) and the force unit
//! `model.units().force` (= Fs [N]); the [`fixed_point`](crate::fixed_point)
//! module gives the ranges, the tables of S and g and the accuracy.
//!
//! # Effects
//!
//! Real axes show friction the base model above does not contain. The
//! project names each such effect; the library implements the base model,
//! `viscous` included (σ), and the compensation blocks track a slow change of
//! level (`drift`, [`LevelAdaptation`](crate::compensation::LevelAdaptation),
//! and Fc and Fs − Fc separately with
//! [`StictionAdaptation`](crate::compensation::StictionAdaptation));
//! the other effects are modelled in the project's f64 reference and found in
//! measured data by its discrepancy workflow
//! ([lab/README.md](https://github.com/breakaway-rs/breakaway/blob/main/lab/README.md)).
//!
//! | name | form | parameters |
//! |---|---|---|
//! | `viscous` | F += σ·v | σ ≥ 0 [N·s/m] |
//! | `offset` | F += F0, at rest and in motion | F0 [N], signed |
//! | `asymmetry` | Fc, Fs scaled by (1 + a·d) | −1 < a < 1 |
//! | `position_ripple` | F += A·sin(2π·x/λ + φ) | A [N], λ > 0 [m], φ [rad] |
//! | `dwell_stiction` | Fs raised by ΔFs·t_d/(t_d + γ), t_d the length of the latest rest (\|v\| ≤ v_rest) | ΔFs ≥ 0 [N], γ > 0 [s], v_rest > 0 [m/s] |
//! | `frictional_lag` | S evaluated at a lagged velocity, τ_L·dv_l/dt = v − v_l | τ_L > 0 [s] |
//! | `drift` | Fc, Fs scaled by (1 + β·t) | β [1/s] |
//! | `nonlinear_viscous` | F += σ_n·sgn(v)·\|v\|^n, n ≠ 1 | σ_n ≥ 0 [N·(s/m)^n], 0 < n ≤ 2 |
//! | `stribeck` | without it Fs = Fc | Fs, V, δ |
//! | `presliding` | without it H = d·S(v) at once after a turning point | z_max |
//!
//! # Known limits
//!
//! - **Self-excited presliding.** H reads S at the current velocity, so
//!   inside presliding ∂H/∂v = g(w)·S′(|v|) < 0, a negative damping (the paper
//!   assumes 0), infinite at v = 0 for δ < 1. With Π = √(2·Fs·z_max/m)/V
//!   [–] of about 10 or more, a constant force below Fc can make the mass
//!   oscillate and, through the single-turning-point memory, creep for ever;
//!   below Π ≈ 5 rests are quiet. A closing memory
//!   ([minor loops](#minor-loops)) stops the creep.
//! - **Inertia.** The predicted fall of F_ba with k lies mostly where Λ is
//!   not small ([validity](#break-away-predictor)); the full dynamics are the
//!   reference there.
//! - **Re-simulation.** Integrating a measured record open-loop from its
//!   logged u follows it only briefly at low speed, where the loop
//!   stick-slips. Compare model and data locally (the friction along the
//!   measured motion), not by a simulation over a whole record.
