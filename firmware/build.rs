//! Link set-up of the firmware examples on the Cortex-M (`thumb*`) targets:
//! cortex-m-rt's `link.x`, which includes `memory.x`. That map serves the
//! mps2 boards (4 MiB / 4 MiB); for thumbv6m (QEMU's microbit: 256 KiB of
//! flash, 16 KiB of RAM) this script defines the smaller lengths that
//! `memory.x` reads. `memory.x` goes to `OUT_DIR`, on the linker's search
//! path. On thumbv6m the cfg `breakaway_armv6m` too, as the library's
//! build script sets it (no DWT cycle counter: `cycle_budget` counts
//! without it).

use std::env;
use std::fs;
use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo::rustc-check-cfg=cfg(breakaway_armv6m)");
    let target = env::var("TARGET").unwrap_or_default();
    if target.starts_with("thumbv6m") {
        println!("cargo:rustc-cfg=breakaway_armv6m");
    }
    if !target.starts_with("thumb") {
        return;
    }
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::copy("memory.x", out.join("memory.x")).expect("memory.x beside build.rs");
    println!("cargo:rustc-link-search={}", out.display());
    if target.starts_with("thumbv6m") {
        println!("cargo:rustc-link-arg-examples=--defsym=__flash_length=0x40000");
        println!("cargo:rustc-link-arg-examples=--defsym=__ram_length=0x4000");
    }
    println!("cargo:rustc-link-arg-examples=-Tlink.x");
}
