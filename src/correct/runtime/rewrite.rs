//! The program rewritten to call the controller module: every move's
//! target argument wrapped in the module's correcting function, with the
//! move's own tool and work object, so that the target is corrected when
//! the program reaches it. Targets computed at run time (a camera's
//! variable, `Offs` of a variable) are covered too, which a rewrite of
//! numbers never can. Nothing else changes: the declarations keep their
//! cold numbers.
//!
//! ```text
//! MoveL p10, v100, z1, tGlue\WObj:=wTable;
//! MoveL RtWarm(p10, tGlue \WObj:=wTable), v100, z1, tGlue\WObj:=wTable;
//! MoveAbsJ jHome\NoEOffs, v1000, fine, tool0;
//! MoveAbsJ RtWarmJ(jHome)\NoEOffs, v1000, fine, tool0;
//! ```
//!
//! A move already wrapped is left as it is: a second run changes nothing.

use crate::rapid::numprint::NumberPrint;
use crate::rapid::rewrite::Edit;
use crate::rapid::Program;
use crate::rapid::{motion_signature, ArgAt};
use crate::resolve::{each_move_instruction, Move};
use std::collections::HashMap;
use std::io::Write;
use std::ops::Range;

/// How many moves the rewrite touched, per file and in all.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct MoveTally {
    /// Target arguments wrapped by this run.
    pub wrapped: usize,
    /// Target arguments a former run wrapped already.
    pub already: usize,
    /// Move instructions of no robot (MoveExtJ), or written so that the
    /// rewrite cannot find their arguments (a late-bound call): left.
    pub left: usize,
    /// Of those wrapped, the ones the module's table knows (a lookup on
    /// the controller); the rest take the slower path (`CalcJointT`).
    pub table: usize,
    /// Target arguments left as written, each with its reason (a target
    /// read back from the robot is where the warm robot already is).
    pub unwrapped: Vec<Unwrapped>,
}

/// A move's target argument the rewrite leaves as written, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Unwrapped {
    pub file: usize,
    pub line: u32,
    pub col: u32,
    pub reason: String,
}

/// How one target argument of a move is corrected on the controller.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Route {
    /// By the module's table, row `n` (from 1).
    Table(usize),
    /// An element of a one-dimensional array indexed at run time
    /// (`pCorner{i}`): by the table, element `k`'s row being `n - 1 + k`.
    TableArray(usize),
    /// By the slower path: the controller's joints of the target.
    Slow,
    /// Not at all, for this reason.
    Leave(String),
    /// By the table, the row an expression gives (made of a
    /// [`Route::TableArray`] by the rewrite).
    Index(String),
}

/// The index of a one-dimensional array's element as written
/// (`pCorner{i + 1}` → `i + 1`); `None` for anything else (a record's
/// field after it, two dimensions, a call).
fn array_index(written: &str) -> Option<&str> {
    let open = written.find('{')?;
    let name = written[..open].trim_end();
    let plain = name.bytes().next().is_some_and(|b| b.is_ascii_alphabetic())
        && name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_');
    let index = written[open + 1..].strip_suffix('}')?;
    let (mut depth, mut ok) = (0i32, plain);
    for b in index.bytes() {
        match b {
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' => depth -= 1,
            b',' if depth == 0 => ok = false,
            _ => {}
        }
        ok &= depth >= 0;
    }
    (ok && depth == 0 && !index.trim().is_empty()).then_some(index.trim())
}

/// The module's four correcting functions, by the module's name `n`.
pub(super) struct Funcs {
    rob: String,
    rob_table: String,
    joint: String,
    joint_table: String,
}

impl Funcs {
    pub(super) fn new(n: &str) -> Funcs {
        Funcs {
            rob: n.to_string(),
            rob_table: format!("{n}T"),
            joint: format!("{n}J"),
            joint_table: format!("{n}JT"),
        }
    }

    /// Whether `written` already calls one of them.
    pub(super) fn wraps(&self, written: &str) -> bool {
        [&self.rob, &self.rob_table, &self.joint, &self.joint_table]
            .iter()
            .any(|f| calls(written, f))
    }
}

