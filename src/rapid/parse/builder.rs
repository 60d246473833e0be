//! What the parse of a run builds as it reads its files: the program,
//! the names it interns, each routine's count of literals, and the
//! names of the fast lane's runs.

use crate::rapid::runs::NONE;
use crate::rapid::Program;
use std::collections::HashMap;
use std::sync::Arc;

#[derive(Default)]
pub(super) struct Builder {
    pub prog: Program,
    pub names: foldhash::HashMap<String, Arc<str>>,
    /// Per routine (lower-case "module\0routine"): literals counted so far.
    pub inline_counts: HashMap<String, usize>,
    /// The runs' names by their text: their number in the runs' table.
    pub run_names: foldhash::HashMap<Arc<str>, u16>,
    /// Whether the fast lane reads what it can (else the grammar reads
    /// everything), and reads ahead of the parse on every core.
    pub lanes: bool,
    pub ahead: bool,
}

impl Builder {
    pub fn intern(&mut self, s: &str) -> Arc<str> {
        if let Some(a) = self.names.get(s) {
            return a.clone();
        }
        let a: Arc<str> = Arc::from(s);
        self.names.insert(s.to_string(), a.clone());
        a
    }

    /// The number of `name` (interned) in the runs' table of names;
    /// `None` when the table is full.
    pub fn run_name(&mut self, name: &Arc<str>) -> Option<u16> {
        if let Some(&id) = self.run_names.get(name) {
            return Some(id);
        }
        let id = u16::try_from(self.prog.runs.names.len())
            .ok()
            .filter(|&id| id != NONE)?;
        self.prog.runs.names.push(name.clone());
        self.run_names.insert(name.clone(), id);
        Some(id)
    }
}

/// Instruction context of inline literals.
#[derive(Clone, Default)]
pub(super) struct InlineCtx {
    pub instruction: Option<Arc<str>>,
    pub tool: Option<Arc<str>>,
    pub wobj: Option<Arc<str>>,
    pub assigned_to: Option<String>,
}
