//! Robtarget variables whose value the run decides: assigned in a routine
//! (`pUnloadA := pLage1A;`, `p.trans.z := 200;`), written by a search
//! instruction, or handed to a procedure that may change them. Their
//! declared value is a placeholder or a start value, not a taught point,
//! so it is not corrected; what they are assigned from is followed, so
//! that a base reached only through such a variable
//! (`pAbove := Offs(pPallet, ...); MoveL pAbove, ...`) still has the tool
//! and work object of its moves.

use crate::rapid::constants::names_read;
use crate::rapid::{Expr, Program, Routine, Statement, StatementKind};
use std::collections::{HashMap, HashSet};

use super::statements::{routine_bodies, walk_statements};

/// Where the run writes a robtarget variable.
#[derive(Debug, Clone, PartialEq)]
pub struct Write {
    /// The variable as written.
    pub variable: String,
    pub routine: String,
    pub line: u32,
    /// How: `assigned`, `assigned by component`, `written by SearchL`, ...
    pub how: String,
}

/// Instructions that store a robtarget into an argument, and which
/// positional argument (0-based): the search point of the search
/// instructions.
const WRITING_INSTRUCTIONS: [(&str, usize); 4] = [
    ("SearchL", 1),
    ("SearchC", 1),
    ("SearchExtJ", 1),
    ("SearchJ", 1),
];

/// Every robtarget and jointtarget variable some routine writes, by lower-case name (the
/// first write found, for messages).
pub fn runtime_writes(program: &Program) -> HashMap<String, Write> {
    let robtargets = variables_of(program, &["robtarget", "jointtarget"]);
    let writable_params = writable_parameters(program);
    let mut out: HashMap<String, Write> = HashMap::new();
    let mut note = |name: &str, routine: &Routine, line: u32, how: String| {
        let key = name.to_lowercase();
        if robtargets.contains(&key) {
            out.entry(key).or_insert_with(|| Write {
                variable: name.to_string(),
                routine: routine.name.to_string(),
                line,
                how,
            });
        }
    };
    for routine in program.modules.iter().flat_map(|m| &m.routines) {
        for body in routine_bodies(routine) {
            walk_statements(body, &mut |s: &Statement| match &s.kind {
                StatementKind::Assign { target, .. } => {
                    if let Some(root) = root_name(target) {
                        let how = if matches!(target, Expr::Name(_)) {
                            "assigned"
                        } else {
                            "assigned in part"
                        };
                        note(root, routine, s.pos.line, how.to_string());
                    }
                }
                StatementKind::Call(call) => {
                    let positional: Vec<&Expr> = call.positional().collect();
                    let name = call.name.to_lowercase();
                    let mut written: Vec<usize> = WRITING_INSTRUCTIONS
                        .iter()
                        .filter(|(n, _)| n.eq_ignore_ascii_case(&name))
                        .map(|(_, i)| *i)
                        .collect();
                    if let Some(params) = writable_params.get(&name) {
                        written.extend(params);
                    }
                    // `\SearchStop:=p` (SmarTac's searches and others):
                    // where the search stopped, written by the run.
                    let stop = call.optional("SearchStop").and_then(|a| a.value.as_ref());
                    if let Some(root) = stop.and_then(root_name) {
                        note(
                            root,
                            routine,
                            s.pos.line,
                            format!("written by {}", call.name),
                        );
                    }
                    for i in written {
                        if let Some(root) = positional.get(i).and_then(|e| root_name(e)) {
                            note(
                                root,
                                routine,
                                s.pos.line,
                                format!("written by {}", call.name),
                            );
                        }
                    }
                }
                _ => {}
            });
        }
    }
    out
}

/// For each robtarget variable assigned in a routine, the robtarget names
/// its assigned values read, followed through other such variables:
/// `pAbove := Offs(pPallet, ...)` gives `pabove → [ppallet]`. Keys and
/// names lower case.
pub fn aliases(program: &Program) -> HashMap<String, Vec<String>> {
    let robtargets = robtarget_variables(program);
    let mut direct: HashMap<String, Vec<String>> = HashMap::new();
    for routine in program.modules.iter().flat_map(|m| &m.routines) {
        for body in routine_bodies(routine) {
            walk_statements(body, &mut |s: &Statement| {
                let StatementKind::Assign { target, value } = &s.kind else {
                    return;
                };
                let Some(root) = root_name(target).map(str::to_lowercase) else {
                    return;
                };
                if !robtargets.contains(&root) {
                    return;
                }
                let mut read = names_read(value);
                for t in targets_in(value) {
                    if let Some(d) = program.targets().get(t).and_then(|t| t.derived.clone()) {
                        read.extend(d.bases.iter().cloned());
                    }
                }
                let list = direct.entry(root.clone()).or_default();
                for name in read {
                    let name = name.to_lowercase();
                    let base = name.split('{').next().unwrap_or("").to_string();
                    if robtargets.contains(&base) && name != root && !list.contains(&name) {
                        list.push(name);
                    }
                }
            });
        }
    }
    // Follow chains (`a := b; b := Offs(c, ...)`) to every base.
    let mut out = HashMap::new();
    for key in direct.keys() {
        let mut seen = HashSet::from([key.clone()]);
        let mut stack = direct[key].clone();
        let mut all = Vec::new();
        while let Some(n) = stack.pop() {
            if !seen.insert(n.clone()) {
                continue;
            }
            all.push(n.clone());
            if let Some(next) = direct.get(&n) {
                stack.extend(next.iter().cloned());
            }
        }
        out.insert(key.clone(), all);
    }
    out
}

