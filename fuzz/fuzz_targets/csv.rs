//! Any bytes as each CSV the tool reads (a heating recording, a schedule,
//! tracker measurements): each reader returns its table or an error that
//! names a line and column, never panics or hangs, and whatever it
//! accepts is finite where the file format says it is a number.
#![no_main]

use libfuzzer_sys::fuzz_target;
use rapidtherm::diagnose::measurements::Measurements;
use rapidtherm::schedule::Schedule;
use rapidtherm::thermal::record::HeatingRecord;

/// An error's place, where it has one, is a real line and column.
fn placed(e: &rapidtherm::error::Error) {
    if let Some(loc) = &e.location {
        assert!(loc.line >= 1 && loc.col >= 1);
    }
}

fuzz_target!(|data: &[u8]| {
    match HeatingRecord::parse("fuzz.csv", data) {
        Ok(_) => {}
        Err(e) => placed(&e),
    }
    if let Err(e) = Schedule::read("fuzz.csv", data) {
        placed(&e);
    }
    let limits = [(-180.0, 180.0); 6];
    match Measurements::parse("fuzz.csv", data, &limits) {
        Ok(m) => {
            for r in &m.rows {
                assert!(r.position.iter().all(|v| v.is_finite()));
                assert!(r.joints.iter().all(|v| v.is_finite()));
            }
        }
        Err(e) => placed(&e),
    }
});
