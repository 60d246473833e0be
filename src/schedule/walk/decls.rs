//! The walk's table of module data by name: every declaration of the
//! program's modules (those of the tree and the fast lane's runs) under
//! its name as RAPID compares names, and the routines by name. Built
//! beside the table of targets by identifier, on another core.

use crate::rapid::{self, DataDecl, DeclBatch, NoCase, Program, Routine};

type FastMap<K, V> = foldhash::HashMap<K, V>;

/// Module data by name, routines by lower-case name, and the runs of
/// declarations in the order of their targets.
pub(super) type Declarations<'p> = (
    FastMap<NoCase<'p>, DeclList<'p>>,
    FastMap<String, Vec<(usize, &'p Routine)>>,
    Vec<RunDecls<'p>>,
);

/// The declarations of one name, with their modules' numbers, in the
/// program's order: nearly always one.
pub(super) type DeclList<'p> = smallvec::SmallVec<[(usize, Decl<'p>); 1]>;

/// A declaration run: its targets are `first..first + len`, declared in
/// `module`, LOCAL or not.
#[derive(Clone, Copy)]
pub(super) struct RunDecls<'p> {
    pub first: usize,
    pub len: usize,
    pub module: usize,
    pub local: bool,
    pub batch: DeclBatch<'p>,
}

/// A module's declaration: in the tree, or a robtarget of a run of the
/// fast lane's (its target's number).
#[derive(Debug, Clone, Copy)]
pub(super) enum Decl<'p> {
    Tree(&'p DataDecl),
    Run { local: bool, target: usize },
}

impl Decl<'_> {
    pub(super) fn local(&self) -> bool {
        match self {
            Decl::Tree(d) => d.scope == Some(rapid::Scope::Local),
            Decl::Run { local, .. } => *local,
        }
    }
}

/// The program's declarations and routines by name ([`Declarations`]).
pub(super) fn declarations(program: &Program) -> Declarations<'_> {
    // Borrowed names, compared as RAPID compares them: a lower-case
    // copy of each of a million declared names cost as much as the
    // rest of this table.
    // Room for every name at once: growing the table hashed each name
    // again at every doubling, reading it from the source, and was a
    // second of a million declared targets' walk. A name declared once
    // keeps its one declaration in the entry, with no vector of its
    // own to make and free.
    let names = (program.modules.iter())
        .map(|m| {
            m.data.len()
                + (program.declaration_batches(m))
                    .map(|b| b.len())
                    .sum::<usize>()
        })
        .sum();
    let mut decls: FastMap<NoCase<'_>, DeclList<'_>> =
        FastMap::with_capacity_and_hasher(names, Default::default());
    let mut routines: FastMap<String, Vec<(usize, &Routine)>> = FastMap::default();
    let mut run_decls = Vec::new();
    for (mi, m) in program.modules.iter().enumerate() {
        for d in &m.data {
            decls
                .entry(NoCase(d.name.as_bytes()))
                .or_default()
                .push((mi, Decl::Tree(d)));
        }
        for batch in program.declaration_batches(m) {
            let local = batch.scope() == Some(rapid::Scope::Local);
            run_decls.push(RunDecls {
                first: batch.first_target(),
                len: batch.len(),
                module: mi,
                local,
                batch,
            });
            for (name, target) in batch.names() {
                decls
                    .entry(NoCase(name.as_bytes()))
                    .or_default()
                    .push((mi, Decl::Run { local, target }));
            }
        }
        for r in &m.routines {
            routines
                .entry(r.name.to_ascii_lowercase())
                .or_default()
                .push((mi, r));
        }
    }
    run_decls.sort_unstable_by_key(|r| r.first);
    (decls, routines, run_decls)
}