/// One file's insertions, held compactly: a million moves are two
/// million insertions of a handful of distinct texts (the call opened,
/// and closed with each tool and work object), so each is a place and
/// the number of its text. As edits with bytes of their own they took
/// four times the file in memory.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Insertions {
    /// (byte offset in the file, text number), in file order.
    at: Vec<(usize, u32)>,
    texts: Vec<Box<[u8]>>,
}

impl Insertions {
    pub fn is_empty(&self) -> bool {
        self.at.is_empty()
    }

    pub fn len(&self) -> usize {
        self.at.len()
    }

    /// Where each insertion goes and its text, in file order.
    pub fn iter(&self) -> impl Iterator<Item = (usize, &[u8])> + '_ {
        self.at
            .iter()
            .map(|&(at, t)| (at, self.texts.get(t as usize).map_or(&[][..], |b| &b[..])))
    }

    fn push(&mut self, at: usize, text: &[u8], known: &mut HashMap<Vec<u8>, u32>) {
        let n = match known.get(text) {
            Some(&n) => n,
            None => {
                let n = self.texts.len() as u32;
                self.texts.push(text.into());
                known.insert(text.to_vec(), n);
                n
            }
        };
        self.at.push((at, n));
    }
}

/// The insertions that wrap every move of `program` (by file), and the
/// tally. `func` is the module's name (its functions `func`, `funcT`,
/// `funcJ`, `funcJT`); `route` says how each move's target argument
/// (its point number) is corrected.
pub fn move_insertions(
    program: &Program,
    func: &str,
    route: &mut dyn FnMut(&Move, usize) -> Route,
) -> (Vec<Insertions>, MoveTally) {
    let mut out: Vec<Insertions> = vec![Insertions::default(); program.files.len()];
    let mut known: Vec<HashMap<Vec<u8>, u32>> = vec![HashMap::new(); program.files.len()];
    let mut tally = MoveTally::default();
    let funcs = Funcs::new(func);
    each_move_instruction(program, &mut |m: &Move| {
        let src = program.source(m.file);
        let Some(found) = wrap(src, m, &funcs, route) else {
            tally.left += 1;
            return;
        };
        for w in found {
            match w {
                Wrap::Already => tally.already += 1,
                Wrap::Left(reason) => tally.unwrapped.push(Unwrapped {
                    file: m.file,
                    line: m.line,
                    col: m.col,
                    reason,
                }),
                Wrap::Edit(open, close, by_table) => {
                    tally.wrapped += 1;
                    tally.table += usize::from(by_table);
                    for e in [open, close] {
                        out[m.file].push(e.span.start, &e.new, &mut known[m.file]);
                    }
                }
            }
        }
    });
    for ins in &mut out {
        // Stable: the call opened before an argument stays before the
        // close of one that ends where it starts.
        ins.at.sort_by_key(|&(at, _)| at);
    }
    (out, tally)
}

/// `src` with the insertions and `marker` (an insertion too: the line
/// under the module header) written to `out` as it goes, and the
/// numbers' fingerprint line above the last `ENDMODULE`, taken of the
/// rewritten bytes before it: the file is never held whole.
pub fn write_rewritten(
    src: &[u8],
    ins: &Insertions,
    marker: Option<&Edit>,
    sealed: &crate::correct::marker::Marker,
    out: &mut dyn Write,
) -> std::io::Result<()> {
    let end = crate::correct::marker::numbers_at(src);
    let mut print = NumberPrint::new();
    // The marker goes under the module header, before every move.
    let marker = marker.map(|m| (m.span.start, &m.new[..]));
    let mut from = 0;
    for (at, text) in marker.into_iter().chain(ins.iter()) {
        let at = at.min(src.len());
        // The source up to the insertion: the part before the last
        // ENDMODULE line counts in the fingerprint.
        if at > from {
            let cut = at.min(end).max(from);
            print.feed(&src[from..cut]);
            out.write_all(&src[from..at])?;
            from = at;
        }
        // As the whole rewritten file's fingerprint would: an insertion
        // on the ENDMODULE line's start is on that line.
        if at < end || end == src.len() {
            print.feed(text);
        }
        out.write_all(text)?;
    }
    if from < end {
        print.feed(&src[from..end]);
        out.write_all(&src[from..end])?;
        from = end;
    }
    // The rewritten body's line ends and last line are the source's:
    // the insertions add neither.
    let seal = sealed.seal(&print.finish());
    let line = crate::correct::marker::numbers_line(src, end, &seal);
    out.write_all(&line)?;
    out.write_all(&src[from..])
}

