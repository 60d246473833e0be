//! The visits of a streamed run's cut literals: the targets of the moves a
//! skeleton cut out, kept by their number among the cut literals (in file
//! order) rather than by identifier (a million identifiers made and hashed
//! were a third of timing a CAM program). Each literal's identifier (its
//! routine's `main#1234`) is made only where one is asked for.

use super::file::{encode_visits, Schedule};
use crate::digest::Encoder;
use std::borrow::Cow;
use std::sync::Arc;

/// Every visit of every cut literal, and where each was first visited
/// among the walk's other targets.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CutVisits {
    /// Each literal's first visit (minutes); NaN: not visited.
    first: Vec<f64>,
    /// Every visit of a literal visited more than once.
    more: foldhash::HashMap<usize, Vec<f64>>,
    /// Each visited literal's prefix (an index into `prefixes`: its
    /// routine, qualified or not) and inline number: its identifier.
    names: Vec<(u32, u32)>,
    prefixes: Vec<Arc<str>>,
    /// Literals in first-visit order, each with the number of the walk's
    /// other targets first visited before it.
    order: Vec<(usize, usize)>,
}

impl CutVisits {
    /// No visit yet of `literals` literals.
    pub(crate) fn new(literals: usize) -> CutVisits {
        CutVisits {
            first: vec![f64::NAN; literals],
            names: vec![(0, 0); literals],
            ..CutVisits::default()
        }
    }

    /// A visit of `literal`, identified `{prefix}#{inline}`, at
    /// `time_min`, after `before` other targets were first visited.
    pub(crate) fn visit(
        &mut self,
        literal: usize,
        (prefix, inline): (&Arc<str>, usize),
        time_min: f64,
        before: usize,
    ) {
        let Some(first) = self.first.get_mut(literal) else {
            return;
        };
        if !first.is_nan() {
            let all = self.more.entry(literal).or_insert_with(|| vec![*first]);
            all.push(time_min);
            return;
        }
        *first = time_min;
        let r = match self.prefixes.iter().rposition(|p| Arc::ptr_eq(p, prefix)) {
            Some(r) => r,
            None => {
                self.prefixes.push(prefix.clone());
                self.prefixes.len() - 1
            }
        };
        self.names[literal] = (r as u32, inline as u32);
        self.order.push((before, literal));
    }

    /// Every visit of `literal`, in the order made; `None`: never visited.
    pub fn times(&self, literal: usize) -> Option<&[f64]> {
        if let Some(all) = self.more.get(&literal) {
            return Some(all);
        }
        self.first
            .get(literal)
            .filter(|t| !t.is_nan())
            .map(std::slice::from_ref)
    }

    /// How many literals there are.
    pub fn len(&self) -> usize {
        self.first.len()
    }

    pub fn is_empty(&self) -> bool {
        self.first.is_empty()
    }

    /// The latest visit, in minutes (0 without one).
    pub fn latest(&self) -> f64 {
        let firsts = self.first.iter().filter(|t| !t.is_nan());
        firsts
            .chain(self.more.values().flatten())
            .copied()
            .fold(0.0, f64::max)
    }

    /// A visited literal's identifier, as written (`main#1234`).
    fn id(&self, literal: usize) -> String {
        let (r, n) = self.names[literal];
        format!("{}#{n}", self.prefixes[r as usize])
    }

    /// Whether an identifier is a visited literal's (case ignored): a
    /// lookup made once, for many identifiers (a scan of every literal
    /// for each made a program of many inline jointtargets quadratic),
    /// and only when an identifier of an inline target (`main#1`) is
    /// asked.
    pub fn ids(&self) -> impl Fn(&str) -> bool + '_ {
        let named = std::cell::OnceCell::new();
        move |id: &str| {
            let Some((prefix, n)) = id.rsplit_once('#') else {
                return false;
            };
            let Ok(n) = n.parse::<u32>() else {
                return false;
            };
            let named: &foldhash::HashSet<(u32, u32)> =
                named.get_or_init(|| self.order.iter().map(|&(_, l)| self.names[l]).collect());
            // A prefix may be held more than once (one per run).
            self.prefixes
                .iter()
                .enumerate()
                .filter(|(_, p)| p.eq_ignore_ascii_case(prefix))
                .any(|(r, _)| named.contains(&(r as u32, n)))
        }
    }

    /// Every target the whole program's walk reaches, where `own` has
    /// the walk's other targets, in first-visit order: its identifier as
    /// written and its visits.
    pub fn in_order<'a>(&'a self, own: &'a Schedule) -> Vec<(Cow<'a, str>, &'a [f64])> {
        let targets = own.targets();
        let mut all = Vec::with_capacity(targets.len() + self.order.len());
        let mut cut = self.order.iter().peekable();
        let put_cut = |all: &mut Vec<(Cow<'a, str>, &'a [f64])>, l: usize| {
            all.push((Cow::Owned(self.id(l)), self.times(l).unwrap_or(&[])));
        };
        for (j, id) in targets.iter().enumerate() {
            while let Some(&(_, l)) = cut.next_if(|(before, _)| *before <= j) {
                put_cut(&mut all, l);
            }
            all.push((Cow::Borrowed(&**id), own.times(id).unwrap_or(&[])));
        }
        for &(_, l) in cut {
            put_cut(&mut all, l);
        }
        all
    }

    /// The schedule a walk of the whole program makes, where `own` has
    /// the walk's other targets, in its byte encoding (which a corrected
    /// file's marker fingerprints: the same as the whole walk's
    /// [`Schedule::encode`]).
    pub fn encode_whole(&self, own: &Schedule, e: &mut Encoder) {
        let all = self.in_order(own);
        encode_visits(e, all.len(), all.iter().map(|(id, t)| (&**id, *t)));
    }
}
