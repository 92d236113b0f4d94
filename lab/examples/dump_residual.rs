//! Development aid: the residual of a fixed model along a record, as CSV
//! (`t,x,v,u,still,weight,var,r`), for looking at what the metric sees.
//!
//! `cargo run -p breakaway-lab --release --example dump_residual -- DATA MODEL.toml [K [KF]]` (default: the
//! half-widths `diagnose` chooses)

use breakaway_lab::data;
use breakaway_lab::residual::Prepared;
use breakaway_reference::Model;
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(d), Some(m)) = (args.first(), args.get(1)) else {
        eprintln!("usage: dump_residual DATA MODEL.toml [K [KF]]");
        std::process::exit(2);
    };
    let rec = data::load(Path::new(d))?;
    let model = Model::load(Path::new(m))?;
    let auto = breakaway_lab::residual::auto_window(&rec);
    let k = args
        .get(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(auto.velocity);
    let kf = args
        .get(3)
        .and_then(|s| s.parse().ok())
        .unwrap_or(auto.force);
    let mut p = Prepared::with_window(
        &rec,
        breakaway_lab::residual::Window {
            velocity: k,
            force: kf,
        },
    );
    let r0 = p.residual(&model);
    let s0 = p.set_error_weights(&model, &r0);
    eprintln!("sigma0 {s0}, floor {}", p.floor(None));
    let r = p.residual(&model);
    println!("t,x,v,u,still,weight,var,r");
    for (i, ri) in r.iter().enumerate() {
        println!(
            "{},{},{},{},{},{},{},{}",
            p.t[i],
            p.x[i],
            p.v[i],
            p.u_mid[i],
            u8::from(p.still[i]),
            p.weight[i],
            p.var[i],
            ri
        );
    }
    Ok(())
}
