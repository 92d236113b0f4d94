//! The repository's firmware for QEMU's Cortex-M boards (`examples/`, not
//! published): each example runs a part of `breakaway` on the MCU and
//! prints what `cargo xtask` compares with the host's f64 reference, or
//! measures flash, RAM and instruction counts. Built only with the feature
//! `qemu`, on a `thumb*` target (`cargo xtask qemu`, `cargo xtask test`),
//! so that host builds of the workspace skip them. This library is empty.
#![no_std]
