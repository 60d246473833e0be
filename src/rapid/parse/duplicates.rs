//! One name, one thing. RAPID refuses a program that declares a name
//! twice in one scope: twice among a module's data, twice among a
//! routine's data and parameters, or twice among the data every module of
//! a task sees (declared without `LOCAL`). A routine's own data may share
//! a name with a module's: it shadows it within the routine. A second
//! declaration would otherwise leave a move bound to whichever came
//! first, and the other corrected as if unused.

use crate::error::{Error, ErrorKind, Location, Result};
use crate::rapid::nocase::NoCase;
use crate::rapid::targets::name_hash;
use crate::rapid::values::Scope;
use crate::rapid::Program;

/// Where a declaration is: its file and byte offset, and its line.
#[derive(Clone, Copy)]
struct At {
    file: usize,
    offset: usize,
    line: u32,
}

/// The scopes a name is declared in.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum Space {
    /// Every module of the task (data declared without `LOCAL`).
    Task,
    /// One module's (its `LOCAL` data, and all its data besides).
    Module(usize),
    /// One routine's data and parameters: (module, routine).
    Routine(usize, usize),
}

/// Refuse every name declared twice in one scope, each at its second
/// declaration, naming the first.
pub(super) fn refuse_duplicates<'a>(prog: &'a Program, refs: &[(&str, &'a [u8])]) -> Result<()> {
    // A name declared twice in one scope is declared twice in the task, so
    // a first pass finds the names that may be declared more than once
    // anywhere, and the scopes are compared for those names alone. It
    // sorts the names' hashes (as RAPID compares names) on every core:
    // counting a million names in a table was a cache miss per name, on
    // one core. Two names alike have one hash; two hashes alike make
    // candidates, which the second pass compares as names.
    use rayon::slice::ParallelSliceMut;
    let names: usize = prog.runs.decls.iter().map(|r| r.items.len()).sum();
    let mut hashes: Vec<u64> = Vec::with_capacity(names);
    each_declaration(prog, refs, |_, name, _, _| {
        hashes.push(name_hash(name.as_bytes()));
    });
    hashes.par_sort_unstable();
    let twice: foldhash::HashSet<u64> = hashes
        .windows(2)
        .filter(|w| w[0] == w[1])
        .map(|w| w[0])
        .collect();
    drop(hashes);
    if twice.is_empty() {
        return Ok(());
    }
    let mut first: foldhash::HashMap<(Space, NoCase<'a>), At> = Default::default();
    let mut errors = Vec::new();
    each_declaration(prog, refs, |spaces, name, at, what| {
        if !twice.contains(&name_hash(name.as_bytes())) {
            return;
        }
        let key = NoCase(name.as_bytes());
        for &space in spaces {
            let Some(seen) = first.get(&(space, key)).copied() else {
                first.insert((space, key), at);
                continue;
            };
            let (file, src) = refs.get(at.file).copied().unwrap_or(("", &[]));
            let seen_file = refs.get(seen.file).map_or("", |r| r.0);
            let scope = match space {
                Space::Task => "the task (neither is LOCAL)",
                Space::Module(_) => "its module",
                Space::Routine(..) => "its routine",
            };
            errors.push(
                Error::new(
                    ErrorKind::Syntax,
                    format!(
                        "{what} {name} is declared twice in {scope}: also at {seen_file}:{}; RAPID refuses the program, and a move would be bound to one of them",
                        seen.line
                    ),
                )
                .at(Location::from_offset(file, src, at.offset)),
            );
            return;
        }
    });
    match Error::many(errors) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// Every declaration of the program, in order: the scopes its name is
/// declared in, the name, where, and what it is (data or a parameter).
fn each_declaration<'a>(
    prog: &'a Program,
    refs: &[(&str, &'a [u8])],
    mut declare: impl FnMut(&[Space], &'a str, At, &'static str),
) {
    for (mi, m) in prog.modules.iter().enumerate() {
        let module_and_task = [Space::Module(mi), Space::Task];
        let spaces = |scope: Option<Scope>| -> &[Space] {
            match scope {
                Some(Scope::Local) => &module_and_task[..1],
                _ => &module_and_task[..],
            }
        };
        for d in &m.data {
            let at = At {
                file: m.file,
                offset: d.pos.offset,
                line: d.pos.line,
            };
            declare(spaces(d.scope), &d.name, at, "data");
        }
        for &r in &m.decl_runs {
            let Some(run) = prog.runs.decls.get(r) else {
                continue;
            };
            let src = refs.get(run.file).map_or(&[][..], |x| x.1);
            for item in &run.items {
                let Some(name) = run.name_of(src, item) else {
                    continue;
                };
                let at = At {
                    file: run.file,
                    offset: item.at as usize + usize::from(item.name.0),
                    line: item.line,
                };
                declare(spaces(run.scope), name, at, "data");
            }
        }
        for (ri, routine) in m.routines.iter().enumerate() {
            let space = [Space::Routine(mi, ri)];
            for p in &routine.params {
                let at = At {
                    file: m.file,
                    offset: routine.pos.offset,
                    line: routine.pos.line,
                };
                declare(&space, &p.name, at, "parameter");
            }
            for d in &routine.data {
                let at = At {
                    file: m.file,
                    offset: d.pos.offset,
                    line: d.pos.line,
                };
                declare(&space, &d.name, at, "data");
            }
        }
    }
}
