//! Targets moved to with several tools or work objects (`MoveJ pHome, ...,
//! tGrip; ... MoveL pHome, ..., tGlue;`). One robtarget holds one set of
//! numbers, and the numbers that are right warm depend on the tool and
//! work object: the tool's length changes the joints, and the joints
//! change the drift.
//!
//! Rules:
//! - The first use decides: the target is corrected for the tool and work
//!   object of its first use in program order (the order
//!   [`crate::resolve::usages`] lists them). Every use with another pair
//!   gets a line of the report: where the warm robot's TCP lands there,
//!   in that use's own tool and work object, against where the cold
//!   program meant it. The moment is the one the target is corrected for:
//!   a schedule gives a target's visits, not which instruction makes each,
//!   so the line measures what the other pair costs, and the drift's
//!   spread over the visits stays the correction's own figure.
//! - On request, a split: a declared target gets a copy per other pair,
//!   declared on the line after it (same storage, same layout, the
//!   numbers corrected for that pair), and the moves with that pair name
//!   the copy. Only where the copy's written numbers would differ from the
//!   original's (so minute 0, where nothing changes, splits nothing), and
//!   only where renaming is all it takes: not for array elements, record
//!   fields, a global PERS (other tasks share it), a target also reached
//!   through Offs/RelTool or a variable, read elsewhere (passed to a
//!   procedure, assigned from), or whose name is declared twice. Those
//!   keep the first-use rule, and their lines say why.

use super::context::Run;
use super::derived::apply_with;
use super::names::Names;
use super::outcome::{Correction, FramesUse, SharedUse, SplitTarget};
use super::solve::{at_target, corrected, nearest_solution, prefix, Meant};
use crate::error::{ErrorKind, Result};
use crate::rapid::rewrite::{apply_edits, statement_words, Edit};
use crate::rapid::{Expr, Program, Storage, Target, TargetKind};
use crate::resolve::monitoring::Monitor;
use crate::resolve::{frames_named, uses_by_frames, Through, Usage};
use crate::robot::frames::{flange_of_target, target_of_flange, ToolFrame, WobjFrames};
use nalgebra::Isometry3;
use std::collections::{BTreeMap, HashSet};
use std::ops::Range;

/// RAPID's longest identifier.
const MAX_NAME: usize = 32;

/// One tool/work-object pair of a target other than the one it is
/// corrected for.
pub(super) struct OtherPair {
    /// The report line of each use with this pair.
    pub lines: Vec<SharedUse>,
    /// With a split asked for: the copy for this pair, or why there is
    /// none.
    pub copy: Option<std::result::Result<Copy, String>>,
}

/// A copy of a declared target for one other pair, before it is named.
pub(super) struct Copy {
    /// The target corrected for this pair; its edits are over the
    /// original's literal.
    correction: Correction,
    decl: Declaration,
    /// Where the moves with this pair name the target, per file.
    renames: Vec<(usize, Range<usize>)>,
    uses: Vec<FramesUse>,
}

/// Where a target's declaration is written.
#[derive(Clone)]
struct Declaration {
    file: usize,
    /// The whole declaration, through its `;`.
    span: Range<usize>,
    /// The declared name in it.
    name: Range<usize>,
}

