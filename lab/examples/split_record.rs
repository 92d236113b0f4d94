//! Development aid: writes the first and second half (in time) of a record
//! as MODEL.md §6 CSV files, to check that a model fitted on one stretch of
//! an axis holds on another.
//!
//! `cargo run -p breakaway-lab --release --example split_record -- DATA OUT_PREFIX`

use breakaway_lab::data::{self, Record};
use std::path::Path;

fn part(rec: &Record, lo: usize, hi: usize) -> Record {
    Record {
        t: rec.t[lo..hi].to_vec(),
        u: rec.u[lo..hi].to_vec(),
        x: rec.x[lo..hi].to_vec(),
        v: rec.v.as_ref().map(|v| v[lo..hi].to_vec()),
        source: rec.source.clone(),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(d), Some(prefix)) = (args.first(), args.get(1)) else {
        eprintln!("usage: split_record DATA OUT_PREFIX");
        std::process::exit(2);
    };
    let rec = data::load(Path::new(d))?;
    let n = rec.len();
    for (k, (lo, hi)) in [(0, n / 2), (n / 2, n)].into_iter().enumerate() {
        let path = format!("{prefix}{}.csv", k + 1);
        data::write_csv(Path::new(&path), &part(&rec, lo, hi), &[])?;
    }
    Ok(())
}
