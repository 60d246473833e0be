//! From bytes to [`Program`]: pieces from the scanner, each parsed by pest
//! with the rule its context calls for, assembled into blocks here; then a
//! pass over the whole run for what needs every file (record types, FUNCs
//! returning robtarget, identifiers unique across modules).
//!
//! This file holds the entry points, the state of one file's parse and
//! the glue to pest ([`FileParser::with_pair`]); the assembly is in
//! `structure` (modules, routines), `statements`, `declarations`,
//! `expressions`, with `words` (reserved words), `shapes` (what a value
//! of each type looks like), `calls` (the instruction table), `run` (the
//! whole-run pass) and `messages` (syntax errors).

use super::motion::{motion_signature, ArgAt};
use super::scan::{Piece, PieceKind, Scanner};
use super::visit::*;
use super::*;
use crate::error::{decode_lossless, Error, ErrorKind, Location};
use pest::iterators::Pair;
use pest::Parser as _;
use std::collections::{HashMap, HashSet};

mod calls;
mod cuts;
mod declarations;
mod expressions;
mod messages;
mod run;
mod shapes;
mod statements;
mod structure;
mod words;

use calls::*;
use expressions::*;
pub(super) use run::{name_space, qualified};
use shapes::*;
use words::*;

#[derive(pest_derive::Parser)]
#[grammar = "../grammar/rapid.pest"]
struct RapidParser;

/// Blocks (IF, FOR, ...) nested deeper than this are refused: the
/// assembler recurses on them.
const MAX_BLOCK_DEPTH: usize = 64;
/// Binary operators in one expression beyond this are refused (the tree
/// is as deep as the chain is long).
const MAX_OPERATORS: usize = 1000;

/// Whether `word` is one of RAPID's reserved words (no name can be one).
pub(super) fn is_reserved_word(word: &str) -> bool {
    is_reserved(word)
}

/// Parse one file (one or several modules).
pub fn parse(file_name: &str, bytes: &[u8]) -> Result<Program> {
    parse_files(&[(file_name, bytes)])
}

/// Parse a run of files together: identifiers are made unique across all
/// their modules, and RECORD types and FUNCs of one file apply to all.
pub fn parse_files(inputs: &[(&str, &[u8])]) -> Result<Program> {
    let mut b = Builder::default();
    let mut lines = Vec::new();
    for (i, (name, bytes)) in inputs.iter().enumerate() {
        b.prog.files.push(name.to_string());
        b.prog.sources.push(Arc::from(*bytes));
        let line_starts = line_starts(bytes);
        FileParser::new(i, name, bytes, &line_starts, &mut b).run()?;
        lines.push(line_starts);
    }
    // RAPID loads one module of a name per task; two would also make the
    // identifiers of the run ambiguous.
    let mut seen: HashMap<String, usize> = HashMap::new();
    for (i, m) in b.prog.modules.iter().enumerate() {
        if let Some(&first) = seen.get(&m.name.to_lowercase()) {
            let f = &b.prog.modules[first];
            let name = inputs.get(m.file).map_or("", |x| x.0);
            let src = inputs.get(m.file).map_or(&[][..], |x| x.1);
            return Err(Error::new(
                ErrorKind::Syntax,
                format!(
                    "module {} is defined twice (also at {}:{})",
                    m.name,
                    inputs.get(f.file).map_or("", |x| x.0),
                    f.pos.line
                ),
            )
            .at(Location::from_offset(name, src, m.pos.offset)));
        }
        seen.insert(m.name.to_lowercase(), i);
    }
    b.finish(inputs, &lines)?;
    Ok(b.prog)
}

/// The program of `src` read as its skeleton `skeleton` (see
/// [`fastmove`](super::fastmove)): the program [`parse`] makes of `src`,
/// every statement, target and identifier alike, without the grammar
/// reading the cut moves. Two things differ, and make it a program to
/// walk, not to rewrite: the offsets of what the skeleton kept are the
/// skeleton's (a cut move's targets are at its place there, their numbers
/// at the file's offsets), and its source is the skeleton. Lines and
/// columns are the file's throughout.
pub fn parse_skeleton(
    file_name: &str,
    skeleton: &super::fastmove::Skeleton,
    src: &[u8],
) -> Result<Program> {
    read_skeleton(file_name, skeleton, src, false)
}

