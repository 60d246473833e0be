//! Any bytes as a controller backup's configuration file (SYS.cfg,
//! MOC.cfg) and its backinfo.txt: the readers return their entries or an
//! error at a line and column, never panic; a contradiction check over
//! whatever was read answers, never panics.
#![no_main]

use libfuzzer_sys::fuzz_target;
use rapidtherm::rapid::task::{backinfo, cfg::Cfg, contradiction};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let _ = backinfo::parse(text);
    match Cfg::parse("fuzz.cfg", text) {
        Ok(cfg) => {
            let _ = contradiction::refuse(&cfg);
        }
        Err(e) => {
            if let Some(loc) = &e.location {
                assert!(loc.line >= 1 && loc.col >= 1);
            }
        }
    }
});
