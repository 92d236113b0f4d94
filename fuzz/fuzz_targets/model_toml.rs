//! The model-file reader (MODEL.md §7) on arbitrary text. Invariants: it
//! never panics; a file it accepts writes back and reads back unchanged.
#![no_main]

use breakaway_reference::Model;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    if let Ok(model) = Model::from_toml_str(text) {
        let written = model.to_toml_string();
        let again = Model::from_toml_str(&written).expect("a written model reads back");
        assert_eq!(again, model, "round trip changed the model");
    }
});