/// The program of `src` read as its skeleton, each run of cut moves left
/// unread as one [`StatementKind::CutMoves`]: every other statement,
/// target and identifier is [`parse_skeleton`]'s (the skeleton's inline
/// targets numbered after the cut ones), and the cut moves' targets are
/// not among the program's. A walk that reads the moves from the file
/// itself takes this one: reading a million moves into statements and
/// targets was most of timing a CAM program.
pub fn parse_skeleton_runs(
    file_name: &str,
    skeleton: &super::fastmove::Skeleton,
    src: &[u8],
) -> Result<Program> {
    read_skeleton(file_name, skeleton, src, true)
}

fn read_skeleton(
    file_name: &str,
    skeleton: &super::fastmove::Skeleton,
    src: &[u8],
    runs: bool,
) -> Result<Program> {
    let bytes: &[u8] = &skeleton.bytes;
    let mut b = Builder::default();
    b.prog.files.push(file_name.to_string());
    b.prog.sources.push(Arc::from(bytes));
    let line_starts = line_starts(bytes);
    let mut p = FileParser::new(0, file_name, bytes, &line_starts, &mut b);
    p.cuts = Some(cuts::CutFeed::new(skeleton, src, runs));
    if !runs {
        // The cut literals are most of the targets: room for them at once
        // (a list of a million grown by doubling was copied twenty times).
        let literals: usize = skeleton.literals.iter().map(|&n| usize::from(n)).sum();
        p.b.prog.targets.reserve(literals);
    }
    p.run()?;
    b.finish(&[(file_name, bytes)], &[line_starts])?;
    Ok(b.prog)
}

pub(super) fn line_starts(src: &[u8]) -> Vec<usize> {
    let mut v = vec![0];
    v.extend(
        src.iter()
            .enumerate()
            .filter(|(_, &b)| b == b'\n')
            .map(|(i, _)| i + 1),
    );
    v
}

fn pos_of(src: &[u8], lines: &[usize], offset: usize) -> Pos {
    let offset = offset.min(src.len());
    let line = lines.partition_point(|&s| s <= offset).max(1);
    let start = lines.get(line - 1).copied().unwrap_or(0);
    Pos {
        offset,
        line: line as u32,
        col: column(&src[start..offset]),
    }
}

/// The 1-based column after `prefix`, the line up to a place: characters
/// where it is UTF-8, bytes otherwise.
pub(super) fn column(prefix: &[u8]) -> u32 {
    let n = match std::str::from_utf8(prefix) {
        Ok(s) => s.chars().count(),
        Err(_) => prefix.len(),
    };
    1 + n as u32
}

// ------------------------------------------------------------- builder

#[derive(Default)]
struct Builder {
    prog: Program,
    names: foldhash::HashMap<String, Arc<str>>,
    /// Per routine (lower-case "module\0routine"): literals counted so far.
    inline_counts: HashMap<String, usize>,
    /// The module and routine of each run of cut moves left unread
    /// ([`parse_skeleton_runs`]): name spaces of targets the program does
    /// not list.
    cut_runs: Vec<(Arc<str>, Arc<str>)>,
}

impl Builder {
    fn intern(&mut self, s: &str) -> Arc<str> {
        if let Some(a) = self.names.get(s) {
            return a.clone();
        }
        let a: Arc<str> = Arc::from(s);
        self.names.insert(s.to_string(), a.clone());
        a
    }
}

/// Instruction context of inline literals.
#[derive(Clone, Default)]
struct InlineCtx {
    instruction: Option<Arc<str>>,
    tool: Option<Arc<str>>,
    wobj: Option<Arc<str>>,
    assigned_to: Option<String>,
}

struct FileParser<'a, 'b> {
    file: usize,
    name: &'a str,
    src: &'a [u8],
    lines: &'a [usize],
    scanner: Scanner<'a>,
    peeked: Option<Piece>,
    b: &'b mut Builder,
    module: Arc<str>,
    routine: Option<Arc<str>>,
    /// Robtarget and jointtarget literals of the current routine so far.
    inline_k: usize,
    joint_k: usize,
    call_targets: Vec<usize>,
    call_joints: Vec<usize>,
    /// The moves cut out of the file, where the bytes parsed are its
    /// skeleton ([`parse_skeleton`]).
    cuts: Option<cuts::CutFeed<'a>>,
}

/// Pest's view of a piece: ASCII as is, every other byte as U+007F, so
/// that offsets are unchanged.
fn piece_text(raw: &[u8]) -> std::borrow::Cow<'_, str> {
    match std::str::from_utf8(raw) {
        Ok(s) if raw.is_ascii() => std::borrow::Cow::Borrowed(s),
        _ => std::borrow::Cow::Owned(
            raw.iter()
                .map(|&b| if b >= 0x80 { '\u{7F}' } else { b as char })
                .collect(),
        ),
    }
}

