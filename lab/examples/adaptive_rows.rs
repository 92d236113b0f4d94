//! The `presliding+observer+adaptation` row of `breakaway-lab closed-loop`
//! (1 µm encoder) on both plants and every drift, at n count phases
//! (0, 1/n, …; n = 4 unless `PHASES` says otherwise): the peak reversal
//! error [µm] at each, their mean and largest, and the drift rows against
//! the tuned one (at phase 0, as the benchmark's table, and on the means).
//! A first argument `presliding` or `presliding+observer` runs that row
//! instead. The quick check of an adaptation change (about 15 s for n = 4).
//!
//! `cargo run --release -p breakaway-lab --example adaptive_rows`

use breakaway_lab::closed_loop::{
    peaks_over_phases, Compensator, Drift, PlantKind, Setup, TARGET_ENCODER,
};

fn main() -> Result<(), String> {
    let n: usize = std::env::var("PHASES")
        .ok()
        .and_then(|n| n.parse().ok())
        .filter(|n| *n > 0)
        .unwrap_or(4);
    let phases: Vec<f64> = (0..n).map(|i| i as f64 / n as f64).collect();
    let c = match std::env::args().nth(1).as_deref() {
        Some("presliding") => Compensator::PRESLIDING,
        Some("presliding+observer") => Compensator::PRESLIDING_OBSERVER,
        _ => Compensator::ADAPTIVE,
    };
    println!(
        "{}, 1 um encoder, peak reversal error [um] at count phases {phases:?}",
        c.name()
    );
    for plant in [PlantKind::LuGre, PlantKind::Model] {
        let mut tuned = (0.0, 0.0);
        for drift in [Drift::None, Drift::Coulomb, Drift::Levels] {
            let peaks: Vec<f64> =
                peaks_over_phases(plant, c, drift, &Setup::encoder(TARGET_ENCODER), &phases)?
                    .into_iter()
                    .map(|p| p * 1e6)
                    .collect();
            let mean = peaks.iter().sum::<f64>() / peaks.len() as f64;
            if drift == Drift::None {
                tuned = (peaks[0], mean);
            }
            println!(
                "{:<6} {:<10} {}  mean {:>5.2} max {:>5.2}  vs tuned: phase 0 {:+6.1} %, mean {:+6.1} %",
                plant.name(),
                drift.name(),
                peaks
                    .iter()
                    .map(|p| format!("{p:>5.2}"))
                    .collect::<Vec<_>>()
                    .join(" / "),
                mean,
                peaks.iter().copied().fold(0.0, f64::max),
                (peaks[0] / tuned.0 - 1.0) * 100.0,
                (mean / tuned.1 - 1.0) * 100.0
            );
        }
    }
    Ok(())
}
