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
//! is then omitted too). Calls that pass different ones pair each target
//! with the frames of the call that passes it ([`per_call`](super::per_call)).

use crate::rapid::{Expr, Program, StatementKind};
use std::collections::HashMap;

use super::per_call::{declared_frames, proc_calls};
use super::statements::{routine_bodies, walk_statements};

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

/// For each tooldata or wobjdata parameter that every call of every
/// procedure with a parameter of that name settles to one and the same
/// name, that name; by lower-case parameter name. Parameters the calls
/// settle to different names move with each call's (see
/// [`per_call`](super::per_call)).
fn settled_frame_parameters(program: &Program) -> HashMap<String, Vec<String>> {
    let Some(procs) = proc_calls(program) else {
        return HashMap::new();
    };
    let mut passed: HashMap<String, super::calls::Passed> = HashMap::new();
    for pc in procs.values() {
        for (k, (name, _)) in pc.frames.iter().enumerate() {
            let entry = passed
                .entry(name.clone())
                .or_insert_with(|| Some(Vec::new()));
            for call in &pc.calls {
                super::calls::pass(entry, call.frames[k].clone());
            }
        }
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
        for body in routine_bodies(routine) {
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
