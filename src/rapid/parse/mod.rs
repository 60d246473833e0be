//! From bytes to [`Program`]: pieces from the scanner, each read by the
//! fast lane where it can (the statements large programs are made of,
//! held compactly in runs: `lane`) and else parsed by pest with the rule
//! its context calls for, assembled into blocks here; then a pass over
//! the whole run for what needs every file (record types, FUNCs
//! returning robtarget, identifiers unique across modules, the targets'
//! numbering).
//!
//! The entry points are here; the state of one file's parse and the glue
//! to pest are in `file`, the assembly in `structure` (modules, routines),
//! `statements`, `declarations`, `expressions`, with `words` (reserved
//! words), `shapes` (what a value of each type looks like), `calls` (the
//! instruction table), `lane` (the fast lane's statements into runs),
//! `run` (the whole-run pass) and `messages` (syntax errors).

use super::build::{
    aggregate_of, arg, declaration, declared_id, inline_id, keyword_number, scope, storage,
    DeclParts, HeldBy, MoveParts, Place, TargetParts, SCOPE_WORDS, STORAGE_WORDS,
};
use super::lane::{read_decl, read_move, LaneDecl, Seen};
use super::motion::{motion_signature, ArgAt};
use super::place::{line_starts, pos_of};
use super::scan::{Piece, PieceKind, Scanner};
use super::visit::*;
use super::*;
use crate::error::{decode_lossless, Error, ErrorKind, Location, Result};
use pest::iterators::Pair;
use std::collections::{HashMap, HashSet};
use std::ops::Range;
use std::sync::Arc;

mod ahead;
mod builder;
mod calls;
mod declarations;
mod duplicates;
mod expressions;
mod file;
mod grammar;
mod items;
mod lane;
mod messages;
mod run;
mod shapes;
mod statements;
mod structure;
mod words;

use ahead::Ahead;
use builder::{Builder, InlineCtx};
use calls::*;
use expressions::*;
use file::*;
use grammar::Rule;
use shapes::*;
use words::*;

/// How a run is read. Every way reads the same program; the tests that
/// hold the ways to it read each ([`parse_read`]), every other caller
/// the first ([`parse_sources`]). A test hook, hidden from the docs.
#[doc(hidden)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reading {
    /// The fast lane first, reading stretches of the file ahead of the
    /// parse on every core: what every command does.
    Lane,
    /// The fast lane first, each statement at the parse's place.
    LaneInPlace,
    /// The grammar alone, every statement held one by one.
    Grammar,
}

impl Reading {
    #[doc(hidden)]
    pub const ALL: [Reading; 3] = [Reading::Lane, Reading::LaneInPlace, Reading::Grammar];
}

/// What a RAPID file in an encoding that is not read should be saved as:
/// the controller's own character set is ISO 8859-1 (ABB, Technical
/// reference manual, RAPID kernel, 2.1 Character set), and UTF-8 is read
/// as RobotStudio writes it.
pub const SAVE_AS: &str =
    "UTF-8 or ISO-8859-1 (Latin-1), as RobotStudio and the controller write RAPID";

/// Parse one file (one or several modules).
pub fn parse(file_name: &str, bytes: &[u8]) -> Result<Program> {
    parse_files(&[(file_name, bytes)])
}

/// Parse a run of files together: identifiers are made unique across all
/// their modules, and RECORD types and FUNCs of one file apply to all.
pub fn parse_files(inputs: &[(&str, &[u8])]) -> Result<Program> {
    let sources = inputs
        .iter()
        .map(|(name, bytes)| (name.to_string(), Source::copied(bytes)))
        .collect();
    parse_sources(sources)
}

/// [`parse_files`] of files whose bytes the program keeps as they are
/// (a file mapped into memory is not copied).
pub fn parse_sources(inputs: Vec<(String, Source)>) -> Result<Program> {
    parse_read(inputs, Reading::Lane)
}