/// The target's uses with other pairs than its first use's: a report line
/// for each, and (with a split asked for) the copies.
pub(super) fn other_pairs(
    run: &Run,
    index: usize,
    target: &Target,
    meant: &Meant,
    correction: &Correction,
) -> Result<Vec<OtherPair>> {
    if !run.set.uses.several_frames(index) {
        return Ok(Vec::new());
    }
    let uses = &run.set.uses.usages(index);
    let groups = uses_by_frames(uses);
    let Some(exact) = correction.exact else {
        return Ok(Vec::new());
    };
    let first = groups[0][0];
    let declaration = run
        .options
        .split_shared
        .then(|| splittable(run, index, target, uses));
    let mut out = Vec::new();
    for group in &groups[1..] {
        let pair = group[0];
        let frames = frames_named(
            run.program,
            &run.set.frames,
            target,
            pair.tool.as_deref(),
            pair.wobj.as_deref(),
        )
        .map_err(|e| {
            e.with_note(format!(
                "named by {} in {} line {}",
                pair.instruction, pair.routine, pair.line
            ))
        })?;
        let mut lines = Vec::new();
        for u in group {
            let (residual, unknown) = match landed(run, target, meant, &exact, u, &frames)? {
                Ok((mm, deg)) => (Some((mm, deg)), None),
                Err(why) => (None, Some(why)),
            };
            lines.push(SharedUse {
                id: correction.id.clone(),
                kind: correction.kind,
                file: correction.file.clone(),
                line: correction.line,
                col: correction.col,
                corrected_for: FramesUse::of(first, run.program),
                other: FramesUse::of(u, run.program),
                time_min: correction.time_min,
                residual_mm: residual.map(|r| r.0),
                residual_deg: residual.map(|r| r.1),
                unknown,
                not_split: None,
            });
        }
        let copy = declaration.as_ref().map(|d| {
            let decl = d.clone()?;
            let renames = renames(run, target, group)?;
            let names = [pair.tool_name(), pair.wobj_name()];
            let correction = corrected(run, target, meant, (&frames.0, &frames.1), names, None)
                .map_err(|e| format!("it cannot be corrected for this pair: {}", e.headline()))?;
            Ok(Copy {
                correction,
                decl,
                renames,
                uses: group
                    .iter()
                    .map(|u| FramesUse::of(u, run.program))
                    .collect(),
            })
        });
        out.push(OtherPair { lines, copy });
    }
    Ok(out)
}

/// Where the warm robot's TCP lands at use `u` (tool and work object
/// `frames`) when the corrected target `exact` is sent, against where the
/// cold program meant it: (mm, degrees), or why only the run time knows.
fn landed(
    run: &Run,
    target: &Target,
    meant: &Meant,
    exact: &Isometry3<f64>,
    u: &Usage,
    (tool, wobj): &(ToolFrame, WobjFrames),
) -> Result<std::result::Result<(f64, f64), String>> {
    let Run { program, warm, .. } = run;
    let (cold, sent) = match u.through {
        Through::Direct => (meant.pose, *exact),
        Through::Derived(i) => {
            let derived = program.targets().at(i);
            let derived = &*derived;
            // Constants as seen where the expression is written, as the
            // derived target's own residual reads them.
            let eval = |e: &Expr| run.eval(derived, e);
            let poses = run
                .set
                .calls
                .get(&derived.origin.pos.offset)
                .and_then(|call| {
                    Some((
                        apply_with(call, &meant.pose, &eval)?,
                        apply_with(call, exact, &eval)?,
                    ))
                });
            match poses {
                Some(p) => p,
                None => return Ok(Err("its offsets are known only at run time".to_string())),
            }
        }
        Through::Variable => {
            return Ok(Err("reached through a variable the run assigns".to_string()))
        }
    };
    let flange = match flange_of_target(&sent, tool, wobj) {
        Ok(f) => f,
        Err(e) if e.kind == ErrorKind::Unsupported => return Ok(Err(e.message)),
        Err(e) => return Err(at_target(program, target, prefix_use(e, u))),
    };
    let q = match warm.nominal.ik_conf(&flange, &meant.conf) {
        Ok(q) => q,
        // As the correction does: with configuration monitoring off the
        // controller takes the nearest solution.
        Err(e)
            if run.set.monitoring.at(u.file, u.offset, &u.instruction) == Some(Monitor::Off)
                && e.kind == ErrorKind::Unreachable =>
        {
            match nearest_solution(warm, &flange, &meant.conf) {
                Some(q) => q,
                None => return Err(at_target(program, target, prefix_use(e, u))),
            }
        }
        Err(e) => return Err(at_target(program, target, prefix_use(e, u))),
    };
    let reached = target_of_flange(&warm.flange(&q, &meant.state), tool, wobj)?;
    Ok(Ok((
        (reached.translation.vector - cold.translation.vector).norm(),
        cold.rotation.angle_to(&reached.rotation).to_degrees(),
    )))
}