enum Wrap {
    Already,
    Left(String),
    /// The call opened before the argument and closed after it, and
    /// whether by the table.
    Edit(Edit, Edit, bool),
}

/// The wraps of one move's target arguments; `None` where the move moves
/// no robot or its arguments cannot be read from its text.
fn wrap(
    src: &[u8],
    m: &Move,
    funcs: &Funcs,
    route: &mut dyn FnMut(&Move, usize) -> Route,
) -> Option<Vec<Wrap>> {
    let sig = motion_signature(m.instruction)?;
    sig.tool?;
    let args = arguments(src, m.offset)?;
    // The positional arguments: those not starting with `\`; each one's
    // expression ends where its first optional argument starts.
    let positional: Vec<&Arg> = args.iter().filter(|a| !a.optional).collect();
    let tool_at = match sig.tool? {
        ArgAt::Index(i) => i,
        ArgAt::FromEnd(k) => positional.len().checked_sub(k)?,
    };
    let tool = text(src, positional.get(tool_at)?.head.clone());
    // The work object as the move gives it: `\WObj:=w`, or passed on
    // from the routine's own optional parameter, `\WObj?W`.
    let wobj = args.iter().find_map(|a| a.wobj.clone()).map(|(r, passed)| {
        let w = text(src, r);
        if passed {
            format!(" \\WObj?{w}")
        } else {
            format!(" \\WObj:={w}")
        }
    });
    let joints = sig.robtargets.is_empty();
    let places = if joints {
        sig.jointtargets
    } else {
        sig.robtargets
    };
    let mut out = Vec::new();
    for (k, &i) in places.iter().enumerate() {
        let head = positional.get(i)?.head.clone();
        let written = text(src, head.clone());
        if funcs.wraps(&written) {
            out.push(Wrap::Already);
            continue;
        }
        let frames = format!("{tool}{}", wobj.as_deref().unwrap_or(""));
        // Two insertions, before and after the argument: its own bytes are
        // not copied (a CAM program's million inline targets).
        let mut route = route(m, k);
        if let Route::TableArray(first) = route {
            // The row is the element's: the index expression, as written,
            // added to the array's first row.
            route = match array_index(&written) {
                Some(index) if first == 1 => Route::Index(index.to_string()),
                Some(index) => Route::Index(format!("{} + {index}", first - 1)),
                None => Route::Slow,
            };
        }
        let (name, close, by_table) = match (route, joints) {
            (Route::Leave(reason), _) => {
                out.push(Wrap::Left(reason));
                continue;
            }
            (Route::TableArray(_), _) => unreachable!("made an index above"),
            (Route::Index(r), false) => (&funcs.rob_table, format!(", {r}, {frames})"), true),
            (Route::Index(r), true) => (&funcs.joint_table, format!(", {r})"), true),
            (Route::Table(r), false) => (&funcs.rob_table, format!(", {r}, {frames})"), true),
            (Route::Table(r), true) => (&funcs.joint_table, format!(", {r})"), true),
            (Route::Slow, false) => (&funcs.rob, format!(", {frames})"), false),
            (Route::Slow, true) => (&funcs.joint, ")".to_string(), false),
        };
        out.push(Wrap::Edit(
            insert(head.start, format!("{name}(")),
            insert(head.end, close),
            by_table,
        ));
    }
    Some(out)
}

