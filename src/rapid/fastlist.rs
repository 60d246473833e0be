//! The robtargets of a file read as a [`Skeleton`], as the whole parse of
//! the file lists them: the skeleton's own targets and the literals of
//! the cut moves, in file order, each with its identifier, place,
//! routine, instruction, tool and work object.
//!
//! Two things differ between the skeleton's parse and the whole file's.
//! The literals of a routine are numbered together (`main#3`), so the
//! skeleton's are numbered again with the cut ones counted; and an
//! identifier gets its module (`M1:main#3`) where the whole file has its
//! name space in two modules, which the cut literals can make so. Where
//! this cannot be worked out for sure, [`Listing::new`] declines and the
//! whole parse lists the file.

use super::fastmove::Skeleton;
use super::parse::{column, line_starts, name_space, qualified};
use super::{Origin, Pos, Program, Target, TargetKind};
use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;
use std::sync::Arc;

/// One place of the file's list of targets, in file order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Entry {
    /// The skeleton's target of this index ([`Listing::kept`]).
    Kept(usize),
    /// The literals of the cut move of this index ([`CutReader::read`]).
    Cut(usize),
}

/// A routine, as its literals are numbered: by module and name, without
/// regard to case (two routines of one name in one module count on).
struct Place {
    module: Arc<str>,
    routine: Arc<str>,
    /// `Module:` where the file's identifiers of this routine's name
    /// space are qualified, else empty.
    prefix: String,
}

/// The file's targets; see the module doc.
pub struct Listing<'a> {
    skeleton: &'a Skeleton,
    src: &'a [u8],
    kept: Vec<Target>,
    entries: Vec<Entry>,
    /// Per cut move: its routine (into `places`) and the number of its
    /// first literal in that routine.
    cuts: Vec<(u32, u32)>,
    places: Vec<Place>,
    /// Where the skeleton's lines start (the file's lines: cuts are
    /// within lines).
    lines: Vec<usize>,
}

impl<'a> Listing<'a> {
    /// The listing of `src`, read as `skeleton` whose kept bytes parsed as
    /// `program`; `None` where it could differ from the whole parse's.
    pub fn new(program: &Program, skeleton: &'a Skeleton, src: &'a [u8]) -> Option<Listing<'a>> {
        if program.files.len() != 1
            || skeleton.literals.len() != skeleton.cuts.len()
            || skeleton.cuts_before_declarations(program)
        {
            return None;
        }
        // Every routine by where it starts in the file, and its place.
        let mut places: Vec<Place> = Vec::new();
        let mut place_of: HashMap<(String, String), u32> = HashMap::new();
        let mut routines: Vec<(usize, u32)> = Vec::new();
        for m in &program.modules {
            for r in &m.routines {
                let key = (m.name.to_lowercase(), r.name.to_lowercase());
                let p = *place_of.entry(key).or_insert_with(|| {
                    places.push(Place {
                        module: m.name.clone(),
                        routine: r.name.clone(),
                        prefix: String::new(),
                    });
                    places.len() as u32 - 1
                });
                routines.push((skeleton.file_offset(r.pos.offset), p));
            }
        }
        if !routines.is_sorted_by_key(|r| r.0) {
            return None;
        }
        let kept: Vec<Target> = program.targets().to_vec();
        // The skeleton's identifiers as they would be unqualified.
        let plain: Vec<&str> = kept
            .iter()
            .map(|t| {
                let m = &*t.origin.module;
                match t.id.split_once(':') {
                    Some((q, rest)) if q == m => rest,
                    _ => t.id.as_str(),
                }
            })
            .collect();
        let mut count = vec![0u32; places.len()];
        let mut cuts = Vec::with_capacity(skeleton.cuts.len());
        let mut entries = Vec::with_capacity(kept.len() + skeleton.cuts.len());
        let mut renumbered: Vec<Option<String>> = vec![None; kept.len()];
        let mut with_cuts = vec![false; places.len()];
        let mut skeleton_count = vec![0u32; places.len()];
        let (mut i, mut k) = (0, 0);
        while i < kept.len() || k < skeleton.cuts.len() {
            let kept_at = kept
                .get(i)
                .map(|t| skeleton.file_offset(t.origin.pos.offset));
            let cut_at = skeleton.cuts.get(k).map(|c| c.start);
            if kept_at.is_some_and(|a| cut_at.is_none_or(|c| a < c)) {
                let t = &kept[i];
                if let Some((routine, n)) = plain[i].split_once('#') {
                    let inline = matches!(t.kind, TargetKind::Inline | TargetKind::Assigned);
                    let r = t.origin.routine.as_deref()?;
                    let key = (t.origin.module.to_lowercase(), r.to_lowercase());
                    let p = *place_of.get(&key)? as usize;
                    skeleton_count[p] += 1;
                    count[p] += 1;
                    // The skeleton counted its own literals just so.
                    if !inline || routine != r || n.parse::<u32>().ok()? != skeleton_count[p] {
                        return None;
                    }
                    renumbered[i] = Some(format!("{r}#{}", count[p]));
                }
                entries.push(Entry::Kept(i));
                i += 1;
            } else {
                let at = cut_at?;
                let r = routines.partition_point(|r| r.0 <= at).checked_sub(1)?;
                let p = routines[r].1;
                cuts.push((p, count[p as usize] + 1));
                count[p as usize] += u32::from(skeleton.literals[k]);
                with_cuts[p as usize] = true;
                entries.push(Entry::Cut(k));
                k += 1;
            }
        }
        // Name spaces and the modules they occur in, in the whole file.
        let ids: Vec<&str> = plain
            .iter()
            .zip(&renumbered)
            .map(|(p, r)| r.as_deref().unwrap_or(p))
            .collect();
        let mut modules_of: HashMap<String, HashSet<String>> = HashMap::new();
        for (t, id) in kept.iter().zip(&ids) {
            modules_of
                .entry(name_space(id))
                .or_default()
                .insert(t.origin.module.to_lowercase());
        }
        for (p, _) in places.iter().zip(&with_cuts).filter(|(_, c)| **c) {
            modules_of
                .entry(name_space(&format!("{}#1", p.routine)))
                .or_default()
                .insert(p.module.to_lowercase());
        }
        let in_two = |id: &str| modules_of.get(&name_space(id)).is_some_and(|s| s.len() > 1);
        let kept: Vec<Target> = kept
            .iter()
            .zip(&ids)
            .map(|(t, id)| Target {
                id: if in_two(id) {
                    qualified(&t.origin.module, id)
                } else {
                    id.to_string()
                },
                ..t.clone()
            })
            .collect();
        for p in &mut places {
            if in_two(&format!("{}#1", p.routine)) {
                p.prefix = qualified(&p.module, "");
            }
        }
        Some(Listing {
            skeleton,
            src,
            kept,
            entries,
            cuts,
            places,
            lines: line_starts(&skeleton.bytes),
        })
    }

    /// Every target of the file, in file order.
    pub fn entries(&self) -> &[Entry] {
        &self.entries
    }

    /// The skeleton's target `i` with its identifier in the whole file.
    pub fn kept(&self, i: usize) -> &Target {
        &self.kept[i]
    }

    /// A reader of cut moves (one per thread: it reuses its target).
    pub fn reader(&self) -> CutReader<'_, 'a> {
        let none: Arc<str> = Arc::from("");
        CutReader {
            listing: self,
            target: Target {
                id: String::new(),
                kind: TargetKind::Inline,
                origin: Origin {
                    file: 0,
                    module: none.clone(),
                    routine: Some(none.clone()),
                    pos: Pos::default(),
                },
                name: None,
                storage: None,
                value: None,
                instruction: Some(none.clone()),
                tool: Some(none),
                wobj: None,
                derived: None,
            },
        }
    }
}

