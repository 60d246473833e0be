//! Every robtarget of a program, numbered in file and source order,
//! whether it is held one by one or in a run of the fast lane's: a
//! target of a run is made when asked for, exactly as the grammar makes
//! it. The numbers are those of [`Expr::Target`](super::Expr::Target)
//! and every list of targets the library keeps.

use super::nocase::NoCase;
use super::runs::{blank_target, MoveRef, Runs};
use super::source::Source;
use super::values::{PoseNumbers, Target, TargetKind};
use std::borrow::Cow;
use std::cell::Cell;
use std::collections::HashMap;

thread_local! {
    /// The declared target after the one this thread's last lookup found
    /// ([`TargetIndex::get`]); `u32::MAX`: none.
    static NEXT: Cell<u32> = const { Cell::new(u32::MAX) };
}

#[cfg(test)]
thread_local! {
    /// How many lookups this thread answered by the guess.
    static GUESSED: Cell<usize> = const { Cell::new(0) };
}

/// An empty target, to be filled ([`Targets::fill`]).
pub fn blank() -> Target {
    blank_target()
}

/// Where a stretch of the targets' numbers is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Held {
    /// One by one, from this index of the program's own list.
    OneByOne(usize),
    /// In the move run of this number (its literals).
    Moves(usize),
    /// In the declaration run of this number.
    Decls(usize),
    /// In the array run of this number (its elements).
    Array(usize),
}

/// A stretch of the targets' numbers: from `start`, `len` of them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Segment {
    pub start: usize,
    pub len: usize,
    pub held: Held,
}

/// Every robtarget of a program, in file and source order (see
/// [`Program::targets`](super::Program::targets)).
#[derive(Clone, Copy)]
pub struct Targets<'p> {
    pub(crate) one_by_one: &'p [Target],
    pub(crate) runs: &'p Runs,
    pub(crate) segments: &'p [Segment],
    pub(crate) sources: &'p [Source],
}

