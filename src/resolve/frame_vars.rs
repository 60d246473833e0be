//! Tools and work objects declared without a value and assigned at run
//! time from declared ones: `PERS tooldata ToolActual;` with
//! `ToolActual := BoxUp;`. A move with `ToolActual` moves with the tools
//! it is assigned from; with several, its targets are moved to with
//! several tools, and the shared-target rule says what that leaves.
//! Anything else assigned (a function's result, a component changed)
//! leaves the variable to the run: it stays an unknown name.
//!
//! A procedure's tooldata or wobjdata parameter is settled by its calls
//! where they all pass the same one: `PROC GunMove(robtarget ToPoint,
//! \wobjdata WObj)` with `MoveL ToPoint, v200, fine, tGun \WObj?WObj;`
//! moves with the work object every call passes, or with `wobj0` where
//! every call leaves the optional argument out (the conditional argument
//! is then omitted too).

use crate::rapid::{Expr, Program, RoutineKind, StatementKind};
use std::collections::HashMap;

use super::walk_statements;

/// For each tooldata or wobjdata variable declared without a value whose
/// every assignment is a declared tool or work object (by name), those
/// names as written, in program order; by lower-case variable name.
pub fn frame_variables(program: &Program) -> HashMap<String, Vec<String>> {
    let mut out = assigned_variables(program);
    for (name, list) in settled_frame_parameters(program) {
        let entry = out.entry(name).or_default();
        for n in list {
            if !entry.iter().any(|x| x.eq_ignore_ascii_case(&n)) {
                entry.push(n);
            }
        }
    }
    out
}

/// The tool and work object names of the program, lower case, with the
/// defaults: (tools, work objects).
fn declared_frames(program: &Program) -> (Vec<String>, Vec<String>) {
    let tools = program
        .tools()
        .iter()
        .map(|t| t.name.to_ascii_lowercase())
        .chain(["tool0".to_string()])
        .collect();
    let wobjs = program
        .wobjs()
        .iter()
        .map(|w| w.name.to_ascii_lowercase())
        .chain(["wobj0".to_string()])
        .collect();
    (tools, wobjs)
}

/// For each tooldata or wobjdata parameter of a procedure that every call
/// settles to one and the same name (a declared tool or work object passed
/// by name, or an optional argument left out: the default), that name; by
/// lower-case parameter name. Calls that pass different ones leave the
/// parameter to the run: the target a call passes goes with the frames of
/// that call, and pairing every target with every frame would refuse
/// targets over frames the program never moves them in. A call by a name
/// computed at run time with arguments leaves every parameter to the run.
fn settled_frame_parameters(program: &Program) -> HashMap<String, Vec<String>> {
    // (routine, parameter, its place among the required ones or None for
    // an optional one, tool or not), by lower-case routine name.
    type Wanted = (String, Option<usize>, bool);
    let mut wanted: HashMap<String, Vec<Wanted>> = HashMap::new();
    let (tools, wobjs) = declared_frames(program);
    for routine in program.modules.iter().flat_map(|m| &m.routines) {
        if routine.kind != RoutineKind::Proc {
            continue;
        }
        let mut required = 0;
        for p in &routine.params {
            let place = (!p.optional).then_some(required);
            required += usize::from(!p.optional);
            let t = p.type_name.to_ascii_lowercase();
            let is_tool = t == "tooldata";
            let name = p.name.to_ascii_lowercase();
            // A parameter that shares its name with declared data is left
            // to the data's rules: one list per name could not tell them.
            let taken = tools.contains(&name) || wobjs.contains(&name);
            if (is_tool || t == "wobjdata") && p.array_dims == 0 && !taken {
                wanted
                    .entry(routine.name.to_ascii_lowercase())
                    .or_default()
                    .push((name, place, is_tool));
            }
        }
    }
    if wanted.is_empty() {
        return HashMap::new();
    }
    let mut passed: HashMap<String, super::calls::Passed> = HashMap::new();
    let bound = super::calls::each_call(program, &mut |call| {
        let Some(params) = wanted.get(&call.name.to_ascii_lowercase()) else {
            return;
        };
        let args: Vec<&Expr> = call.positional().collect();
        for (name, place, is_tool) in params {
            let (declared, default) = match is_tool {
                true => (&tools, "tool0"),
                false => (&wobjs, "wobj0"),
            };
            let value = match place {
                Some(k) => args.get(*k).copied().map(Some),
                None => match call.optional(name) {
                    None => Some(None),
                    Some(a) => a.value.as_ref().map(Some),
                },
            };
            let entry = passed
                .entry(name.clone())
                .or_insert_with(|| Some(Vec::new()));
            let settled = match value {
                Some(None) => Some(default.to_string()),
                Some(Some(Expr::Name(n))) if declared.contains(&n.to_ascii_lowercase()) => {
                    Some(n.to_string())
                }
                _ => None,
            };
            super::calls::pass(entry, settled);
        }
    });
    if !bound {
        return HashMap::new();
    }
    super::calls::settled(passed, |names| names.len() == 1)
}

/// Tool and work object variables declared without a value, each with the
/// declared names assigned to it (see the module doc).
fn assigned_variables(program: &Program) -> HashMap<String, Vec<String>> {
    let mut unset: HashMap<String, &str> = HashMap::new();
    for m in &program.modules {
        let routine_data = m.routines.iter().flat_map(|r| &r.data);
        for d in m.data.iter().chain(routine_data) {
            let t = d.type_name.to_ascii_lowercase();
            if d.init.is_none() && d.dims.is_empty() && (t == "tooldata" || t == "wobjdata") {
                unset.insert(
                    d.name.to_ascii_lowercase(),
                    if t == "tooldata" { "tool" } else { "wobj" },
                );
            }
        }
    }
    if unset.is_empty() {
        return HashMap::new();
    }
    let (tools, wobjs) = declared_frames(program);
    // `None`: an assignment that does not settle it.
    let mut sources: HashMap<String, Option<Vec<String>>> = HashMap::new();
    for routine in program.modules.iter().flat_map(|m| &m.routines) {
        for body in super::routine_bodies(routine) {
            walk_statements(body, &mut |s| {
                let StatementKind::Assign { target, value } = &s.kind else {
                    return;
                };
                let Some(root) = root(target) else { return };
                let key = root.to_ascii_lowercase();
                let Some(kind) = unset.get(&key) else { return };
                let entry = sources.entry(key).or_insert_with(|| Some(Vec::new()));
                let declared = |n: &str| {
                    let n = n.to_ascii_lowercase();
                    match *kind {
                        "tool" => tools.contains(&n),
                        _ => wobjs.contains(&n),
                    }
                };
                match (target, value, entry.as_mut()) {
                    (Expr::Name(_), Expr::Name(v), Some(list)) if declared(v) => {
                        if !list.iter().any(|x| x.eq_ignore_ascii_case(v)) {
                            list.push(v.to_string());
                        }
                    }
                    _ => *entry = None,
                }
            });
        }
    }
    sources
        .into_iter()
        .filter_map(|(k, v)| Some((k, v?)))
        .filter(|(_, v)| !v.is_empty())
        .collect()
}

fn root(e: &Expr) -> Option<&str> {
    match e {
        Expr::Name(n) => Some(n),
        Expr::Index(b) => root(&b.0),
        Expr::Component(b) => root(&b.0),
        _ => None,
    }
}