/// Lower-case names of every robtarget variable declared in the program.
fn robtarget_variables(program: &Program) -> Variables<'_> {
    variables_of(program, &["robtarget"])
}

/// The variables of these types declared in the program, by lower-case
/// name: the set is made when first asked (a program of a million
/// declared targets and no assignment never makes it).
fn variables_of<'p>(program: &'p Program, types: &'static [&'static str]) -> Variables<'p> {
    Variables {
        program,
        types,
        set: std::cell::OnceCell::new(),
    }
}

struct Variables<'p> {
    program: &'p Program,
    types: &'static [&'static str],
    set: std::cell::OnceCell<HashSet<String>>,
}

impl Variables<'_> {
    fn contains(&self, key: &str) -> bool {
        self.set
            .get_or_init(|| {
                let p = self.program;
                let robtargets = self.types.contains(&"robtarget");
                let in_runs = (p.modules.iter())
                    .filter(|_| robtargets)
                    .flat_map(|m| p.declaration_batches(m))
                    .flat_map(|b| b.names())
                    .map(|(name, _)| name.to_lowercase());
                p.modules
                    .iter()
                    .flat_map(|m| m.data.iter().chain(m.routines.iter().flat_map(|r| &r.data)))
                    .filter(|d| {
                        self.types
                            .iter()
                            .any(|t| d.type_name.eq_ignore_ascii_case(t))
                    })
                    .map(|d| d.name.to_lowercase())
                    .chain(in_runs)
                    .collect()
            })
            .contains(key)
    }
}

/// The program's own procedures, by lower-case name, with the positional
/// indices of their robtarget parameters passed by reference (`INOUT`,
/// `VAR`, `PERS`): a call may write whatever it is given there.
fn writable_parameters(program: &Program) -> HashMap<String, Vec<usize>> {
    let mut out = HashMap::new();
    for r in program.modules.iter().flat_map(|m| &m.routines) {
        let positional = r.params.iter().filter(|p| !p.optional);
        let writable: Vec<usize> = positional
            .enumerate()
            .filter(|(_, p)| {
                (p.type_name.eq_ignore_ascii_case("robtarget")
                    || p.type_name.eq_ignore_ascii_case("jointtarget"))
                    && p.access.as_deref().is_some_and(|a| {
                        ["inout", "var", "pers"]
                            .iter()
                            .any(|k| a.eq_ignore_ascii_case(k))
                    })
            })
            .map(|(i, _)| i)
            .collect();
        if !writable.is_empty() {
            out.insert(r.name.to_lowercase(), writable);
        }
    }
    out
}

/// The variable an assignment or argument writes: `p` of `p`,
/// `p.trans.x`, `arr{i}`.
pub fn root_name(e: &Expr) -> Option<&str> {
    match e {
        Expr::Name(n) => Some(n),
        Expr::Index(b) => root_name(&b.0),
        Expr::Component(b) => root_name(&b.0),
        _ => None,
    }
}

/// Robtarget literals and derived expressions (indices into the program's
/// targets) inside an expression.
fn targets_in(e: &Expr) -> Vec<usize> {
    use crate::rapid::visit::{walk_expr, Visit};
    struct Found(Vec<usize>);
    impl<'a> Visit<'a> for Found {
        // Expressions alone: the fast lane's runs hold none.
        fn program(&self) -> Option<&'a Program> {
            None
        }
        fn visit_expr(&mut self, e: &'a Expr) {
            if let Expr::Target(i) = e {
                self.0.push(*i);
            }
            walk_expr(self, e);
        }
    }
    let mut f = Found(Vec::new());
    f.visit_expr(e);
    f.0
}

#[cfg(test)]
mod tests {
    use super::*;

    const SRC: &str = "MODULE M
  VAR robtarget pUnloadA := [[0,0,0],[0,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pLage1A := [[420,30,320],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pPallet := [[500,0,300],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  VAR robtarget pAbove;
  VAR robtarget pHit;
  PERS robtarget pTaught := [[400,0,300],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    VAR num i := 1;
    pUnloadA := pLage1A;
    pAbove := Offs(pPallet, i*100, 0, 50);
    pTaught.trans.z := 250;
    SearchL \\Stop, diSensor, pHit, pLage1A, v100, tool0;
  ENDPROC
ENDMODULE
";

    #[test]
    fn whole_part_and_search_writes_are_found() {
        let p = crate::rapid::parse("m.mod", SRC.as_bytes()).unwrap();
        let w = runtime_writes(&p);
        assert_eq!(w["punloada"].how, "assigned");
        assert_eq!(w["ptaught"].how, "assigned in part");
        assert_eq!(w["phit"].how, "written by SearchL");
        assert!(!w.contains_key("plage1a"), "only read, never written");
        assert!(!w.contains_key("i"), "not a robtarget");
    }

    #[test]
    fn aliases_follow_assignments_to_their_bases() {
        let p = crate::rapid::parse("m.mod", SRC.as_bytes()).unwrap();
        let a = aliases(&p);
        assert_eq!(a["punloada"], vec!["plage1a"]);
        assert_eq!(a["pabove"], vec!["ppallet"]);
    }
}
