//! Data a program reaches by its name at run time: `GetDataVal "p30", p`
//! reads the datum named `p30` whatever the moves name, `SetDataVal`
//! writes it, `SetAllDataVal` and `SetDataSearch`/`GetNextSym` reach every
//! datum of a type (RAPID Instructions: GetDataVal, SetDataVal,
//! SetAllDataVal, SetDataSearch). A target reached so is the run's, not
//! unused.

use super::statements::{routine_bodies, walk_calls};
use crate::rapid::{Expr, Program};
use std::collections::HashMap;

/// The instructions that take a datum's name as their first argument.
const BY_ONE_NAME: [&str; 2] = ["GetDataVal", "SetDataVal"];

/// The instructions that reach data by a type or a pattern.
const BY_SEARCH: [&str; 3] = ["SetAllDataVal", "SetDataSearch", "GetNextSym"];

/// Where a program reaches data by name.
#[derive(Debug, Default)]
pub struct ByName {
    /// The names written as string literals (lower case), and the first
    /// instruction and line that name each.
    named: HashMap<String, (String, u32)>,
    /// The first instruction that reaches data by a name computed at run
    /// time, or by a search, and its line.
    computed: Option<(String, u32)>,
}

impl ByName {
    pub fn of(program: &Program) -> ByName {
        let mut out = ByName::default();
        for module in &program.modules {
            for routine in &module.routines {
                for body in routine_bodies(routine) {
                    walk_calls(body, &mut |call, line| {
                        let name = &*call.name;
                        let here = || (name.to_string(), line);
                        if BY_SEARCH.iter().any(|n| n.eq_ignore_ascii_case(name)) {
                            out.computed.get_or_insert_with(here);
                        } else if BY_ONE_NAME.iter().any(|n| n.eq_ignore_ascii_case(name)) {
                            match call.args.first().and_then(|a| a.value.as_ref()) {
                                Some(Expr::Str(s)) => {
                                    out.named.entry(s.to_ascii_lowercase()).or_insert_with(here);
                                }
                                _ => {
                                    out.computed.get_or_insert_with(here);
                                }
                            }
                        }
                    });
                }
            }
        }
        out
    }

    /// Why the datum `name` (a target's identifier; an array's element by
    /// its array) may be reached by name at run time, if it may.
    pub fn why(&self, name: &str) -> Option<String> {
        let base = name.split('{').next().unwrap_or(name).to_ascii_lowercase();
        if let Some((instruction, line)) = self.named.get(&base) {
            return Some(format!(
                "{instruction} at line {line} reaches it by its name at run time"
            ));
        }
        self.computed.as_ref().map(|(instruction, line)| {
            format!("{instruction} at line {line} reaches data by a name the run computes, this one among them for all anyone can tell")
        })
    }
}
