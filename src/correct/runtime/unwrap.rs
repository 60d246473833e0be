//! The cold original of a program `correct --runtime` rewrote: each
//! move's call of the module taken off its target argument, and
//! rapidtherm's own lines (the marker, the seal) taken out. The rewrite
//! only inserted text, so this gives the file back byte for byte; the
//! marker's fingerprint of the cold file proves it, and a file edited
//! since (a target touched up on the pendant, a move added) is said, not
//! guessed at.

use super::rewrite::{arguments, Funcs};
use crate::correct::marker;
use crate::error::{Error, Result};
use crate::rapid::Program;
use crate::resolve::each_move_instruction;
use std::ops::Range;

/// Each file of `program` (rewritten for the module `module`) as it was
/// before the rewrite; a file without rapidtherm's lines as it is.
pub fn cold_original(program: &Program, module: &str) -> Result<Vec<Vec<u8>>> {
    let funcs = Funcs::new(module);
    let mut cuts: Vec<Vec<Range<usize>>> = vec![Vec::new(); program.files.len()];
    each_move_instruction(program, &mut |m| {
        let src = program.source(m.file);
        let Some(args) = arguments(src, m.offset) else {
            return;
        };
        for a in args.iter().filter(|a| !a.optional) {
            let written = &src[a.head.clone()];
            let text: String = written.iter().map(|&b| b as char).collect();
            if !funcs.wraps(&text) {
                continue;
            }
            if let Some(inner) = first_argument(src, a.head.clone()) {
                cuts[m.file].push(a.head.start..inner.start);
                cuts[m.file].push(inner.end..a.head.end);
            }
        }
    });
    let mut out = Vec::with_capacity(program.files.len());
    for (f, mut cut) in cuts.into_iter().enumerate() {
        let src = program.source(f);
        cut.extend(marker::own_line_spans(src));
        cut.sort_by_key(|r| r.start);
        let mut cold = Vec::with_capacity(src.len());
        let mut from = 0;
        for r in cut {
            if r.start >= from {
                cold.extend_from_slice(&src[from..r.start]);
                from = r.end;
            }
        }
        cold.extend_from_slice(&src[from.min(src.len())..]);
        if let Some(recorded) = marker::cold_fingerprint(src) {
            let now = marker::fingerprint(&cold);
            if now != recorded {
                return Err(Error::input(format!(
                    "{}: edited since the --runtime rewrite (its cold original's fingerprint was {recorded}, taking the calls off gives {now}): a target touched up or a move changed; its cold original cannot be given back exactly",
                    program.file_name(f)
                )));
            }
        }
        out.push(cold);
    }
    Ok(out)
}

/// The first argument of the call written at `call` (`Name(arg, ...)`):
/// up to its first comma or closing parenthesis outside brackets and
/// strings.
fn first_argument(src: &[u8], call: Range<usize>) -> Option<Range<usize>> {
    let open = call.start + src[call.clone()].iter().position(|&b| b == b'(')? + 1;
    let (mut depth, mut in_str) = (0i32, false);
    for (i, &b) in src.iter().enumerate().take(call.end).skip(open) {
        match b {
            b'"' => in_str = !in_str,
            _ if in_str => {}
            b'(' | b'[' | b'{' => depth += 1,
            b')' | b']' | b'}' if depth > 0 => depth -= 1,
            b',' | b')' if depth == 0 => return Some(open..i),
            _ => {}
        }
    }
    None
}