/// Whether `written` is a call of `name` (as RAPID reads names: without
/// regard to case).
fn calls(written: &str, name: &str) -> bool {
    written.len() > name.len()
        && written.as_bytes()[..name.len()].eq_ignore_ascii_case(name.as_bytes())
        && written[name.len()..].trim_start().starts_with('(')
}

fn insert(at: usize, text: String) -> Edit {
    Edit {
        span: at..at,
        expected_old: Vec::new(),
        new: text.into_bytes(),
    }
}

fn text(src: &[u8], r: Range<usize>) -> String {
    // RAPID is Latin-1: each byte one character.
    src[r].iter().map(|&b| b as char).collect()
}

/// One comma-separated argument of an instruction.
pub(super) struct Arg {
    /// Starts with `\` (an optional argument on its own).
    pub(super) optional: bool,
    /// The argument's expression, trimmed, up to its first optional
    /// argument.
    pub(super) head: Range<usize>,
    /// The value of a `\WObj:=` among its optional arguments, or the
    /// parameter a `\WObj?` passes on (`true`).
    wobj: Option<(Range<usize>, bool)>,
}

/// The arguments of the instruction at `offset` (its name first), up to
/// its `;`: split at the commas outside brackets, parentheses and
/// strings. `None` where the statement does not end (a damaged file the
/// parser took anyway) or starts with no name.
pub(super) fn arguments(src: &[u8], offset: usize) -> Option<Vec<Arg>> {
    let mut i = offset;
    let name_end = src[i..]
        .iter()
        .position(|b| !(b.is_ascii_alphanumeric() || *b == b'_'))
        .map(|p| i + p)?;
    if name_end == i {
        return None;
    }
    i = name_end;
    let mut pieces: Vec<Range<usize>> = Vec::new();
    let (mut depth, mut start) = (0i32, i);
    loop {
        let b = *src.get(i)?;
        match b {
            b'"' => {
                i += 1;
                while *src.get(i)? != b'"' {
                    i += 1;
                }
            }
            b'!' if depth == 0 => {
                // A comment runs to the line's end.
                while !matches!(src.get(i), Some(b'\n' | b'\r') | None) {
                    i += 1;
                }
                continue;
            }
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' => depth -= 1,
            b',' if depth == 0 => {
                pieces.push(start..i);
                start = i + 1;
            }
            b';' if depth == 0 => {
                pieces.push(start..i);
                break;
            }
            _ => {}
        }
        i += 1;
    }
    Some(pieces.into_iter().map(|r| split_optional(src, r)).collect())
}

/// An argument's expression and the `\WObj:=` among the optional
/// arguments that follow it.
fn split_optional(src: &[u8], r: Range<usize>) -> Arg {
    let trimmed = trim(src, r.clone());
    let optional = src.get(trimmed.start) == Some(&b'\\');
    // The first `\` outside brackets and strings ends the expression.
    let mut cuts = Vec::new();
    let (mut depth, mut in_str) = (0i32, false);
    for i in r.clone() {
        match src[i] {
            b'"' => in_str = !in_str,
            _ if in_str => {}
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' => depth -= 1,
            b'\\' if depth == 0 => cuts.push(i),
            _ => {}
        }
    }
    let head_end = cuts.first().copied().unwrap_or(r.end);
    let mut wobj = None;
    for (k, &c) in cuts.iter().enumerate() {
        let end = cuts.get(k + 1).copied().unwrap_or(r.end);
        let part = trim(src, c + 1..end);
        let t = &src[part.clone()];
        if t.len() > 4 && t[..4].eq_ignore_ascii_case(b"wobj") {
            let rest = &src[part.start + 4..part.end];
            let after = rest.iter().position(|b| !b.is_ascii_whitespace());
            match after.map(|p| (p, rest[p])) {
                Some((p, b'?')) => {
                    wobj = Some((trim(src, part.start + 4 + p + 1..part.end), true));
                }
                _ => {
                    if let Some(p) = rest.windows(2).position(|w| w == b":=") {
                        wobj = Some((trim(src, part.start + 4 + p + 2..part.end), false));
                    }
                }
            }
        }
    }
    Arg {
        optional,
        head: trim(src, r.start..head_end),
        wobj,
    }
}

