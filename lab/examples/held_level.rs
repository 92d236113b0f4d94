//! Development aid: where the metric puts `Fs` against what a record's
//! still samples held. For a fixed model (a truth file, or a model
//! `diagnose` wrote), with the record's weights taken from that model:
//! the static level each direction's held force shows
//! ([`held_levels`]), the model's `Fs` and model error, and the same model
//! refitted with every parameter free from itself (where the residual
//! alone puts `Fs`, and the model error there).
//!
//! `cargo run -p breakaway-lab --release --example held_level -- DATA MODEL.toml`
//!
//! See lab/README.md, *Static level from the held force*.

use breakaway_lab::data;
use breakaway_lab::diagnose::held_levels;
use breakaway_lab::fit::{self, FitOptions};
use breakaway_lab::residual::{self, Prepared};
use breakaway_reference::Model;
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(d), Some(m)) = (args.first(), args.get(1)) else {
        eprintln!("usage: held_level DATA MODEL.toml");
        std::process::exit(2);
    };
    let rec = data::load(Path::new(d))?;
    let model = Model::load(Path::new(m))?;
    let mut p = Prepared::with_window(&rec, residual::auto_window(&rec));
    let r0 = p.residual(&model);
    p.set_error_weights(&model, &r0);
    let floor = p.floor(Some(true));
    let error = |m: &Model| residual::model_error(p.rms(&p.residual(m), Some(true)), floor);
    let [up, down] = held_levels(&p, &model);
    let params = fit::params_of(&model);
    let free = fit::fit(&p, &model, &params, &FitOptions::default(), &mut |_| {}).model;
    println!(
        "held {up:.4} N (+), {down:.4} N (-) | model Fs {:.4} N, model error {:.3e} N | refitted free: Fs {:.4} N, model error {:.3e} N",
        model.fs,
        error(&model),
        free.fs,
        error(&free)
    );
    Ok(())
}
