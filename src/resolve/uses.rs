//! The moves that reach each target, held compactly: a program of a
//! million declared targets has a million moves by name, one use each,
//! and an array walked by a FOR loop a million elements reached by one
//! move. Each move is a [`Site`] (its tool, work object, instruction and
//! routine interned as numbers); a target's uses are the sites of its own
//! entries, merged with those reaching a whole stretch of targets (an
//! array's elements through `arr{i}`), in program order. A [`Usage`] is
//! made of a site when a caller asks for one.
//!
//! A literal of a run of moves (`MoveL [[...]], ...` the fast lane read)
//! has no entry: its own move is its one use, read from the run when
//! asked for.

use super::usage::{Through, Usage};
use crate::rapid::Targets;
use std::collections::HashMap;
use std::ops::Range;
use std::sync::Arc;

/// Where a move is and what it moves with: 32 bytes, since a program of
/// a million moves by name holds a million of them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Site {
    pub through: Packed,
    /// Tool and work object as written (into [`Uses::names`]); `NONE`:
    /// the move names none.
    pub tool: u32,
    pub wobj: u32,
    pub instruction: u32,
    pub routine: u32,
    pub line: u32,
    pub file: u32,
    /// Where the move's statement starts ([`offset32`]).
    pub offset: u32,
}

/// A [`Through`] in four bytes: a derived expression's target number,
/// or one of the two values above every number a program can have.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Packed(u32);

const DIRECT: u32 = u32::MAX;
const VARIABLE: u32 = u32::MAX - 1;

impl From<Through> for Packed {
    fn from(t: Through) -> Packed {
        Packed(match t {
            Through::Direct => DIRECT,
            Through::Variable => VARIABLE,
            // Targets are numbered below 2^32 - 2: each has a statement
            // of its own in a file the lane addresses with 32-bit offsets.
            Through::Derived(i) => u32::try_from(i).unwrap_or(VARIABLE - 1).min(VARIABLE - 1),
        })
    }
}

impl From<Packed> for Through {
    fn from(p: Packed) -> Through {
        match p.0 {
            DIRECT => Through::Direct,
            VARIABLE => Through::Variable,
            i => Through::Derived(i as usize),
        }
    }
}

/// A statement's byte offset in 32 bits: the lane's runs address files
/// so, and a RAPID file of 4 GB is beyond what the controller loads.
pub(crate) fn offset32(offset: usize) -> u32 {
    u32::try_from(offset).unwrap_or(u32::MAX)
}

/// No name.
const NONE: u32 = u32::MAX;

/// Every target's uses; see the module doc.
#[derive(Clone, Default)]
pub struct Uses<'p> {
    names: Vec<Arc<str>>,
    sites: Vec<Site>,
    /// (target, site), by target, each target's in program order (the
    /// target's number in 32 bits, as [`Packed`] holds it).
    pairs: Vec<(u32, u32)>,
    /// Where each target's entries start in `pairs` (the next target's
    /// start ends them): a target's uses are found in constant time, where
    /// two binary searches of a million pairs showed for every target.
    starts: Vec<u32>,
    /// Sites reaching every target of a stretch, in program order.
    spans: Vec<(Range<usize>, u32)>,
    /// The program's targets, for the literals of its runs of moves.
    lane: Option<Targets<'p>>,
}

/// Makes [`Uses`]: sites interned, entries gathered, then ordered.
#[derive(Default)]
pub(crate) struct UsesBuilder<'p> {
    uses: Uses<'p>,
    /// Hashed fast: each of a million moves numbers its tool and work
    /// object here.
    by_name: foldhash::HashMap<Arc<str>, u32>,
}

impl<'p> UsesBuilder<'p> {
    /// The uses of `targets`' literals of runs of moves are their moves.
    pub fn new(targets: Targets<'p>) -> Self {
        let mut b = UsesBuilder::default();
        b.uses.lane = Some(targets);
        b
    }

    /// The number of `name`.
    pub fn name(&mut self, name: Option<&str>) -> u32 {
        let Some(name) = name else { return NONE };
        if let Some(&id) = self.by_name.get(name) {
            return id;
        }
        let id = self.uses.names.len() as u32;
        let a: Arc<str> = Arc::from(name);
        self.uses.names.push(a.clone());
        self.by_name.insert(a, id);
        id
    }

