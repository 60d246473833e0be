//! Robtarget parameters their call sites settle: `PROC EG1ML(robtarget
//! ToPoint, ...)` called only as `EG1ML pStart1, ...;` and
//! `EG1ML pStart2, ...;` moves to pStart1 and pStart2, with the tool and
//! work object of its own moves. A parameter is settled when every call
//! of its routine passes a plain name in its place (a literal, a
//! function's result or a call the program makes by a name computed at
//! run time leaves it to the run).

use crate::rapid::{Expr, Program, RoutineKind};
use std::collections::HashMap;

/// For each settled robtarget parameter, by `routine/parameter` (lower
/// case), the names its calls pass.
pub fn settled_parameters(program: &Program) -> HashMap<String, Vec<String>> {
    let mut wanted: HashMap<String, Vec<(usize, String)>> = HashMap::new();
    for routine in program.modules.iter().flat_map(|m| &m.routines) {
        if routine.kind != RoutineKind::Proc {
            continue;
        }
        let required = routine.params.iter().filter(|p| !p.optional);
        for (k, p) in required.enumerate() {
            if p.type_name.eq_ignore_ascii_case("robtarget") && p.array_dims == 0 {
                wanted
                    .entry(routine.name.to_ascii_lowercase())
                    .or_default()
                    .push((k, p.name.to_ascii_lowercase()));
            }
        }
    }
    if wanted.is_empty() {
        return HashMap::new();
    }
    // Passed names by (routine, parameter); `None`: a call that does not
    // settle it.
    let mut passed: HashMap<String, super::calls::Passed> = HashMap::new();
    let bound = super::calls::each_call(program, &mut |call| {
        let Some(params) = wanted.get(&call.name.to_ascii_lowercase()) else {
            return;
        };
        let args: Vec<&Expr> = call.positional().collect();
        for (k, p) in params {
            let key = format!("{}/{p}", call.name.to_ascii_lowercase());
            let entry = passed.entry(key).or_insert_with(|| Some(Vec::new()));
            let name = match args.get(*k) {
                Some(Expr::Name(n)) => Some(n.to_ascii_lowercase()),
                _ => None,
            };
            super::calls::pass(entry, name);
        }
    });
    if !bound {
        return HashMap::new();
    }
    super::calls::settled(passed, |names| !names.is_empty())
}
