//! The calls of a program's procedures by name: what settles a
//! procedure's parameters, where every call passes the same kind of thing.

use crate::rapid::{Call, Program, StatementKind};
use std::collections::HashMap;

use super::statements::{routine_bodies, walk_statements};

/// Call `f` with every call of a procedure by its name, in program order.
/// Returns `false` where some call by a name computed at run time
/// (`%name% ...`) passes arguments: any procedure's parameters may then be
/// what it passes, so no parameter is settled by the calls seen.
pub(super) fn each_call(program: &Program, f: &mut dyn FnMut(&Call)) -> bool {
    let mut late_bound_with_arguments = false;
    for routine in program.modules.iter().flat_map(|m| &m.routines) {
        for body in routine_bodies(routine) {
            walk_statements(body, &mut |s| {
                let StatementKind::Call(call) = &s.kind else {
                    return;
                };
                if call.late_bound {
                    late_bound_with_arguments |= !call.args.is_empty();
                } else {
                    f(call);
                }
            });
        }
    }
    !late_bound_with_arguments
}

/// What the calls seen so far pass for one parameter: the names, each
/// once, or `None` once a call passes something that does not settle it.
pub(super) type Passed = Option<Vec<String>>;

/// One more call passes `name` (`None`: something that does not settle
/// the parameter) where `entry` holds what the others passed.
pub(super) fn pass(entry: &mut Passed, name: Option<String>) {
    match (name, entry.as_mut()) {
        (Some(n), Some(list)) => {
            if !list.iter().any(|x| x.eq_ignore_ascii_case(&n)) {
                list.push(n);
            }
        }
        _ => *entry = None,
    }
}

/// The parameters every call settled, with what they pass, where `keep`
/// takes the names.
pub(super) fn settled(
    passed: HashMap<String, Passed>,
    keep: impl Fn(&[String]) -> bool,
) -> HashMap<String, Vec<String>> {
    passed
        .into_iter()
        .filter_map(|(k, v)| Some((k, v?)))
        .filter(|(_, v)| keep(v))
        .collect()
}