/// An error of the corrected target at another use, saying which.
fn prefix_use(e: crate::error::Error, u: &Usage) -> crate::error::Error {
    prefix(
        e,
        &format!(
            "corrected for its first use, sent by {} in {} line {} (tool {}, wobj {})",
            u.instruction,
            u.routine,
            u.line,
            u.tool_name(),
            u.wobj_name()
        ),
    )
}

/// The declaration a split copies, or why the target cannot be split by
/// renaming alone.
fn splittable(
    run: &Run,
    index: usize,
    target: &Target,
    uses: &[Usage],
) -> std::result::Result<Declaration, String> {
    let program = run.program;
    let name = target.name.as_deref().unwrap_or(&target.id);
    match target.kind {
        TargetKind::Declared => {}
        TargetKind::ArrayElement => {
            return Err(format!(
                "an element of array {name}: a copy would be a new array"
            ))
        }
        TargetKind::RecordField => {
            return Err(format!(
                "a field of record {name}: a copy would be a new record"
            ))
        }
        _ => return Err("not a declared robtarget".to_string()),
    }
    if target.value.is_none() {
        return Err("written with named constants or expressions".to_string());
    }
    let names = run.names.get_or_init(|| Names::of(program));
    let key = name.to_ascii_lowercase();
    let decl = names
        .decl_of
        .get(&index)
        .ok_or_else(|| "its declaration was not found".to_string())?;
    if decl.storage == Storage::Pers && decl.scope.is_none() {
        return Err(format!(
            "a global PERS, shared with every task that declares {name}: a copy in this one would not be"
        ));
    }
    if names.declared.get(&key).copied().unwrap_or(0) != 1 {
        return Err(format!(
            "the name {name} is declared more than once (as data or a parameter)"
        ));
    }
    if let Some(u) = uses.iter().find(|u| u.through != Through::Direct) {
        let how = match u.through {
            Through::Derived(i) => program
                .targets()
                .get(i)
                .and_then(|t| t.derived.as_ref().map(|d| d.expr.clone()))
                .unwrap_or_else(|| "a derived target".to_string()),
            _ => "a variable".to_string(),
        };
        return Err(format!(
            "also reached through {how} ({} in {} line {})",
            u.instruction, u.routine, u.line
        ));
    }
    if let Some(other) = names.other.get(&key) {
        return Err(format!("also read other than as a move's target ({other})"));
    }
    let src = program.source(target.origin.file);
    let (span, words) = statement_words(src, decl.offset)
        .ok_or_else(|| "its declaration was not found".to_string())?;
    let name_at = words
        .into_iter()
        .find(|w| src[w.clone()].eq_ignore_ascii_case(name.as_bytes()))
        .ok_or_else(|| "its declared name was not found".to_string())?;
    let literal_inside = target.value.as_ref().is_some_and(|v| {
        v.numbers()
            .all(|n| span.start <= n.span().start && n.span().end <= span.end)
    });
    if !literal_inside {
        return Err("its numbers are not written in its declaration".to_string());
    }
    Ok(Declaration {
        file: target.origin.file,
        span,
        name: name_at,
    })
}

