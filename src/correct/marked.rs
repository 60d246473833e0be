//! A program its marker says is corrected: what a run on it still finds.
//! The files without a marker that hold targets are cold (a module added
//! after the correction); the marked files keep their bytes, and what a
//! whole run would correct in them is dropped (a second correction on top
//! of the first), while what it leaves cold or lands off stays: that is
//! decided by the program's statements, not its numbers.

use super::marker;
use super::options::Options;
use super::outcome::{Outcome, Summary};
use super::pass::{tallied, Tally};
use crate::rapid::{Program, TargetKind};

/// The files of `program` without any rapidtherm line (`marked`) that
/// hold targets with numbers: cold, whatever another file's marker says.
pub(super) fn unmarked_with_targets(program: &Program, marked: &[bool]) -> Vec<usize> {
    let targets = program.targets();
    let mut files: Vec<usize> = (0..targets.len())
        .filter(|&i| targets.has_value(i))
        .filter_map(|i| targets.place(i).map(|p| p.0))
        .chain(
            program
                .jointtargets()
                .iter()
                .filter(|j| j.kind != TargetKind::Derived)
                .map(|j| j.origin.file),
        )
        .filter(|&f| !marked.get(f).copied().unwrap_or(true))
        .collect();
    files.sort_unstable();
    files.dedup();
    files
}

/// A whole run on a marked program (its outcome and whether each file
/// changes) cut to what is still cold: the marked files keep their bytes
/// and lose their rows of corrections (what they would move is a second
/// correction on top of the first); the targets left cold and the uses
/// landing off stay, wherever they are.
/// `marked`: whether each file holds rapidtherm's lines; `unmarked`: the
/// files without that hold targets (each said in a note); `found`: the
/// marker. Where no file changes, the outcome says the program is
/// corrected already.
pub(super) fn keep_unmarked(
    program: &Program,
    marked: &[bool],
    unmarked: &[usize],
    found: &marker::FoundMarker,
    o: &mut Outcome,
    changed: &mut [bool],
    options: &Options,
) {
    let is_marked = |name: &str| {
        program
            .files
            .iter()
            .zip(marked)
            .any(|(n, &m)| m && n == name)
    };
    for (f, c) in changed.iter_mut().enumerate() {
        *c &= !marked.get(f).copied().unwrap_or(false);
    }
    o.corrections.retain(|c| !is_marked(&c.file));
    o.derived.retain(|d| !is_marked(&d.file));
    o.splits.retain(|s| !is_marked(&s.file));
    o.residuals.retain(|r| !is_marked(&r.file));
    let mut tally = Tally::default();
    for c in &o.corrections {
        tally.add(tallied(c));
    }
    let s = &mut o.summary;
    (s.corrected, s.rewritten) = (tally.corrected, tally.rewritten);
    (s.max_mm, s.rms_mm, s.max_drift_mm) = (tally.max_mm, tally.rms_mm(), tally.max_drift_mm);
    (s.derived, s.left_alone) = (o.derived.len(), o.left_alone.len());
    (s.shared, s.split) = (o.shared.len(), o.splits.len());
    if changed.iter().all(|c| !c) {
        let done = already_corrected(program, found, options);
        o.already_corrected = done.already_corrected;
        o.notes.extend(done.notes);
    }
    for &f in unmarked {
        o.notes.push(unmarked_note(program, f, found));
    }
}

/// The note of a file without a marker in a program another file of
/// which says it is corrected.
fn unmarked_note(program: &Program, f: usize, found: &marker::FoundMarker) -> String {
    format!(
        "{} has no rapidtherm marker, though {} says the program is corrected: its targets are taken as cold (a module added after the correction)",
        program.files[f], program.files[found.file]
    )
}

/// The outcome of a run on a program its marker says is corrected on the
/// run's basis: nothing to do, every file as it is. A split asked of a
/// program corrected without one is not made (its numbers are no longer
/// the cold ones), and a note says so.
pub(super) fn already_corrected(
    program: &Program,
    found: &marker::FoundMarker,
    options: &Options,
) -> Outcome {
    let m = &found.marker;
    let how = format!(
        "{} line {} says it was corrected by rapidtherm {} for {} with {} (cold original {})",
        program.files[found.file], found.line, m.version, m.basis, m.model, m.cold
    );
    let mut notes = Vec::new();
    if options.split_shared && !m.split {
        let uses = crate::resolve::uses(program);
        let targets = program.targets();
        let mut shared: Vec<String> = uses
            .of_several_frames()
            .into_iter()
            .filter_map(|i| targets.get(i).map(|t| t.id.clone()))
            .collect();
        shared.sort_unstable();
        if !shared.is_empty() {
            notes.push(format!(
                "it was corrected without splitting the targets moved to with several tools or work objects ({}): each is right for its first use only; a split starts from the cold original ({})",
                shared.join(", "),
                m.cold
            ));
        }
    }
    Outcome {
        moves: Vec::new(),
        corrections: Vec::new(),
        derived: Vec::new(),
        left_alone: Vec::new(),
        residuals: Vec::new(),
        shared: Vec::new(),
        splits: Vec::new(),
        already_corrected: Some(how),
        notes,
        summary: Summary {
            corrected: 0,
            rewritten: 0,
            max_mm: 0.0,
            rms_mm: 0.0,
            max_drift_mm: 0.0,
            derived: 0,
            left_alone: 0,
            shared: 0,
            split: 0,
            moves: super::outcome::MoveCounts::default(),
        },
        outputs: (0..program.files.len())
            .map(|f| program.source(f).to_vec())
            .collect(),
    }
}
