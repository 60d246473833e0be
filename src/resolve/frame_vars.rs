//! Tools and work objects declared without a value and assigned at run
//! time from declared ones: `PERS tooldata ToolActual;` with
//! `ToolActual := BoxUp;`. A move with `ToolActual` moves with the tools
//! it is assigned from; with several, its targets are moved to with
//! several tools, and the shared-target rule says what that leaves.
//! Anything else assigned (a function's result, a component changed)
//! leaves the variable to the run: it stays an unknown name.

use crate::rapid::{Expr, Program, StatementKind};
use std::collections::HashMap;

use super::walk_statements;

/// For each tooldata or wobjdata variable declared without a value whose
/// every assignment is a declared tool or work object (by name), those
/// names as written, in program order; by lower-case variable name.
pub fn frame_variables(program: &Program) -> HashMap<String, Vec<String>> {
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
    let tools: Vec<String> = program
        .tools()
        .iter()
        .map(|t| t.name.to_ascii_lowercase())
        .chain(["tool0".to_string()])
        .collect();
    let wobjs: Vec<String> = program
        .wobjs()
        .iter()
        .map(|w| w.name.to_ascii_lowercase())
        .chain(["wobj0".to_string()])
        .collect();
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