/// Where the moves of `group` name the target: every word of the
/// instruction that is the name, which must be as many as the move's
/// targets the name is (so that nothing else is renamed).
fn renames(
    run: &Run,
    target: &Target,
    group: &[&Usage],
) -> std::result::Result<Vec<(usize, Range<usize>)>, String> {
    let program = run.program;
    let name = target.name.as_deref().unwrap_or(&target.id);
    let key = name.to_ascii_lowercase();
    let names = run.names.get_or_init(|| Names::of(program));
    let mut out = Vec::new();
    let mut seen = HashSet::new();
    for u in group {
        if !seen.insert((u.file, u.offset)) {
            continue;
        }
        let src = program.source(u.file);
        let words: Vec<Range<usize>> = statement_words(src, u.offset)
            .map(|(_, w)| w)
            .unwrap_or_default()
            .into_iter()
            .filter(|w| src[w.clone()].eq_ignore_ascii_case(name.as_bytes()))
            .collect();
        let expected = names
            .as_target
            .get(&(key.clone(), u.file, u.offset))
            .copied()
            .unwrap_or(0);
        if words.is_empty() || words.len() != expected {
            return Err(format!(
                "its name could not be located in {} in {} line {}",
                u.instruction, u.routine, u.line
            ));
        }
        out.extend(words.into_iter().map(|w| (u.file, w)));
    }
    Ok(out)
}

/// A target's pairs waiting for the run's end, where copies are named
/// (a name must be new to the whole program).
pub(super) struct Pending {
    /// Index of the target's correction among the run's corrections.
    pub correction: usize,
    pub pairs: Vec<OtherPair>,
}

/// What the other pairs of a run come to: the report lines of the uses
/// left with the first use's numbers, the splits, and the edits beyond
/// the numbers (copy declarations, renamed move arguments), per file.
pub(super) struct Shared {
    pub lines: Vec<SharedUse>,
    pub splits: Vec<SplitTarget>,
    pub edits: Vec<(usize, Edit)>,
}

/// Name and write the copies the run can make, and keep the report lines
/// of every other use.
pub(super) fn finish(
    run: &Run,
    pending: Vec<Pending>,
    corrections: &mut Vec<Correction>,
) -> Result<Shared> {
    let program = run.program;
    let mut out = Shared {
        lines: Vec::new(),
        splits: Vec::new(),
        edits: Vec::new(),
    };
    let mut words: Option<HashSet<String>> = None;
    let mut taken: HashSet<String> = HashSet::new();
    // Copy declarations by where they are inserted: copies of targets
    // declared on one line go in one edit.
    let mut inserts: BTreeMap<(usize, usize), Vec<u8>> = BTreeMap::new();
    let mut copies = Vec::new();
    for p in pending {
        let original = &corrections[p.correction];
        let target = program
            .targets()
            .iter()
            .find(|t| t.id == original.id && t.origin.pos.line == original.line);
        let Some(target) = target else { continue };
        let name = target.name.as_deref().unwrap_or(&target.id);
        for (k, pair) in p.pairs.into_iter().enumerate() {
            let mut lines = pair.lines;
            let copy = match pair.copy {
                None => {
                    out.lines.extend(lines);
                    continue;
                }
                Some(Err(why)) => Err(why),
                // Copies whose numbers are the original's would change
                // the program for nothing.
                Some(Ok(c)) if c.correction.edits == original.edits => Err(
                    "a copy for this tool and work object would be written with the same numbers"
                        .to_string(),
                ),
                Some(Ok(c)) => Ok(c),
            };
            let copy = match copy {
                Ok(c) => c,
                Err(why) => {
                    for l in &mut lines {
                        l.not_split = Some(why.clone());
                    }
                    out.lines.extend(lines);
                    continue;
                }
            };
            let words = words.get_or_insert_with(|| words_of(program));
            let first = &lines[0].corrected_for;
            let new_name = copy_name(name, first, &copy.uses[0], k + 2, words, &mut taken);
            let src = program.source(copy.decl.file);
            let text = copy_text(program, &copy, &new_name)?;
            let (at, eol, lead) = line_after(src, copy.decl.span.end);
            let indent = indent_of(src, copy.decl.span.start);
            let insert = inserts.entry((copy.decl.file, at)).or_default();
            insert.extend_from_slice(lead.as_bytes());
            insert.extend_from_slice(indent);
            insert.extend_from_slice(&text);
            insert.extend_from_slice(eol.as_bytes());
            for (file, span) in &copy.renames {
                out.edits.push((
                    *file,
                    Edit {
                        span: span.clone(),
                        expected_old: program.source(*file)[span.clone()].to_vec(),
                        new: new_name.clone().into_bytes(),
                    },
                ));
            }
            let pair = &copy.uses[0];
            out.splits.push(SplitTarget {
                id: original.id.clone(),
                copy: new_name.clone(),
                file: original.file.clone(),
                line: original.line,
                tool: pair.tool.clone(),
                wobj: pair.wobj.clone(),
                moves: copy.uses.clone(),
            });
            copies.push((
                p.correction,
                Correction {
                    id: new_name,
                    rewritten: true,
                    edits: Vec::new(),
                    ..copy.correction
                },
            ));
        }
    }
    // Each copy is listed right after its original.
    for (after, copy) in copies.into_iter().rev() {
        corrections.insert(after + 1, copy);
    }
    for ((file, at), new) in inserts {
        out.edits.push((
            file,
            Edit {
                span: at..at,
                expected_old: Vec::new(),
                new,
            },
        ));
    }
    Ok(out)
}

