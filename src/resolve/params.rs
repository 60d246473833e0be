//! Target parameters their call sites settle: `PROC EG1ML(robtarget
//! ToPoint, ...)` called only as `EG1ML pStart1, ...;` and
//! `EG1ML pStart2, ...;` moves to pStart1 and pStart2, with the tool and
//! work object of its own moves (of each call's, where those are
//! parameters too: see [`per_call`](super::per_call)). Jointtarget
//! parameters likewise. A parameter is settled when every call of its
//! routine passes a plain name in its place (a literal, a function's
//! result or a call the program makes by a name computed at run time
//! leaves it to the run).

use super::per_call::proc_calls;
use crate::rapid::Program;
use std::collections::HashMap;

/// For each settled robtarget or jointtarget parameter, by
/// `routine/parameter` (lower case), the names its calls pass, each once.
pub fn settled_parameters(program: &Program) -> HashMap<String, Vec<String>> {
    let mut out = HashMap::new();
    let Some(procs) = proc_calls(program) else {
        return out;
    };
    for (routine, pc) in &procs {
        for (k, param) in pc.targets.iter().enumerate() {
            let mut passed: super::calls::Passed = Some(Vec::new());
            for call in &pc.calls {
                super::calls::pass(&mut passed, call.targets[k].clone());
            }
            match passed {
                Some(names) if !names.is_empty() => {
                    out.insert(format!("{routine}/{param}"), names);
                }
                _ => {}
            }
        }
    }
    out
}
