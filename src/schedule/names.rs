//! The targets a schedule file may name: the program's robtargets and
//! jointtargets, two name spaces (`docs/formats.md`), each identifier in
//! lower case as RAPID compares names.

use crate::rapid::Program;

/// Which of the program's name spaces a schedule row names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TargetType {
    Robtarget,
    Jointtarget,
}

impl TargetType {
    pub fn name(self) -> &'static str {
        match self {
            TargetType::Robtarget => "robtarget",
            TargetType::Jointtarget => "jointtarget",
        }
    }
}

/// The identifiers of a program's targets, by kind.
#[derive(Debug, Clone, Default)]
pub struct ProgramNames {
    robtargets: foldhash::HashSet<String>,
    jointtargets: foldhash::HashSet<String>,
}

impl ProgramNames {
    /// The identifiers of `program`'s robtargets and jointtargets.
    pub fn of(program: &Program) -> ProgramNames {
        let targets = program.targets();
        let mut robtargets = foldhash::HashSet::default();
        robtargets.reserve(targets.len());
        let mut id = String::new();
        for i in 0..targets.len() {
            if targets.id_into(i, &mut id).is_some() {
                id.make_ascii_lowercase();
                robtargets.insert(std::mem::take(&mut id));
            }
        }
        let jointtargets = program
            .jointtargets()
            .iter()
            .map(|j| j.id.to_ascii_lowercase())
            .collect();
        ProgramNames {
            robtargets,
            jointtargets,
        }
    }

    /// Whether the program has a target `id` of `kind`.
    pub fn has(&self, kind: TargetType, id: &str) -> bool {
        let set = match kind {
            TargetType::Robtarget => &self.robtargets,
            TargetType::Jointtarget => &self.jointtargets,
        };
        if id.bytes().any(|b| b.is_ascii_uppercase()) {
            set.contains(&id.to_ascii_lowercase())
        } else {
            set.contains(id)
        }
    }
}