impl<'p> Targets<'p> {
    fn src(&self, file: usize) -> &'p [u8] {
        self.sources.get(file).map_or(&[], Source::bytes)
    }

    pub fn len(&self) -> usize {
        match self.segments.last() {
            Some(s) => s.start + s.len,
            None => self.one_by_one.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Where target `i` is held, and its place in that holder.
    fn locate(&self, i: usize) -> Option<(Held, usize)> {
        if self.segments.is_empty() {
            return (i < self.one_by_one.len()).then_some((Held::OneByOne(0), i));
        }
        let s = self.segments.partition_point(|s| s.start <= i);
        let seg = self.segments.get(s.checked_sub(1)?)?;
        let k = i - seg.start;
        (k < seg.len).then_some((seg.held, k))
    }

    /// Target `i`, held one by one: borrowed.
    pub fn one_by_one(&self, i: usize) -> Option<&'p Target> {
        match self.locate(i)? {
            (Held::OneByOne(first), k) => self.one_by_one.get(first + k),
            _ => None,
        }
    }

    /// Target `i`: borrowed where it is held one by one, made where it is
    /// in a run.
    pub fn get(&self, i: usize) -> Option<Cow<'p, Target>> {
        if let Some(t) = self.one_by_one(i) {
            return Some(Cow::Borrowed(t));
        }
        let mut t = blank_target();
        self.fill(i, &mut t).then_some(Cow::Owned(t))
    }

    /// Target `i`, which the caller knows the program has.
    ///
    /// # Panics
    /// Where it has no target `i` (as indexing a list would).
    pub fn at(&self, i: usize) -> Cow<'p, Target> {
        match self.get(i) {
            Some(t) => t,
            None => panic!("target {i} of a program of {} targets", self.len()),
        }
    }

    /// Target `i` into `t` (its allocations reused: a loop over a million
    /// targets of a run makes no million targets); `false` where the
    /// program has none.
    pub fn fill(&self, i: usize, t: &mut Target) -> bool {
        let Some((held, k)) = self.locate(i) else {
            return false;
        };
        let runs: &Runs = self.runs;
        match held {
            Held::OneByOne(first) => match self.one_by_one.get(first + k) {
                Some(one) => {
                    t.clone_from(one);
                    true
                }
                None => false,
            },
            Held::Moves(r) => runs
                .moves
                .get(r)
                .is_some_and(|run| run.fill(runs, self.src(run.file), k, t)),
            Held::Decls(r) => runs
                .decls
                .get(r)
                .is_some_and(|run| run.fill(self.src(run.file), k, t)),
            Held::Array(r) => runs
                .arrays
                .get(r)
                .is_some_and(|run| run.fill(self.src(run.file), k, t)),
        }
    }

    /// The pose numbers of target `i` alone, read as [`Targets::fill`]
    /// reads them, where it makes the target with a value: all a pose is
    /// made of, without the identifier, place and names a target carries
    /// (a read of a million poses made a million of those) nor its
    /// external axes.
    pub fn pose(&self, i: usize) -> Option<PoseNumbers> {
        let (held, k) = self.locate(i)?;
        let runs: &Runs = self.runs;
        match held {
            Held::OneByOne(first) => self
                .one_by_one
                .get(first + k)?
                .value
                .as_ref()
                .map(PoseNumbers::from),
            Held::Moves(r) => {
                let run = runs.moves.get(r)?;
                run.pose(self.src(run.file), k)
            }
            Held::Decls(r) => {
                let run = runs.decls.get(r)?;
                run.pose(self.src(run.file), k)
            }
            Held::Array(r) => {
                let run = runs.arrays.get(r)?;
                run.pose(self.src(run.file), k)
            }
        }
    }

    /// The identifier of target `i` into `id`, and whether it has a value
    /// (a target of a run always has its literal's), without reading its
    /// numbers: a check of a million identifiers reads no million
    /// literals. `None` where the program has no target `i`.
    pub fn id_into(&self, i: usize, id: &mut String) -> Option<bool> {
        let (held, k) = self.locate(i)?;
        let runs: &Runs = self.runs;
        match held {
            Held::OneByOne(first) => {
                let one = self.one_by_one.get(first + k)?;
                id.clone_from(&one.id);
                Some(one.value.is_some())
            }
            Held::Moves(r) => {
                let run = runs.moves.get(r)?;
                (k < run.targets()).then(|| run.id_into(k, id))?;
                Some(true)
            }
            Held::Decls(r) => {
                let run = runs.decls.get(r)?;
                run.id_into(self.src(run.file), k, id).then_some(true)
            }
            Held::Array(r) => {
                let run = runs.arrays.get(r)?;
                (k < run.elements.len()).then(|| run.id_into(k, id))?;
                Some(true)
            }
        }
    }

    /// The targets held one by one, each with its number, in order.
    pub fn one_by_one_all(&self) -> impl Iterator<Item = (usize, &'p Target)> + 'p {
        let loose = self.one_by_one;
        let plain = self
            .segments
            .is_empty()
            .then(|| loose.iter().enumerate())
            .into_iter()
            .flatten();
        let held = self.segments.iter().flat_map(move |s| match s.held {
            Held::OneByOne(first) => {
                let end = (first + s.len).min(loose.len());
                let start = s.start;
                loose[first.min(end)..end]
                    .iter()
                    .enumerate()
                    .map(move |(k, t)| (start + k, t))
                    .collect::<Vec<_>>()
            }
            _ => Vec::new(),
        });
        plain.chain(held)
    }

    /// Every target, in order (those of runs made one at a time).
    pub fn iter(&self) -> impl Iterator<Item = Cow<'p, Target>> + 'p {
        let t = *self;
        (0..t.len()).filter_map(move |i| t.get(i))
    }

    /// Whether target `i` has numbers (a target of a run always has its
    /// literal's), without reading them.
    pub fn has_value(&self, i: usize) -> bool {
        match self.locate(i) {
            Some((Held::OneByOne(first), k)) => self
                .one_by_one
                .get(first + k)
                .is_some_and(|t| t.value.is_some()),
            Some(_) => true,
            None => false,
        }
    }

    /// Target `i`'s kind, without making it.
    pub fn kind(&self, i: usize) -> Option<TargetKind> {
        Some(match self.locate(i)? {
            (Held::OneByOne(first), k) => self.one_by_one.get(first + k)?.kind,
            (Held::Moves(_), _) => TargetKind::Inline,
            (Held::Decls(_), _) => TargetKind::Declared,
            (Held::Array(_), _) => TargetKind::ArrayElement,
        })
    }

    /// Target `i`'s file and byte offset, without making it.
    pub fn place(&self, i: usize) -> Option<(usize, usize)> {
        let runs = self.runs;
        Some(match self.locate(i)? {
            (Held::OneByOne(first), k) => {
                let t = self.one_by_one.get(first + k)?;
                (t.origin.file, t.origin.pos.offset)
            }
            (Held::Moves(r), k) => {
                let run = runs.moves.get(r)?;
                let (m, j) = run.move_of(k);
                let item = run.items.get(m)?;
                (run.file, item.at as usize + usize::from(item.parts[j]))
            }
            (Held::Decls(r), k) => {
                let run = runs.decls.get(r)?;
                let item = run.items.get(k)?;
                (run.file, item.at as usize + usize::from(item.literal))
            }
            (Held::Array(r), k) => {
                let run = runs.arrays.get(r)?;
                (run.file, *run.elements.get(k)? as usize)
            }
        })
    }

    /// How many targets are held in runs (the fast lane's work).
    pub fn in_runs(&self) -> usize {
        self.len() - self.one_by_one.len()
    }

    /// The move whose literal target `i` is, where a run of moves holds
    /// it.
    pub fn move_of(&self, i: usize) -> Option<MoveRef<'p>> {
        match self.locate(i)? {
            (Held::Moves(r), k) => {
                let run = self.runs.moves.get(r)?;
                let (m, _) = run.move_of(k);
                Some(MoveRef::new(self.runs, self.sources, run, m))
            }
            _ => None,
        }
    }

    /// The stretches of targets that are literals of runs of moves.
    pub fn move_literals(&self) -> impl Iterator<Item = std::ops::Range<usize>> + 'p {
        self.segments
            .iter()
            .filter(|s| matches!(s.held, Held::Moves(_)) && s.len > 0)
            .map(|s| s.start..s.start + s.len)
    }

    /// How many of the targets held in runs are literals of moves.
    pub fn moves_in_runs(&self) -> usize {
        self.segments
            .iter()
            .filter(|s| matches!(s.held, Held::Moves(_)))
            .map(|s| s.len)
            .sum()
    }
}

