//! The CLI's words: every remedy the library names, said with the flags
//! that apply it. One place, so that a renamed flag is renamed in every
//! message.

use rapidtherm::error::{Error, Remedy};

/// A remedy in the command line's terms.
pub fn remedy(r: Remedy) -> &'static str {
    match r {
        Remedy::ChooseEntry => " (choose one with --entry)",
        Remedy::GiveSchedule => ": give the schedule with --schedule instead",
        Remedy::GiveDefaultTime => " (add it, or give a default time with --default-time)",
        Remedy::GiveMinute => ": give a time with --at MIN",
        Remedy::FitSaturatingOrGiveMinute => {
            ": fit a saturating model (first-order, two-tau) or give a time with --at MIN"
        }
        Remedy::FitBeyondRecording => {
            "; fit a saturating model (`heating fit --model first-order`) to predict beyond it, or hold the end values explicitly"
        }
        Remedy::ListArms => " (`rapidtherm arms` lists every name)",
    }
}

/// An error as the CLI prints it.
pub fn error(e: &Error) -> String {
    e.render(&remedy)
}
