//! A run's derived targets: left as written, their bases' corrections
//! carry them; what remains at each is its residual.

use super::context::Run;
use super::derived;
use super::outcome::{derived_report, Correction, Derived};
use super::progress::Progress;
use crate::rapid::TargetKind;
use std::collections::{HashMap, HashSet};

/// The targets whose rows a derived target's residual reads: its bases.
pub(super) fn derived_bases(run: &Run) -> HashSet<usize> {
    let program = run.program;
    let derived: Vec<String> = program
        .targets()
        .one_by_one_all()
        .filter(|(_, t)| t.kind == TargetKind::Derived && !t.written_with_expressions())
        .flat_map(|(_, t)| {
            t.derived
                .iter()
                .flat_map(|d| d.bases.clone())
                .collect::<Vec<_>>()
        })
        .collect();
    if derived.is_empty() {
        return HashSet::new();
    }
    let index = program.target_index(|t| t.kind != TargetKind::Inline);
    derived.iter().filter_map(|b| index.get(b)).collect()
}

/// The rows of the derived targets the pass found (`derived`, by index),
/// each with its residual against the corrected rows (`rows`).
pub(super) fn derived_rows(
    run: &Run,
    derived: &[usize],
    rows: &[Correction],
    progress: &mut Progress,
) -> Vec<Derived> {
    let program = run.program;
    let warm = run.warm;
    let targets = program.targets();
    // The index by name is built only for them: a million declared
    // targets made it a second's work on one core.
    let index_of =
        (!derived.is_empty()).then(|| program.target_index(|t| t.kind != TargetKind::Inline));
    let passed = match derived.is_empty() {
        true => HashMap::new(),
        false => crate::resolve::settled_parameters(program),
    };
    // No derived targets: no index, and nothing below runs.
    let lookups = index_of
        .iter()
        .map(|index| (&run.set.frames, &run.set.uses, index));
    (lookups.flat_map(|l| derived.iter().map(move |&i| (i, l))))
        .map(|(i, lookup)| {
            progress.step();
            let target = targets.at(i);
            let reads: Vec<&str> = match passed.is_empty() {
                true => Vec::new(),
                false => (run.set.calls.get(&target.origin.pos.offset).into_iter())
                    .flat_map(|c| &c.args)
                    .filter(|a| !a.optional)
                    .filter_map(|a| a.value.as_ref().and_then(crate::rapid::Expr::as_name))
                    .collect(),
            };
            let mut report = derived_report(program, &target, rows, &passed, &reads);
            report.residual_mm = derived::residual(
                program,
                i,
                &run.set.calls,
                &lookup,
                rows,
                warm,
                &run.states,
                &|e| run.eval(&target, e),
            );
            report
        })
        .collect()
}
