//! The widened evaluation of the diagnosis (issue 46): data as the world
//! sends them, not as the IRB 140's own evaluation (`eval.rs`) draws them.
//!
//! Every set is drawn from its seed: an arm (the IRB 140, a UR5, a Stäubli
//! TX60 with its lateral offset, a KUKA KR 210 of 2.7 m reach, the last
//! three from their URDFs in `tests/data/`), and a form: motor temperatures
//! logged or not, poses measured again and again or each once, a clock or
//! time only as the rows' order, the tracker's frame known (data in the
//! robot's base) or not (a tracker metres away at any heading, `--register`).
//! One library effect (or none) is withheld at a size drawn from zero to
//! four times the noise, judged against the smallest size these poses,
//! times and noise could have revealed (`limit.rs`): below it, the right
//! verdict names nothing. The noise is never given to the diagnosis.
//!
//! Files: [`arms`] (the arms and their poses), [`world`] (the generator),
//! [`limit`] (the detection limit of the withheld effect), [`score`] (what a
//! right verdict is, from the rules), [`run`] (sets diagnosed, the
//! confusion table), [`saved_check`] (the report's "after" against `gap
//! --model` of the saved files). The runner is `examples/diagnose_eval.rs`; a small
//! seeded run is `tests/diagnose/wide_ci.rs`.

pub mod arms;
pub mod limit;
pub mod run;
pub mod saved_check;
pub mod score;
pub mod world;