/// The copy's declaration: the original's text with the copy's name and
/// numbers.
fn copy_text(program: &Program, copy: &Copy, name: &str) -> Result<Vec<u8>> {
    let d = &copy.decl;
    let src = program.source(d.file);
    let shift = |r: &Range<usize>| r.start - d.span.start..r.end - d.span.start;
    let mut edits: Vec<Edit> = copy
        .correction
        .edits
        .iter()
        .map(|e| Edit {
            span: shift(&e.span),
            ..e.clone()
        })
        .collect();
    edits.push(Edit {
        span: shift(&d.name),
        expected_old: src[d.name.clone()].to_vec(),
        new: name.as_bytes().to_vec(),
    });
    apply_edits(program.file_name(d.file), &src[d.span.clone()], &edits)
}

/// Where the line after the one holding byte `end` starts, its line end,
/// and what must precede an insertion there (a line end, when `end` is on
/// the file's last line and it has none).
fn line_after(src: &[u8], end: usize) -> (usize, &'static str, &'static str) {
    match src[end..].iter().position(|&b| b == b'\n' || b == b'\r') {
        Some(p) => {
            let at = end + p;
            if src[at] == b'\r' && src.get(at + 1) == Some(&b'\n') {
                (at + 2, "\r\n", "")
            } else if src[at] == b'\r' {
                (at + 1, "\r", "")
            } else {
                (at + 1, "\n", "")
            }
        }
        None => (src.len(), "", "\n"),
    }
}

/// The blanks that start the line holding byte `start`, up to it.
fn indent_of(src: &[u8], start: usize) -> &[u8] {
    let line = src[..start]
        .iter()
        .rposition(|&b| b == b'\n' || b == b'\r')
        .map_or(0, |p| p + 1);
    let n = src[line..start]
        .iter()
        .take_while(|&&b| b == b' ' || b == b'\t')
        .count();
    &src[line..line + n]
}

/// Every word of the program's files, lower case (comments and strings
/// included: a name only a comment holds is still not taken).
fn words_of(program: &Program) -> HashSet<String> {
    let mut out = HashSet::new();
    for f in 0..program.files.len() {
        let src = program.source(f);
        for w in src.split(|&b| !(b.is_ascii_alphanumeric() || b == b'_' || b >= 0x80)) {
            if !w.is_empty() {
                out.insert(String::from_utf8_lossy(w).to_ascii_lowercase());
            }
        }
    }
    out
}