impl<'p> IntoIterator for Targets<'p> {
    type Item = Cow<'p, Target>;
    type IntoIter = Box<dyn Iterator<Item = Cow<'p, Target>> + 'p>;
    fn into_iter(self) -> Self::IntoIter {
        Box::new(self.iter())
    }
}

/// The program's targets by identifier (compared without regard to
/// case): those held one by one that `keep` keeps, every declared target
/// and array element of the runs; built once for many lookups.
pub struct TargetIndex<'p> {
    one_by_one: HashMap<String, usize>,
    /// The declared targets of runs, by number alone: the name is read
    /// from the run where a lookup compares it. Four programs' worth of
    /// these tables are alive at once in a correction, and a map holding
    /// each name borrowed took 25 bytes a target where this takes 5.
    declared: hashbrown::HashTable<u32>,
    /// Declared targets of runs whose name another of the table's has
    /// too: the table answers the first, so a guess may not.
    shadowed: std::collections::HashSet<u32>,
    targets: Targets<'p>,
    qualified: HashMap<String, usize>,
    /// Array runs by their identifiers' prefix, lower case.
    arrays: HashMap<String, (usize, usize)>,
    /// Whether some identifier carries its routine (`r1/pA`): only then
    /// is a routine-scoped key worth building for a lookup.
    scoped: bool,
    /// Whether some identifier carries its module (`M:p10`).
    module_keyed: bool,
}

