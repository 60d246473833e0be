//! Any bytes as a model file: the reader returns a model or an error that
//! names a place in the file, never panics; a model it returns writes back
//! to a file that reads as the same model (in the current format).
#![no_main]

use libfuzzer_sys::fuzz_target;
use rapidtherm::model::file::Model;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match Model::parse("fuzz.toml", text) {
        Ok(model) => {
            let again = model.to_toml().expect("a parsed model writes back");
            let back = Model::parse("again.toml", &again).expect("what it wrote reads back");
            // An older format is written in the current one: the same
            // model but for its format number.
            let mut expect = model.clone();
            expect.format = back.format;
            assert_eq!(back, expect);
        }
        Err(e) => {
            if let Some(loc) = &e.location {
                assert!(loc.line >= 1 && loc.col >= 1);
            }
        }
    }
});