/// [`parse_sources`] read the way `reading` says: a test hook.
#[doc(hidden)]
pub fn parse_read(inputs: Vec<(String, Source)>, reading: Reading) -> Result<Program> {
    let mut b = Builder {
        lanes: reading != Reading::Grammar,
        ahead: reading == Reading::Lane,
        ..Builder::default()
    };
    let mut lines = Vec::new();
    for (i, (name, source)) in inputs.iter().enumerate() {
        b.prog.files.push(name.clone());
        b.prog.sources.push(source.clone());
        let bytes = source.bytes();
        // Offsets, edits and markers are of the file's own bytes: a file
        // in an encoding of two or four bytes a character is named and
        // refused rather than read as Latin-1 noise (`ÿþM`).
        crate::input::refuse_unread_encoding(name, bytes, SAVE_AS)?;
        let line_starts = line_starts(bytes);
        FileParser::new(i, name, bytes, &line_starts, &mut b).run()?;
        lines.push(line_starts);
    }
    let refs: Vec<(&str, &[u8])> = inputs
        .iter()
        .map(|(n, s)| (n.as_str(), s.bytes()))
        .collect();
    // RAPID loads one module of a name per task; two would also make the
    // identifiers of the run ambiguous.
    let mut seen: HashMap<String, usize> = HashMap::new();
    for (i, m) in b.prog.modules.iter().enumerate() {
        if let Some(&first) = seen.get(&m.name.to_lowercase()) {
            let f = &b.prog.modules[first];
            let name = refs.get(m.file).map_or("", |x| x.0);
            let src = refs.get(m.file).map_or(&[][..], |x| x.1);
            return Err(Error::new(
                ErrorKind::Syntax,
                format!(
                    "module {} is defined twice (also at {}:{})",
                    m.name,
                    refs.get(f.file).map_or("", |x| x.0),
                    f.pos.line
                ),
            )
            .at(Location::from_offset(name, src, m.pos.offset)));
        }
        seen.insert(m.name.to_lowercase(), i);
    }
    refuse_speeds(&b.prog, &refs)?;
    duplicates::refuse_duplicates(&b.prog, &refs)?;
    b.finish(&refs, &lines)?;
    super::bounds::refuse_out_of_bounds(&b.prog)?;
    Ok(b.prog)
}

/// A speeddata whose TCP or orientation speed is not a positive number:
/// the controller stops on it, and a time estimate would divide by it.
/// Every such speed is reported at its number.
fn refuse_speeds(prog: &Program, refs: &[(&str, &[u8])]) -> Result<()> {
    let mut errors = Vec::new();
    for s in &prog.speeds {
        for (what, n) in [("TCP speed", &s.v_tcp), ("orientation speed", &s.v_ori)] {
            if n.value.is_finite() && n.value > 0.0 {
                continue;
            }
            let (name, src) = refs.get(s.origin.file).copied().unwrap_or(("", &[]));
            errors.push(
                Error::new(
                    ErrorKind::Syntax,
                    format!(
                        "speeddata {}: the {what} {} is not a speed (it must be greater than 0)",
                        s.name, n.value
                    ),
                )
                .at(Location::from_offset(name, src, n.span().start)),
            );
        }
    }
    match Error::many(errors) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_compact_if_call_keeps_its_targets_after_sorting() {
        // The derived target is found after the literal below it, so the
        // sort moves both; the call inside the one-line IF must follow
        // (read by the grammar: the lane would hold the move in a run).
        let src = b"MODULE m\nPROC main()\nIF TRUE MoveL Offs(p10,0,0,10), v100, fine, tool0;\nMoveL [[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;\nENDPROC\nENDMODULE\n";
        let prog = parse_read(
            vec![("m.mod".to_string(), Source::copied(src))],
            Reading::Grammar,
        )
        .unwrap();
        let body = &prog.modules[0].routines[0].body;
        let StatementKind::CompactIf { then, .. } = &body[0].kind else {
            panic!("{:?}", body[0].kind)
        };
        let StatementKind::Call(c) = &then.kind else {
            panic!("{:?}", then.kind)
        };
        assert_eq!(prog.targets().at(c.targets[0]).id, "main@1");
        let StatementKind::Call(c) = &body[1].kind else {
            panic!("{:?}", body[1].kind)
        };
        assert_eq!(prog.targets().at(c.targets[0]).id, "main#1");
    }

    #[test]
    fn reserved_list_matches_the_grammar() {
        for w in RESERVED {
            assert!(
                grammar::read(Rule::reserved_word, w).is_ok(),
                "{w} not in the grammar"
            );
        }
    }
}
