#![no_std]
#![no_main]
#![allow(unsafe_code)]
#[path = "common/mod.rs"]
mod common;
#[cortex_m_rt::entry]
fn main() -> ! {
    common::exit_success()
}