impl<'p> TargetIndex<'p> {
    /// The targets of `targets` by identifier; see [`TargetIndex`].
    pub(crate) fn new(targets: Targets<'p>, keep: impl Fn(&Target) -> bool) -> TargetIndex<'p> {
        let mut one_by_one = HashMap::new();
        for (i, t) in targets.one_by_one.iter().enumerate() {
            if keep(t) {
                let global = targets.global_of_one_by_one(i);
                one_by_one
                    .entry(t.id.to_ascii_lowercase())
                    .or_insert(global);
            }
        }
        let mut declared = hashbrown::HashTable::new();
        // Room for all at once: growing a table of a million by doubling
        // holds the old and the new one together.
        declared.reserve(
            targets.runs.decls.iter().map(|r| r.items.len()).sum(),
            |&i: &u32| targets.name_hash(i as usize),
        );
        let mut qualified = HashMap::new();
        for run in &targets.runs.decls {
            let src = targets.src(run.file);
            for (k, item) in run.items.iter().enumerate().filter(|(_, i)| i.qualified) {
                if let Some(name) = run.name_of(src, item) {
                    qualified
                        .entry(super::build::qualified(&run.module, name).to_ascii_lowercase())
                        .or_insert(run.base + k);
                }
            }
        }
        // The names hashed on every core, then entered in order (the first
        // of two alike stays): a million names read and hashed on one core
        // were most of the table's build.
        let hashed: Vec<Vec<(u64, u32)>> = {
            use rayon::prelude::*;
            targets
                .runs
                .decls
                .par_iter()
                .map(|run| {
                    let src = targets.src(run.file);
                    run.items
                        .par_iter()
                        .enumerate()
                        .filter(|(_, item)| !item.qualified)
                        .filter_map(|(k, item)| {
                            let name = run.name_of(src, item)?;
                            // Targets are numbered below 2^32: the lane's
                            // offsets are 32-bit, so no run holds more.
                            let number = u32::try_from(run.base + k).ok()?;
                            Some((name_hash(name.as_bytes()), number))
                        })
                        .collect()
                })
                .collect()
        };
        let mut shadowed = std::collections::HashSet::new();
        for &(hash, number) in hashed.iter().flatten() {
            // The name read again only where a tag matches.
            let same = |&j: &u32| {
                (targets.declared_name(number as usize))
                    .is_some_and(|n| targets.same_name(j as usize, n))
            };
            match declared.find(hash, same) {
                Some(&first) => {
                    shadowed.insert(first);
                    shadowed.insert(number);
                }
                None => {
                    declared.insert_unique(hash, number, |&j: &u32| targets.name_hash(j as usize));
                }
            }
        }
        let arrays = targets
            .runs
            .arrays
            .iter()
            .map(|a| (a.prefix.to_ascii_lowercase(), (a.base, a.elements.len())))
            .collect::<HashMap<_, _>>();
        let scoped = one_by_one
            .keys()
            .chain(arrays.keys())
            .any(|k| k.contains('/'));
        let module_keyed = !qualified.is_empty()
            || one_by_one
                .keys()
                .chain(arrays.keys())
                .any(|k| k.contains(':'));
        TargetIndex {
            one_by_one,
            declared,
            shadowed,
            targets,
            qualified,
            arrays,
            scoped,
            module_keyed,
        }
    }
}

/// The hash of a name as RAPID compares names (without regard to case).
pub(crate) fn name_hash(name: &[u8]) -> u64 {
    use std::hash::BuildHasher;
    foldhash::fast::FixedState::default().hash_one(NoCase(name))
}

impl Targets<'_> {
    /// The name of declared target `i` of a run, as written.
    fn declared_name(&self, i: usize) -> Option<&[u8]> {
        match self.locate(i)? {
            (Held::Decls(r), k) => {
                let run = self.runs.decls.get(r)?;
                let item = run.items.get(k)?;
                run.name_of(self.src(run.file), item).map(str::as_bytes)
            }
            _ => None,
        }
    }

    fn name_hash(&self, i: usize) -> u64 {
        name_hash(self.declared_name(i).unwrap_or_default())
    }

    /// Whether declared target `i` of a run is named `name`, as RAPID
    /// compares names.
    fn same_name(&self, i: usize, name: &[u8]) -> bool {
        self.declared_name(i)
            .is_some_and(|n| n.eq_ignore_ascii_case(name))
    }

    /// The number of the target held one by one at `i` of the program's
    /// own list.
    pub(crate) fn global_of_one_by_one(&self, i: usize) -> usize {
        if self.segments.is_empty() {
            return i;
        }
        self.segments
            .iter()
            .find_map(|s| match s.held {
                Held::OneByOne(first) if (first..first + s.len).contains(&i) => {
                    Some(s.start + i - first)
                }
                _ => None,
            })
            .unwrap_or(i)
    }
}

