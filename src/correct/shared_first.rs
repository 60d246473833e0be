//! The robtargets moved to with several tools or work objects, solved
//! before the pass over the files: what their other uses come to (and,
//! asked for, their copies) decides edits anywhere in the program.

use super::context::Run;
use super::outcome::Correction;
use super::shared;
use super::target::{correct_robtarget, with_others, Solved};
use crate::error::{Error, Result};
use crate::rapid::rewrite::Edit;
use crate::rapid::TargetKind;
use std::collections::HashMap;

/// The robtargets moved to with several tools or work objects, solved
/// before the pass: what their other uses come to (and, asked for, their
/// copies) decides edits anywhere in the program.
#[derive(Default)]
pub(super) struct Early {
    /// By target: its row, then its copies'.
    pub rows: HashMap<usize, Vec<Correction>>,
    pub lines: Vec<crate::correct::SharedUse>,
    pub splits: Vec<crate::correct::SplitTarget>,
    /// Edits beyond the numbers (copies, renamed arguments), by file.
    pub more: Vec<(usize, Edit)>,
    /// Why the copies could not be made, where they could not (said
    /// when no target is refused).
    pub error: Option<Error>,
}

pub(super) fn solve_shared(run: &Run, errors: &mut Vec<(usize, Error)>) -> Result<Early> {
    let program = run.program;
    let targets = program.targets();
    let mut pending = Vec::new();
    let mut corrections: Vec<Correction> = Vec::new();
    let mut owners: Vec<usize> = Vec::new();
    for i in run.set.uses.of_several_frames() {
        let t = targets.at(i);
        if t.kind == TargetKind::Derived && !t.written_with_expressions() {
            continue;
        }
        match correct_robtarget(run, i, &t) {
            Ok(Solved::Corrected(found)) => match with_others(run, i, &t, &found) {
                Ok((c, pairs)) => {
                    if !pairs.is_empty() {
                        pending.push(shared::Pending {
                            correction: corrections.len(),
                            pairs,
                        });
                    }
                    corrections.push(c);
                    owners.push(i);
                }
                Err(e) => errors.push((i, e)),
            },
            // Left alone, it is the pass's to report.
            Ok(Solved::LeftAlone(_)) => {}
            Err(e) => errors.push((i, e)),
        }
    }
    let mut early = Early::default();
    if corrections.is_empty() {
        return Ok(early);
    }
    let originals: Vec<String> = corrections.iter().map(|c| c.id.clone()).collect();
    let done = match shared::finish(run, pending, &mut corrections) {
        Ok(d) => d,
        Err(e) => {
            early.error = Some(e);
            return Ok(early);
        }
    };
    // Each copy follows its original in `corrections` (a copy has a name
    // of its own).
    let (mut k, mut owner) = (0, None);
    for c in corrections {
        if originals.get(k) == Some(&c.id) {
            owner = owners.get(k).copied();
            k += 1;
        }
        if let Some(o) = owner {
            early.rows.entry(o).or_default().push(c);
        }
    }
    early.lines = done.lines;
    early.splits = done.splits;
    early.more = done.edits;
    Ok(early)
}