fn upper_word(src: &[u8], p: &Piece) -> String {
    String::from_utf8_lossy(&src[p.first.0..p.first.1]).to_ascii_uppercase()
}

impl<'a, 'b> FileParser<'a, 'b> {
    fn new(
        file: usize,
        name: &'a str,
        src: &'a [u8],
        lines: &'a [usize],
        b: &'b mut Builder,
    ) -> Self {
        let mut scanner = Scanner::new(src);
        if src.starts_with(&[0xEF, 0xBB, 0xBF]) {
            scanner.skip_to(3);
        }
        FileParser {
            file,
            name,
            src,
            lines,
            scanner,
            peeked: None,
            b,
            module: Arc::from(""),
            routine: None,
            inline_k: 0,
            joint_k: 0,
            call_targets: Vec::new(),
            call_joints: Vec::new(),
            cuts: None,
        }
    }

    fn err(&self, offset: usize, msg: impl Into<String>) -> Error {
        Error::new(ErrorKind::Syntax, msg).at(Location::from_offset(self.name, self.src, offset))
    }

    fn peek(&mut self) -> Result<Option<Piece>> {
        if self.peeked.is_none() {
            self.peeked = self
                .scanner
                .next_piece()
                .map_err(|e| self.err(e.offset, e.message))?;
        }
        Ok(self.peeked)
    }

    fn next(&mut self) -> Result<Option<Piece>> {
        self.peek()?;
        Ok(self.peeked.take())
    }

    fn pos(&self, offset: usize) -> Pos {
        pos_of(self.src, self.lines, offset)
    }

    fn found(&self, p: &Piece) -> String {
        if p.first.1 > p.first.0 {
            format!("`{}`", decode_lossless(&self.src[p.first.0..p.first.1]))
        } else {
            let end = (p.start + 12).min(p.end);
            format!("`{}`", decode_lossless(&self.src[p.start..end]).trim())
        }
    }

    /// Parse a piece with `rule`; `f` builds from the rule's pair.
    fn with_pair<T>(
        &mut self,
        rule: Rule,
        piece: &Piece,
        f: impl FnOnce(&mut Self, Pair<'_, Rule>) -> Result<T>,
    ) -> Result<T> {
        let raw = &self.src[piece.start..piece.end];
        let text = piece_text(raw);
        let mut pairs = match RapidParser::parse(rule, &text) {
            Ok(p) => p,
            Err(e) => return Err(self.pest_error(&e, &text, piece.start, rule)),
        };
        let Some(pair) = pairs.next() else {
            return Err(self.err(piece.start, "internal: empty parse"));
        };
        if let Some(id) = pair
            .clone()
            .into_inner()
            .flatten()
            .find(|p| p.as_rule() == Rule::identifier && is_reserved(p.as_str()))
        {
            return Err(self.err(
                piece.start + id.as_span().start(),
                format!(
                    "expected a name, found `{}`, a reserved word of RAPID",
                    id.as_str()
                ),
            ));
        }
        f(self, pair)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_compact_if_call_keeps_its_targets_after_sorting() {
        // The derived target is found after the literal below it, so the
        // sort moves both; the call inside the one-line IF must follow.
        let src = b"MODULE m\nPROC main()\nIF TRUE MoveL Offs(p10,0,0,10), v100, fine, tool0;\nMoveL [[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;\nENDPROC\nENDMODULE\n";
        let prog = parse("m.mod", src).unwrap();
        let body = &prog.modules[0].routines[0].body;
        let StatementKind::CompactIf { then, .. } = &body[0].kind else {
            panic!("{:?}", body[0].kind)
        };
        let StatementKind::Call(c) = &then.kind else {
            panic!("{:?}", then.kind)
        };
        assert_eq!(prog.targets()[c.targets[0]].id, "main@1");
        let StatementKind::Call(c) = &body[1].kind else {
            panic!("{:?}", body[1].kind)
        };
        assert_eq!(prog.targets()[c.targets[0]].id, "main#1");
    }

    #[test]
    fn reserved_list_matches_the_grammar() {
        for w in RESERVED {
            assert!(
                RapidParser::parse(Rule::reserved_word, w).is_ok(),
                "{w} not in the grammar"
            );
        }
    }
}
