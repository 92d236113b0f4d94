//! Development aid: how the force-kernel half-width moves the floor and the
//! model error of a true model and of its base (effects removed).
//!
//! `cargo run -p breakaway-lab --release --example window_scan -- DATA TRUTH.toml`

use breakaway_lab::data;
use breakaway_lab::residual::{self, Prepared, Window};
use breakaway_reference::Model;
use std::path::Path;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(d), Some(m)) = (args.first(), args.get(1)) else {
        eprintln!("usage: window_scan DATA TRUTH.toml");
        std::process::exit(2);
    };
    let (Ok(rec), Ok(truth)) = (data::load(Path::new(d)), Model::load(Path::new(m))) else {
        eprintln!("cannot load");
        std::process::exit(1);
    };
    let mut base = truth.clone();
    base.effects = Default::default();
    println!("auto {:?}", residual::auto_window(&rec));
    for kf in [4usize, 8, 16, 32, 64, 100] {
        let mut p = Prepared::with_window(
            &rec,
            Window {
                velocity: 4,
                force: kf,
            },
        );
        let r0 = p.residual(&base);
        p.set_error_weights(&base, &r0);
        let floor = p.floor(Some(true));
        let rt = p.rms(&p.residual(&truth), Some(true));
        let rb = p.rms(&p.residual(&base), Some(true));
        println!(
            "kf {kf:2}: floor {floor:.4} true {rt:.4} (err {:.4}) base {rb:.4} (err {:.4}) sigma0 {:.4}",
            residual::model_error(rt, floor),
            residual::model_error(rb, floor),
            p.sigma0
        );
    }
}