fn trim(src: &[u8], r: Range<usize>) -> Range<usize> {
    let mut a = r.start;
    let mut b = r.end;
    while a < b && src[a].is_ascii_whitespace() {
        a += 1;
    }
    while b > a && src[b - 1].is_ascii_whitespace() {
        b -= 1;
    }
    a..b
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rewrite(text: &str) -> (String, MoveTally) {
        let program = crate::rapid::parse("t.mod", text.as_bytes()).unwrap();
        let (ins, tally) = move_insertions(&program, "RtWarm", &mut |_, _| Route::Slow);
        let mut out = text.as_bytes().to_vec();
        let places: Vec<(usize, &[u8])> = ins[0].iter().collect();
        for (at, t) in places.into_iter().rev() {
            out.splice(at..at, t.iter().copied());
        }
        (String::from_utf8(out).unwrap(), tally)
    }

    #[test]
    fn every_kind_of_move_is_wrapped_once() {
        let text = "MODULE M\n  PROC main()\n    MoveL p10, v100, z1, tGlue\\WObj:=wTable;\n    MoveJ \\Conc, Offs(pCam, x, y, 0), v1000, z50, tool0;\n    MoveC p1, p2, v100, z1, t1 \\WObj:=w1 \\TLoad:=l;\n    MoveAbsJ jHome\\NoEOffs, v1000, fine, tool0;\n    SearchL \\Stop, di1, pFound, pEnd, v100, tool0;\n    MoveL [[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;\n  ENDPROC\nENDMODULE\n";
        let (out, tally) = rewrite(text);
        for want in [
            "MoveL RtWarm(p10, tGlue \\WObj:=wTable), v100, z1, tGlue\\WObj:=wTable;",
            "MoveJ \\Conc, RtWarm(Offs(pCam, x, y, 0), tool0), v1000, z50, tool0;",
            "MoveC RtWarm(p1, t1 \\WObj:=w1), RtWarm(p2, t1 \\WObj:=w1), v100, z1, t1 \\WObj:=w1 \\TLoad:=l;",
            "MoveAbsJ RtWarmJ(jHome)\\NoEOffs, v1000, fine, tool0;",
            "SearchL \\Stop, di1, pFound, RtWarm(pEnd, tool0), v100, tool0;",
            "MoveL RtWarm([[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], tool0), v100, fine, tool0;",
        ] {
            assert!(out.contains(want), "{want}\nin\n{out}");
        }
        assert_eq!(tally.wrapped, 7);
        let (again, tally) = rewrite(&out);
        assert_eq!(again, out, "a second run changes nothing");
        assert_eq!((tally.wrapped, tally.already), (0, 7));
    }

    #[test]
    fn a_work_object_passed_on_is_passed_on_and_the_table_gives_its_row() {
        // Before: `\WObj?W` was dropped, the drift computed in wobj0.
        let text = "MODULE M\n  PROC glue(robtarget p \\wobjdata W)\n    MoveL p, v100, fine, tGun \\WObj?W;\n    MoveAbsJ jHome, v100, fine, tool0;\n  ENDPROC\nENDMODULE\n";
        let program = crate::rapid::parse("t.mod", text.as_bytes()).unwrap();
        let (ins, tally) = move_insertions(&program, "ThWarm", &mut |m, _| {
            if m.joints {
                Route::Table(3)
            } else {
                Route::Slow
            }
        });
        let mut out = text.as_bytes().to_vec();
        let places: Vec<(usize, &[u8])> = ins[0].iter().collect();
        for (at, t) in places.into_iter().rev() {
            out.splice(at..at, t.iter().copied());
        }
        let out = String::from_utf8(out).unwrap();
        assert!(
            out.contains("MoveL ThWarm(p, tGun \\WObj?W), v100, fine, tGun \\WObj?W;"),
            "{out}"
        );
        assert!(out.contains("MoveAbsJ ThWarmJT(jHome, 3), v100"), "{out}");
        assert_eq!((tally.wrapped, tally.table), (2, 1));
    }
}