impl TargetIndex<'_> {
    /// The target with identifier `id`.
    pub fn get(&self, id: &str) -> Option<usize> {
        // The target after the one this thread found last, asked first: a
        // RobotStudio export moves to its targets in the order it declares
        // them, and the table's answer is a cache miss or two (most of
        // looking a million names up). Taken only where the table would
        // give it: a declared target of a run whose name no other has.
        let guess = NEXT.with(Cell::get);
        if guess != u32::MAX && self.declared_alone(guess, id.as_bytes()) {
            NEXT.with(|n| n.set(guess.wrapping_add(1)));
            #[cfg(test)]
            GUESSED.with(|g| g.set(g.get() + 1));
            return Some(guess as usize);
        }
        let same = |&j: &u32| self.targets.same_name(j as usize, id.as_bytes());
        if let Some(&i) = self.declared.find(name_hash(id.as_bytes()), same) {
            NEXT.with(|n| n.set(i.wrapping_add(1)));
            return Some(i as usize);
        }
        let lower = id.to_ascii_lowercase();
        if let Some(&i) = self.one_by_one.get(&lower) {
            return Some(i);
        }
        if let Some(&i) = self.qualified.get(&lower) {
            return Some(i);
        }
        // An element of an array run: `name{k}`.
        let (prefix, rest) = lower.split_once('{')?;
        let k: usize = rest.strip_suffix('}')?.parse().ok()?;
        let &(base, len) = self.arrays.get(prefix)?;
        (1..=len).contains(&k).then_some(base + k - 1)
    }

    /// Whether target `i` is a declared target of a run in the table,
    /// named `name`, whose name no other target of the table has: what
    /// the table answers for `name`.
    fn declared_alone(&self, i: u32, name: &[u8]) -> bool {
        let Some((Held::Decls(r), k)) = self.targets.locate(i as usize) else {
            return false;
        };
        let Some(run) = self.targets.runs.decls.get(r) else {
            return false;
        };
        run.items.get(k).is_some_and(|item| {
            !item.qualified
                && run
                    .name_of(self.targets.src(run.file), item)
                    .is_some_and(|n| n.as_bytes().eq_ignore_ascii_case(name))
                && !self.shadowed.contains(&i)
        })
    }

    /// Whether some identifier is scoped to its routine (`r1/pA`, where a
    /// routine's data shadows a name declared elsewhere too). Lookups skip
    /// the routine-scoped keys where none is: most programs, and every
    /// move by name pays for them otherwise.
    pub fn has_routine_scoped(&self) -> bool {
        self.scoped
    }

    /// Whether some identifier is qualified by its module (`M:p10`).
    pub fn has_qualified(&self) -> bool {
        self.module_keyed
    }

    /// The targets of the array run whose identifiers start `prefix{`
    /// (lower case), where one is: the first's number and how many.
    pub fn array(&self, prefix: &str) -> Option<(usize, usize)> {
        self.arrays.get(&prefix.to_ascii_lowercase()).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each name looked up in order (the guess taken), in reverse (the
    /// table asked), and with the guess pointing at a declaration the
    /// table does not hold (a LOCAL one another module declares too,
    /// known by its module):
    /// the same answers as the table's alone.
    #[test]
    fn the_next_target_guessed_gives_the_tables_answer() {
        let decl = |local: &str, name: String| {
            format!("  {local}CONST robtarget {name}:=[[1,2,3],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n")
        };
        let mut src = String::from("MODULE A\n");
        (0..200).for_each(|k| src.push_str(&decl("", format!("a{k}"))));
        (0..200).for_each(|k| src.push_str(&decl("LOCAL ", format!("T{k}"))));
        src.push_str("ENDMODULE\nMODULE B\n");
        src.push_str(&decl("", "u0".to_string()));
        (0..200).for_each(|k| src.push_str(&decl("LOCAL ", format!("T{k}"))));
        src.push_str("ENDMODULE\n");
        let p = crate::rapid::parse::parse("m.mod", src.as_bytes()).unwrap();
        let index = p.target_index(|_| true);
        let names: Vec<String> = (0..200)
            .map(|k| format!("a{k}"))
            .chain(["u0".to_string(), "t0".to_string(), "B:T0".to_string()])
            .collect();
        // The table alone: no guess before each lookup.
        let alone: Vec<Option<usize>> = names
            .iter()
            .map(|n| {
                NEXT.with(|x| x.set(u32::MAX));
                index.get(n)
            })
            .collect();
        assert!(alone[..201].iter().all(Option::is_some));
        GUESSED.with(|g| g.set(0));
        let in_order: Vec<Option<usize>> = names.iter().map(|n| index.get(n)).collect();
        assert_eq!(in_order, alone);
        // a1..a199 at least were guessed.
        assert!(GUESSED.with(Cell::get) >= 199);
        let reversed: Vec<Option<usize>> = names.iter().rev().map(|n| index.get(n)).collect();
        assert_eq!(reversed.into_iter().rev().collect::<Vec<_>>(), alone);
        // After u0 the guess is B's LOCAL T0, which the table does not
        // hold (A has a T0 too): it is not taken for `t0`.
        index.get("u0");
        assert_eq!(index.get("t0"), alone[201]);
    }
}