    /// A site; its number.
    pub fn site(&mut self, site: Site) -> u32 {
        // Consecutive entries of one move share its site.
        if let Some(last) = self.uses.sites.last() {
            if *last == site {
                return self.uses.sites.len() as u32 - 1;
            }
        }
        self.uses.sites.push(site);
        self.uses.sites.len() as u32 - 1
    }

    /// Target `target` reached at site `site`.
    pub fn reach(&mut self, target: usize, site: u32) {
        // Numbered below 2^32 as [`Packed`] says.
        self.uses
            .pairs
            .push((u32::try_from(target).unwrap_or(u32::MAX), site));
    }

    /// Every target of `targets` reached at site `site`.
    pub fn reach_all(&mut self, targets: Range<usize>, site: u32) {
        self.uses.spans.push((targets, site));
    }

    pub fn finish(mut self) -> Uses<'p> {
        // By target, each in program order (the sites were made so); a use
        // made twice (one move reaching a target twice) kept once.
        let sites = &self.uses.sites;
        self.uses.pairs.sort_by_key(|&(t, s)| (t, s));
        self.uses
            .pairs
            .dedup_by(|a, b| a.0 == b.0 && sites[a.1 as usize] == sites[b.1 as usize]);
        let pairs = &self.uses.pairs;
        let targets = pairs.last().map_or(0, |p| p.0 as usize + 1);
        let mut starts = Vec::with_capacity(targets + 1);
        let mut k = 0;
        for t in 0..=targets {
            while k < pairs.len() && (pairs[k].0 as usize) < t {
                k += 1;
            }
            starts.push(k as u32);
        }
        self.uses.starts = starts;
        self.uses
    }
}

/// One use of a target: a move, with what it moves.
#[derive(Clone, Copy)]
pub struct UseRef<'u> {
    through: Through,
    tool: Option<&'u str>,
    wobj: Option<&'u str>,
    instruction: &'u str,
    routine: &'u str,
    line: u32,
    file: usize,
    offset: usize,
}

impl<'u> UseRef<'u> {
    pub fn through(&self) -> Through {
        self.through
    }
    /// The tool as written; `None` where the move names none.
    pub fn tool(&self) -> Option<&'u str> {
        self.tool
    }
    pub fn wobj(&self) -> Option<&'u str> {
        self.wobj
    }
    /// The tool's name as written (`tool0` where the move names none).
    pub fn tool_name(&self) -> &'u str {
        self.tool().unwrap_or("tool0")
    }
    pub fn wobj_name(&self) -> &'u str {
        self.wobj().unwrap_or("wobj0")
    }
    pub fn file(&self) -> usize {
        self.file
    }
    /// The move instruction's name as written (`MoveL`).
    pub fn instruction(&self) -> &'u str {
        self.instruction
    }
    /// The routine the move is in.
    pub fn routine(&self) -> &'u str {
        self.routine
    }
    /// The move's line.
    pub fn line(&self) -> u32 {
        self.line
    }
    /// Where the move's statement starts.
    pub fn offset(&self) -> usize {
        self.offset
    }
    /// Whether two uses move with the same tool and work object (by name,
    /// as RAPID compares names: case-insensitively).
    pub fn same_frames(&self, other: &UseRef) -> bool {
        self.tool_name().eq_ignore_ascii_case(other.tool_name())
            && self.wobj_name().eq_ignore_ascii_case(other.wobj_name())
    }
    /// The use as a [`Usage`].
    pub fn to_usage(&self) -> Usage {
        Usage {
            through: self.through,
            tool: self.tool.map(str::to_string),
            wobj: self.wobj.map(str::to_string),
            instruction: self.instruction.to_string(),
            routine: self.routine.to_string(),
            line: self.line,
            file: self.file,
            offset: self.offset,
        }
    }
}

impl<'p> Uses<'p> {
    fn name(&self, id: u32) -> Option<&str> {
        (id != NONE).then(|| &*self.names[id as usize])
    }

