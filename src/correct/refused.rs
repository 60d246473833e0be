//! A run's refusals as they are told: every target it refuses, each
//! cause once, the errors shown with their source line.

use crate::error::{Error, ErrorKind, Result};
use crate::rapid::Program;
use std::collections::HashMap;

/// The run's errors, if any, as one: in the order given, one cause shown
/// once. Only the errors shown get their line's text (each a walk through
/// their file): the rest are counted.
pub(super) fn refuse_any(errors: Vec<(usize, Error)>, program: &Program) -> Result<()> {
    if let Some(e) = Error::many(
        same_cause(errors.into_iter().map(|(_, e)| e).collect())
            .into_iter()
            .enumerate()
            .map(|(k, e)| match k <= crate::error::MAX_RELATED {
                true => with_source(e, program),
                false => e,
            })
            .collect(),
    ) {
        return Err(e);
    }
    Ok(())
}

/// Errors with one cause shown once: the targets refused for the same
/// reason (`minute 200 is outside the recording`) are named in a note of
/// the first, not repeated with their own carets. Errors about a target
/// are told apart by their kind and cause (their message, which does not
/// name the target: see [`Subject`](crate::error::Subject)).
fn same_cause(errors: Vec<Error>) -> Vec<Error> {
    // Grouped through a map: a program for another arm can have every one
    // of a million targets refused for the same cause.
    let mut out: Vec<(Error, Vec<String>, usize)> = Vec::new();
    let mut by_cause: HashMap<(ErrorKind, String), usize> = HashMap::new();
    for e in errors {
        if let Some(subject) = &e.subject {
            let key = (e.kind, e.message.clone());
            if let Some(&i) = by_cause.get(&key) {
                let (_, names, count) = &mut out[i];
                *count += 1;
                if names.len() < NAMED_PER_CAUSE {
                    names.push(subject.to_string());
                }
                continue;
            }
            by_cause.insert(key, out.len());
        }
        out.push((e, Vec::new(), 0));
    }
    out.into_iter()
        .map(|(e, names, count)| match count {
            0 => e,
            n if n > names.len() => {
                e.with_note(format!("the same for {n} more: {}, ...", names.join(", ")))
            }
            n => e.with_note(format!("the same for {n} more: {}", names.join(", "))),
        })
        .collect()
}

/// How many other targets a grouped error names; the rest are counted.
const NAMED_PER_CAUSE: usize = 10;

/// Errors located in the program gain the source line and caret.
pub(super) fn with_source(e: Error, program: &Program) -> Error {
    let Some(loc) = &e.location else { return e };
    if !loc.line_text.is_empty() {
        return e;
    }
    let Some(file) = program.files.iter().position(|f| *f == loc.file) else {
        return e;
    };
    let src = program.source(file);
    let line_start = crate::error::start_of_line(src, loc.line);
    let line_text = crate::error::Location::from_offset(&loc.file, src, line_start).line_text;
    let location = crate::error::Location {
        line_text,
        ..(**loc).clone()
    };
    e.at(location)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_cause_is_shown_once_with_its_targets_counted() {
        let about = |id: &str| crate::error::Subject::Target(id.to_string());
        let errors: Vec<Error> = (0..25)
            .map(|i| Error::input("unknown tool `t`").about(about(&format!("p{i}"))))
            .chain([Error::input("another cause").about(about("q"))])
            .chain([Error::input("unknown tool `t`")])
            .collect();
        let grouped = same_cause(errors);
        // An error about no target is never grouped.
        assert_eq!(grouped.len(), 3);
        assert_eq!(
            grouped[0].notes,
            ["the same for 24 more: target p1, target p2, target p3, target p4, target p5, target p6, target p7, target p8, target p9, target p10, ..."]
        );
        assert!(grouped[1].notes.is_empty());
    }
}
