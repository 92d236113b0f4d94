//! `breakaway-gen`: an independent generator of test records for the
//! discrepancy workflow of `breakaway-lab diagnose`.
//!
//! It shares no code with the crates it is used to judge: the friction model
//! (MODEL.md §2, §3, §5), the outside plants (LuGre, Maxwell-slip, a
//! compliant two-mass axis, encoder jitter), the controllers and the
//! integrator (fixed-step semi-implicit Euler on a 1 µs lattice) are written
//! here from the contract alone.
//!
//! * [`friction`]: the MODEL.md model and its effect catalogue.
//! * [`plants`]: the plants and their integration.
//! * [`excite`]: excitation families, controllers, the record loop.
//! * [`draw`]: parameters drawn from a seed.
//! * [`record`]: one record (effect sizes fitted to visibility targets).
//! * [`write`]: `data.csv`, `truth.toml`, `truth.json`.

// Units are written in square brackets ([m], [N], [s]); they are not links.
#![allow(rustdoc::broken_intra_doc_links)]

pub mod draw;
pub mod excite;
pub mod friction;
pub mod plants;
pub mod record;
pub mod write;