    fn at(&self, site: u32) -> UseRef<'_> {
        let s = &self.sites[site as usize];
        UseRef {
            through: Through::from(s.through),
            tool: self.name(s.tool),
            wobj: self.name(s.wobj),
            instruction: self.name(s.instruction).unwrap_or(""),
            routine: self.name(s.routine).unwrap_or(""),
            line: s.line,
            file: s.file as usize,
            offset: s.offset as usize,
        }
    }

    /// The move of target `i`, where it is a literal of a run of moves.
    fn own_move(&self, i: usize) -> Option<UseRef<'p>> {
        let m = self.lane?.move_of(i)?;
        Some(UseRef {
            through: Through::Direct,
            tool: m.tool().map(|t| &**t),
            wobj: m.wobj().map(|w| &**w),
            instruction: m.instruction(),
            routine: m.routine(),
            line: m.line(),
            file: m.file(),
            offset: m.offset(),
        })
    }

    /// The sites of target `i`, in program order.
    fn sites_of(&self, i: usize) -> impl Iterator<Item = u32> + '_ {
        let own = match (self.starts.get(i), self.starts.get(i + 1)) {
            (Some(&lo), Some(&hi)) => &self.pairs[lo as usize..hi as usize],
            _ => &[][..],
        }
        .iter()
        .map(|p| p.1);
        let spans = self
            .spans
            .iter()
            .filter(move |(r, _)| r.contains(&i))
            .map(|s| s.1);
        Merged {
            a: own.peekable(),
            b: spans.peekable(),
        }
    }

    /// The uses of target `i`, in program order.
    pub fn of(&self, i: usize) -> impl Iterator<Item = UseRef<'_>> + '_ {
        self.own_move(i)
            .into_iter()
            .chain(self.sites_of(i).map(move |s| self.at(s)))
    }

    /// Its first use in program order: the one a target is corrected for.
    pub fn first(&self, i: usize) -> Option<UseRef<'_>> {
        self.of(i).next()
    }

    /// Whether any move reaches target `i`.
    pub fn contains(&self, i: usize) -> bool {
        self.first(i).is_some()
    }

    /// The uses of target `i` as [`Usage`]s (none: an empty list).
    pub fn usages(&self, i: usize) -> Vec<Usage> {
        self.of(i).map(|u| u.to_usage()).collect()
    }

    /// Whether some use of target `i` moves with another tool or work
    /// object than its first.
    pub fn several_frames(&self, i: usize) -> bool {
        let mut all = self.of(i);
        let Some(first) = all.next() else {
            return false;
        };
        all.any(|u| !u.same_frames(&first))
    }

    /// The targets some use of which moves with another tool or work
    /// object than their first ([`Uses::several_frames`]), in order:
    /// asked on every core, as a program of a million targets asks a
    /// million times.
    pub fn of_several_frames(&self) -> Vec<usize> {
        use rayon::prelude::*;
        self.targets()
            .into_par_iter()
            .filter(|&i| self.several_frames(i))
            .collect()
    }

    /// The targets with an entry of their own or in a stretch, in order
    /// (each once).
    pub fn targets(&self) -> Vec<usize> {
        let mut out: Vec<usize> = self.pairs.iter().map(|p| p.0 as usize).collect();
        for (r, _) in &self.spans {
            out.extend(r.clone());
        }
        for r in self.lane.iter().flat_map(|t| t.move_literals()) {
            out.extend(r);
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Every target's uses as [`Usage`]s, by target: the form callers that
    /// walk few targets take.
    pub fn to_map(&self) -> HashMap<usize, Vec<Usage>> {
        self.targets()
            .into_iter()
            .map(|i| (i, self.usages(i)))
            .collect()
    }
}

/// Two ascending sequences of sites merged in order.
struct Merged<A: Iterator<Item = u32>, B: Iterator<Item = u32>> {
    a: std::iter::Peekable<A>,
    b: std::iter::Peekable<B>,
}

impl<A: Iterator<Item = u32>, B: Iterator<Item = u32>> Iterator for Merged<A, B> {
    type Item = u32;
    fn next(&mut self) -> Option<u32> {
        match (self.a.peek(), self.b.peek()) {
            (Some(&x), Some(&y)) if y < x => self.b.next(),
            (Some(_), _) => self.a.next(),
            (None, _) => self.b.next(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_name_keeps_its_number_however_often_it_comes_back() {
        let mut b = UsesBuilder::default();
        // Names as moves give them: tool and work object in turn, then
        // others, then the first again past the two kept last.
        let names = [
            "tProbe", "wPart", "tProbe", "wPart", "tGrip", "wTable", "tProbe", "tprobe", "wPart",
        ];
        let ids: Vec<u32> = names.iter().map(|n| b.name(Some(n))).collect();
        assert_eq!(ids, [0, 1, 0, 1, 2, 3, 0, 4, 1]);
        let held: Vec<&str> = b.uses.names.iter().map(|n| &**n).collect();
        assert_eq!(held, ["tProbe", "wPart", "tGrip", "wTable", "tprobe"]);
        assert_eq!(b.name(None), NONE);
    }
}