/// Reads cut moves' literals as targets, reusing one [`Target`] (a million
/// literals make no million allocations).
pub struct CutReader<'l, 'a> {
    listing: &'l Listing<'a>,
    target: Target,
}

impl CutReader<'_, '_> {
    /// The literals of cut move `k`, each handed to `each` as the whole
    /// parse lists it. `None` when the move does not read again with its
    /// values (a number beyond `f64`): the whole parse has its say then.
    pub fn read(&mut self, k: usize, each: &mut dyn FnMut(&Target)) -> Option<()> {
        let l = self.listing;
        let m = l.skeleton.reread(l.src, k)?;
        let (p, first) = *l.cuts.get(k)?;
        let place = &l.places[p as usize];
        let t = &mut self.target;
        let text = |r: &std::ops::Range<usize>| std::str::from_utf8(&l.src[r.clone()]).ok();
        renew(&mut t.instruction, text(&m.instruction)?);
        renew(&mut t.tool, text(&m.tool)?);
        match &m.wobj {
            Some(w) => renew(&mut t.wobj, text(w)?),
            None => t.wobj = None,
        }
        if !Arc::ptr_eq(&t.origin.module, &place.module) {
            t.origin.module = place.module.clone();
        }
        if !t
            .origin
            .routine
            .as_ref()
            .is_some_and(|r| Arc::ptr_eq(r, &place.routine))
        {
            t.origin.routine = Some(place.routine.clone());
        }
        let line = l
            .lines
            .partition_point(|&s| s <= l.skeleton.place_of_cut(k));
        let line_start = l.src[..m.span.start]
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |i| i + 1);
        for (n, (at, value)) in m.targets.into_iter().enumerate() {
            t.id.clear();
            t.id.push_str(&place.prefix);
            t.id.push_str(&place.routine);
            let _ = write!(t.id, "#{}", first as usize + n);
            t.origin.pos = Pos {
                offset: at,
                line: line as u32,
                col: column(&l.src[line_start..at]),
            };
            t.value = Some(value);
            each(t);
        }
        Some(())
    }
}

/// Set a name to `text`, keeping the one it holds when it is the same
/// (CAM programs name the same tool a million times).
fn renew(slot: &mut Option<Arc<str>>, text: &str) {
    if slot.as_deref() != Some(text) {
        *slot = Some(Arc::from(text));
    }
}