/// A new name for the copy of `name` for the pair of `pair`: `name_tool`
/// (`name_wobj` when only the work object differs from the first use's,
/// `name_tool_wobj` when both do); where that is not a legal identifier of
/// at most 32 characters or is taken, `name_N` from `n` on (the name cut
/// to fit). Unused in the whole program, case-insensitively.
fn copy_name(
    name: &str,
    first: &FramesUse,
    pair: &FramesUse,
    n: usize,
    words: &HashSet<String>,
    taken: &mut HashSet<String>,
) -> String {
    let mut parts = vec![name.to_string()];
    if !pair.tool.eq_ignore_ascii_case(&first.tool) {
        parts.push(pair.tool.clone());
    }
    if !pair.wobj.eq_ignore_ascii_case(&first.wobj) {
        parts.push(pair.wobj.clone());
    }
    let free = |c: &str, taken: &HashSet<String>| {
        let lower = c.to_ascii_lowercase();
        legal(c) && !words.contains(&lower) && !taken.contains(&lower)
    };
    let descriptive = parts.join("_");
    let chosen = if free(&descriptive, taken) {
        descriptive
    } else {
        (n..)
            .map(|k| {
                let suffix = format!("_{k}");
                let keep = MAX_NAME.saturating_sub(suffix.len());
                let base: String = name.chars().take(keep).collect();
                format!("{base}{suffix}")
            })
            .find(|c| free(c, taken))
            .unwrap_or_default()
    };
    taken.insert(chosen.to_ascii_lowercase());
    chosen
}

/// A RAPID identifier: a letter, then letters, digits and underscores, at
/// most 32 characters.
fn legal(name: &str) -> bool {
    let b = name.as_bytes();
    !b.is_empty()
        && b.len() <= MAX_NAME
        && b[0].is_ascii_alphabetic()
        && b.iter().all(|c| c.is_ascii_alphanumeric() || *c == b'_')
}

#[cfg(test)]
mod tests {
    use super::*;

    fn use_of(tool: &str, wobj: &str) -> FramesUse {
        FramesUse {
            tool: tool.to_string(),
            wobj: wobj.to_string(),
            instruction: "MoveL".to_string(),
            through: None,
            routine: "main".to_string(),
            line: 1,
        }
    }

    #[test]
    fn copies_are_named_by_what_differs_and_never_reuse_a_name() {
        let first = use_of("tGrip", "wobj0");
        let words: HashSet<String> = ["phome_tglue2".to_string()].into();
        let mut taken = HashSet::new();
        let mut name =
            |tool, wobj, n| copy_name("pHome", &first, &use_of(tool, wobj), n, &words, &mut taken);
        assert_eq!(name("tGlue", "wobj0", 2), "pHome_tGlue");
        assert_eq!(name("tGrip", "wTable", 3), "pHome_wTable");
        assert_eq!(name("tGlue", "wTable", 4), "pHome_tGlue_wTable");
        // Taken in the program (case-insensitively): numbered.
        assert_eq!(name("TGLUE2", "wobj0", 5), "pHome_5");
        // The same descriptive name twice (tools differing in case only
        // cannot happen in RAPID, but the names stay unique anyway).
        assert_eq!(name("TGLUE", "wobj0", 6), "pHome_6");
    }

    #[test]
    fn a_copy_name_fits_32_characters() {
        let first = use_of("tGrip", "wobj0");
        let long = "pAVeryLongTargetNameOf32CharsXYZ";
        assert_eq!(long.len(), 32);
        let mut taken = HashSet::new();
        let c = copy_name(
            long,
            &first,
            &use_of("tGlue", "wobj0"),
            2,
            &HashSet::new(),
            &mut taken,
        );
        assert_eq!(c, "pAVeryLongTargetNameOf32CharsX_2");
        assert!(legal(&c));
    }

    #[test]
    fn a_copy_goes_on_the_line_after_the_declaration_with_its_line_end() {
        let src = b"  CONST robtarget p := [];  ! taught\r\n  PROC main()";
        assert_eq!(line_after(src, 26), (38, "\r\n", ""));
        assert_eq!(indent_of(src, 2), b"  ");
        let last = b"CONST robtarget p := [];";
        assert_eq!(line_after(last, last.len()), (last.len(), "", "\n"));
    }
}
