//! Firmware link set-up, for the Cortex-M (`thumb*`) targets only.
//!
//! The examples link with cortex-m-rt's `link.x`, which includes the
//! top-level `memory.x`. That map serves the mps2 boards (4 MiB / 4 MiB);
//! for thumbv6m (QEMU's microbit) this script defines the smaller flash and
//! RAM lengths that `memory.x` reads. A host build gets nothing from here.

use std::env;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo::rustc-check-cfg=cfg(breakaway_armv6m)");
    let target = env::var("TARGET").unwrap_or_default();
    if target.starts_with("thumbv6m") {
        // ARMv6-M has no DWT cycle counter: `cycles` is left out.
        println!("cargo:rustc-cfg=breakaway_armv6m");
    }
    if !target.starts_with("thumb") {
        return;
    }
    if target.starts_with("thumbv6m") {
        // microbit (nRF51822): 256 KiB flash, 16 KiB RAM.
        println!("cargo:rustc-link-arg-examples=--defsym=__flash_length=0x40000");
        println!("cargo:rustc-link-arg-examples=--defsym=__ram_length=0x4000");
    }
    println!("cargo:rustc-link-arg-examples=-Tlink.x");
}
