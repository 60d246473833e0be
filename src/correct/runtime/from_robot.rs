//! The targets a program reads back from the robot, which the run-time
//! rewrite leaves unwrapped: `CRobT`, `CJointT` and `CPos` return where
//! the robot stands, and a search instruction's found point where it
//! stood when the signal came; with the module correcting the moves, that
//! is a position the correction already went into. Moving to it through
//! the module again would correct twice (issue 48: one drift off).
//!
//! [`FromRobot::new`] finds every datum that holds such a reading: the
//! data assigned from an expression calling one of those functions, the
//! found points of the searches, and then, to a fixed point, every datum
//! assigned from an expression that reads such a datum (`p2 := Offs(p1,
//! 0, 0, 20)`, `p2 := p1`, `p2.trans := p1.trans`), the results of the
//! program's FUNCs that return one, the arguments its PROCs write one
//! into (INOUT, VAR, PERS parameters) and the parameters a call passes
//! one to. Names are followed in RAPID's scopes: a routine's own data and
//! parameters, then its module's data (LOCAL ones there only), then the
//! task's global data; a name reused in another routine is another datum.
//!
//! The analysis does not follow the order of statements: a datum once
//! assigned a reading anywhere counts as one everywhere, as a move may
//! follow the assignment in any run of the program.

use crate::rapid::visit::{walk_expr, walk_function_call, Visit};
use crate::rapid::{Call, Expr, FunctionCall, Program, Routine, RoutineKind, Scope, StatementKind};
use crate::resolve::{root_name, walk_statements, Move};
use std::collections::{HashMap, HashSet};

/// Functions that return the robot's position or joints now.
const READ_BACK: [(&str, &str); 3] = [
    ("CRobT", "the robot's position read by CRobT"),
    ("CJointT", "the robot's joints read by CJointT"),
    ("CPos", "the robot's position read by CPos"),
];

/// Instructions that write where the robot stood into an argument, and
/// which positional argument (0-based): the search point of the search
/// instructions (reference manual), the result of SmarTac's Search_1D.
const FOUND_POINT: [(&str, usize); 5] = [
    ("SearchL", 1),
    ("SearchC", 1),
    ("SearchJ", 1),
    ("SearchExtJ", 1),
    ("Search_1D", 0),
];

/// Why a move's target is a reading of the robot: for the report of a
/// move left unwrapped.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FromRobotReason {
    /// The datum the move's argument reads (as written there); `None`
    /// where the argument calls the reading function itself.
    pub name: Option<String>,
    /// What read it: "the search result of SearchL", "the robot's
    /// position read by CRobT".
    pub source: String,
    /// Where that reading is in the program.
    pub file: String,
    pub line: u32,
    /// The data (or FUNCs) the reading went through on its way to
    /// `name`, nearest first.
    pub through: Vec<String>,
}

impl std::fmt::Display for FromRobotReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if let Some(n) = &self.name {
            write!(f, "{n}: ")?;
        }
        write!(f, "{} at line {}", self.source, self.line)?;
        if !self.through.is_empty() {
            write!(f, " (through {})", self.through.join(", "))?;
        }
        Ok(())
    }
}

/// A datum in RAPID's scopes; names lower case.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
enum Key {
    /// A routine's own datum or parameter: (module, routine, name).
    Routine(String, String, String),
    /// A LOCAL datum of a module: (module, name).
    Module(String, String),
    /// A global datum of the task (or one no file read declares).
    Global(String),
}

/// Where a reading came from.
#[derive(Debug, Clone, PartialEq)]
struct Taint {
    source: String,
    file: usize,
    line: u32,
    through: Vec<String>,
}

/// Where an expression is evaluated: its module and routine, and the
/// statement's place (for a reading function called there).
#[derive(Debug, Clone, Copy)]
struct At<'p> {
    module: &'p str,
    routine: Option<&'p str>,
    file: usize,
    line: u32,
}

/// What takes a reading when something it is made from holds one.
#[derive(Debug)]
enum Into {
    Datum(Key),
    /// The result of the program's FUNC of this (lower-case) name.
    Func(String),
}

/// One way a reading travels, found once and followed to a fixed point.
#[derive(Debug)]
enum Flow<'p> {
    /// `into` is made from the expression `from`, read at `at`.
    Expr {
        into: Into,
        from: &'p Expr,
        at: At<'p>,
    },
    /// `into` takes what the datum `from` holds (an INOUT parameter
    /// written back to the caller's argument).
    Datum { into: Key, from: Key, name: String },
}

/// The data of a program that hold a reading of the robot.
#[derive(Debug, Default)]
pub struct FromRobot {
    files: Vec<String>,
    scopes: Scopes,
    data: HashMap<Key, Taint>,
    funcs: HashMap<String, Taint>,
}

/// Which names each routine and module declares, for [`Key`]s.
#[derive(Debug, Default)]
struct Scopes {
    /// (module, routine) → its data and parameters.
    routines: HashMap<(String, String), HashSet<String>>,
    /// module → its data, and whether each is LOCAL.
    modules: HashMap<String, HashMap<String, bool>>,
}

impl Scopes {
    fn new(program: &Program) -> Scopes {
        let mut s = Scopes::default();
        for m in &program.modules {
            let module = m.name.to_ascii_lowercase();
            let data = s.modules.entry(module.clone()).or_default();
            for d in &m.data {
                data.insert(d.name.to_ascii_lowercase(), d.scope == Some(Scope::Local));
            }
            for b in program.declaration_batches(m) {
                let local = b.scope() == Some(Scope::Local);
                for (name, _) in b.names() {
                    data.insert(name.to_ascii_lowercase(), local);
                }
            }
            for r in &m.routines {
                let own = r.data.iter().map(|d| d.name.to_ascii_lowercase());
                let params = r.params.iter().map(|p| p.name.to_ascii_lowercase());
                let key = (module.clone(), r.name.to_ascii_lowercase());
                s.routines.entry(key).or_default().extend(own.chain(params));
            }
        }
        s
    }

    /// The datum `name` means in `routine` of `module`.
    fn key(&self, module: &str, routine: Option<&str>, name: &str) -> Key {
        let (module, name) = (module.to_ascii_lowercase(), name.to_ascii_lowercase());
        if let Some(r) = routine.map(str::to_ascii_lowercase) {
            let key = (module.clone(), r);
            if self
                .routines
                .get(&key)
                .is_some_and(|own| own.contains(&name))
            {
                return Key::Routine(key.0, key.1, name);
            }
        }
        match self.modules.get(&module).and_then(|d| d.get(&name)) {
            Some(true) => Key::Module(module, name),
            _ => Key::Global(name),
        }
    }
}

/// Whether a move's arguments may call a reading function themselves
/// (a move of the fast lane's runs has names and literals only).
fn mentions_read_back(mv: &Move) -> bool {
    mv.points.iter().any(|p| p.expr.is_some())
}

impl FromRobot {
    /// Every datum of `program` that holds a reading of the robot.
    pub fn new(program: &Program) -> FromRobot {
        let mut me = FromRobot {
            files: program.files.clone(),
            scopes: Scopes::new(program),
            ..FromRobot::default()
        };
        let flows = me.flows(program);
        // Each round adds at least one datum or FUNC, or ends: at most as
        // many rounds as there are flows.
        for _ in 0..=flows.len() {
            if !me.follow(&flows) {
                break;
            }
        }
        me
    }

    /// Whether nothing of the program holds a reading.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty() && self.funcs.is_empty()
    }

    /// Why target argument `point` of `mv` is a reading of the robot, or
    /// `None` where it is not (a taught or computed target to correct).
    pub fn why(&self, mv: &Move, point: usize) -> Option<FromRobotReason> {
        // Most programs read nothing back: a million moves asked for
        // nothing.
        if self.is_empty() && !mentions_read_back(mv) {
            return None;
        }
        let p = mv.points.get(point)?;
        match (p.expr, p.name) {
            (Some(e), _) => self.why_expr(e, mv.module, mv.routine, mv.file, mv.line),
            (None, Some(n)) => self.why_name(n, mv.module, mv.routine),
            (None, None) => None,
        }
    }

    /// Why the expression `e`, written at `line` of file `file` in
    /// `routine` of `module`, is a reading of the robot.
    pub fn why_expr(
        &self,
        e: &Expr,
        module: &str,
        routine: &str,
        file: usize,
        line: u32,
    ) -> Option<FromRobotReason> {
        let at = At {
            module,
            routine: Some(routine),
            file,
            line,
        };
        let (name, t) = self.taint_of(e, at)?;
        Some(self.reason(name, t))
    }

    /// Why the datum `name`, read in `routine` of `module`, is a reading
    /// of the robot.
    pub fn why_name(&self, name: &str, module: &str, routine: &str) -> Option<FromRobotReason> {
        let t = self
            .data
            .get(&self.scopes.key(module, Some(routine), name))?;
        Some(self.reason(Some(name.to_string()), t.clone()))
    }

    fn reason(&self, name: Option<String>, t: Taint) -> FromRobotReason {
        FromRobotReason {
            name,
            source: t.source,
            file: self.files.get(t.file).cloned().unwrap_or_default(),
            line: t.line,
            through: t.through,
        }
    }

    /// The first reading `e` is made from, and the datum it reads it
    /// through (`None`: a function called in `e` itself).
    fn taint_of(&self, e: &Expr, at: At<'_>) -> Option<(Option<String>, Taint)> {
        struct Find<'f, 'p> {
            me: &'f FromRobot,
            at: At<'p>,
            found: Option<(Option<String>, Taint)>,
        }
        impl<'a> Visit<'a> for Find<'_, '_> {
            // An expression's walk: no list of statements in it.
            fn program(&self) -> Option<&'a Program> {
                None
            }
            fn visit_expr(&mut self, e: &'a Expr) {
                if self.found.is_some() {
                    return;
                }
                if let Expr::Name(n) = e {
                    let key = self.me.scopes.key(self.at.module, self.at.routine, n);
                    if let Some(t) = self.me.data.get(&key) {
                        self.found = Some((Some(n.to_string()), t.clone()));
                        return;
                    }
                }
                walk_expr(self, e);
            }
            fn visit_function_call(&mut self, c: &'a FunctionCall) {
                if self.found.is_some() {
                    return;
                }
                let read = READ_BACK
                    .iter()
                    .find(|(f, _)| f.eq_ignore_ascii_case(&c.name));
                if let Some((_, source)) = read {
                    let t = Taint {
                        source: source.to_string(),
                        file: self.at.file,
                        line: self.at.line,
                        through: Vec::new(),
                    };
                    self.found = Some((None, t));
                    return;
                }
                if let Some(t) = self.me.funcs.get(&c.name.to_ascii_lowercase()) {
                    let mut t = t.clone();
                    t.through.insert(0, c.name.to_string());
                    self.found = Some((None, t));
                    return;
                }
                walk_function_call(self, c);
            }
        }
        let mut f = Find {
            me: self,
            at,
            found: None,
        };
        f.visit_expr(e);
        f.found
    }

    /// One round over the flows: whether it found any new reading.
    fn follow(&mut self, flows: &[Flow<'_>]) -> bool {
        let mut grew = false;
        for flow in flows {
            match flow {
                Flow::Expr { into, from, at } => {
                    let taken = match into {
                        Into::Datum(k) => self.data.contains_key(k),
                        Into::Func(f) => self.funcs.contains_key(f),
                    };
                    if taken {
                        continue;
                    }
                    let Some((name, mut t)) = self.taint_of(from, *at) else {
                        continue;
                    };
                    if let Some(n) = name {
                        t.through.insert(0, n);
                    }
                    match into {
                        Into::Datum(k) => self.data.insert(k.clone(), t),
                        Into::Func(f) => self.funcs.insert(f.clone(), t),
                    };
                    grew = true;
                }
                Flow::Datum { into, from, name } => {
                    if self.data.contains_key(into) {
                        continue;
                    }
                    if let Some(t) = self.data.get(from) {
                        let mut t = t.clone();
                        t.through.insert(0, name.clone());
                        self.data.insert(into.clone(), t);
                        grew = true;
                    }
                }
            }
        }
        grew
    }

    /// Every flow of the program, and the found points of its searches
    /// (a reading at once).
    fn flows<'p>(&mut self, program: &'p Program) -> Vec<Flow<'p>> {
        let procs: HashMap<String, (&'p str, &'p Routine)> = (program.modules.iter())
            .flat_map(|m| m.routines.iter().map(move |r| (m, r)))
            .filter(|(_, r)| r.kind == RoutineKind::Proc)
            .map(|(m, r)| (r.name.to_ascii_lowercase(), (m.name.as_ref(), r)))
            .collect();
        let mut flows = Vec::new();
        for m in &program.modules {
            for d in &m.data {
                if let Some(init) = &d.init {
                    let at = At {
                        module: &m.name,
                        routine: None,
                        file: m.file,
                        line: d.pos.line,
                    };
                    let into = Into::Datum(self.scopes.key(&m.name, None, &d.name));
                    flows.push(Flow::Expr {
                        into,
                        from: init,
                        at,
                    });
                }
            }
            for r in &m.routines {
                self.routine_flows(m.file, &m.name, r, &procs, &mut flows);
            }
        }
        flows
    }

    /// The flows of one routine's declarations and statements.
    fn routine_flows<'p>(
        &mut self,
        file: usize,
        module: &'p str,
        r: &'p Routine,
        procs: &HashMap<String, (&'p str, &'p Routine)>,
        flows: &mut Vec<Flow<'p>>,
    ) {
        let at = |line: u32| At {
            module,
            routine: Some(&r.name),
            file,
            line,
        };
        for d in &r.data {
            if let Some(init) = &d.init {
                let into = Into::Datum(self.scopes.key(module, Some(&r.name), &d.name));
                let at = at(d.pos.line);
                flows.push(Flow::Expr {
                    into,
                    from: init,
                    at,
                });
            }
        }
        let bodies = [
            Some(&r.body),
            r.backward.as_ref(),
            r.undo.as_ref(),
            r.error.as_ref().map(|(_, b)| b),
        ];
        for body in bodies.into_iter().flatten() {
            walk_statements(body, &mut |s| match &s.kind {
                StatementKind::Assign { target, value } => {
                    if let Some(root) = root_name(target) {
                        let into = Into::Datum(self.scopes.key(module, Some(&r.name), root));
                        flows.push(Flow::Expr {
                            into,
                            from: value,
                            at: at(s.pos.line),
                        });
                    }
                }
                StatementKind::Return(Some(e)) if r.kind == RoutineKind::Func => {
                    flows.push(Flow::Expr {
                        into: Into::Func(r.name.to_ascii_lowercase()),
                        from: e,
                        at: at(s.pos.line),
                    });
                }
                StatementKind::Call(c) => {
                    self.found_point(c, at(s.pos.line));
                    if let Some(&(callee_module, callee)) = procs.get(&c.name.to_ascii_lowercase())
                    {
                        self.call_flows(c, at(s.pos.line), (callee_module, callee), flows);
                    }
                }
                _ => {}
            });
        }
    }

    /// A search's found point: a reading where the search stands.
    fn found_point(&mut self, c: &Call, at: At<'_>) {
        let written = FOUND_POINT
            .iter()
            .find(|(i, _)| i.eq_ignore_ascii_case(&c.name))
            .and_then(|&(_, k)| c.positional().nth(k));
        // `\SearchStop:=p` (SmarTac's searches and others): where the
        // search stopped.
        let stop = c.optional("SearchStop").and_then(|a| a.value.as_ref());
        for e in written.into_iter().chain(stop) {
            if let Some(root) = root_name(e) {
                let key = self.scopes.key(at.module, at.routine, root);
                self.data.entry(key).or_insert_with(|| Taint {
                    source: format!("the search result of {}", c.name),
                    file: at.file,
                    line: at.line,
                    through: Vec::new(),
                });
            }
        }
    }

    /// A call of one of the program's PROCs: each argument flows into its
    /// parameter, and a parameter the PROC may write (INOUT, VAR, PERS)
    /// back into the argument's datum.
    fn call_flows<'p>(
        &self,
        c: &'p Call,
        at: At<'p>,
        (module, callee): (&'p str, &'p Routine),
        flows: &mut Vec<Flow<'p>>,
    ) {
        let mut positional = callee.params.iter().filter(|p| !p.optional);
        for arg in &c.args {
            let param = match (&arg.name, arg.optional) {
                (Some(n), true) => callee
                    .params
                    .iter()
                    .find(|p| p.optional && p.name.eq_ignore_ascii_case(n)),
                (_, false) => positional.next(),
                (None, true) => None,
            };
            let (Some(param), Some(value)) = (param, &arg.value) else {
                continue;
            };
            let inside = self.scopes.key(module, Some(&callee.name), &param.name);
            let writes = param.access.as_deref().is_some_and(|a| {
                ["INOUT", "VAR", "PERS"]
                    .iter()
                    .any(|w| w.eq_ignore_ascii_case(a))
            });
            if writes {
                if let Some(root) = root_name(value) {
                    flows.push(Flow::Datum {
                        into: self.scopes.key(at.module, at.routine, root),
                        from: inside.clone(),
                        name: format!("{}'s parameter {}", callee.name, param.name),
                    });
                }
            }
            flows.push(Flow::Expr {
                into: Into::Datum(inside),
                from: value,
                at,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::resolve::each_move_instruction;

    /// For each move of `src` (in program order): its instruction, line
    /// and the reason of its last target argument, as text.
    fn reasons(src: &str) -> Vec<(String, u32, Option<String>)> {
        let program = crate::rapid::parse("t.mod", src.as_bytes()).unwrap();
        let from = FromRobot::new(&program);
        let mut out = Vec::new();
        each_move_instruction(&program, &mut |mv| {
            let last = mv.points.len().saturating_sub(1);
            let why = from.why(mv, last).map(|r| r.to_string());
            out.push((mv.instruction.to_string(), mv.line, why));
        });
        out
    }

    const HEAD: &str = "MODULE Cell\n  CONST robtarget pTaught := [[500,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n";

    #[test]
    fn a_crobt_then_an_offset_of_it() {
        // Lines worked by hand: 3 PROC, 4 VAR, 5 the reading, 6 the
        // offset, 7 and 8 the moves.
        let src = format!(
            "{HEAD}  PROC main()\n    VAR robtarget p1;\n    p1 := CRobT(\\Tool:=tool0);\n    MoveL Offs(p1, 0, 0, 20), v100, fine, tool0;\n    MoveL pTaught, v100, fine, tool0;\n  ENDPROC\nENDMODULE\n"
        );
        let r = reasons(&src);
        assert_eq!(
            r[0],
            (
                "MoveL".into(),
                6,
                Some("p1: the robot's position read by CRobT at line 5".into())
            )
        );
        // A taught target is no reading.
        assert_eq!(r[1].2, None);
    }

    #[test]
    fn a_chain_of_assignments_to_a_fixed_point() {
        // p3 is assigned from p2 before p2 is assigned from p1: the order
        // of statements does not stop the reading.
        let src = format!(
            "{HEAD}  PROC main()\n    VAR robtarget p1;\n    VAR robtarget p2;\n    VAR robtarget p3;\n    p3 := p2;\n    p2.trans := p1.trans;\n    p1 := CRobT();\n    MoveL p3, v100, fine, tool0;\n  ENDPROC\nENDMODULE\n"
        );
        let r = reasons(&src);
        assert_eq!(
            r[0].2.as_deref(),
            Some("p3: the robot's position read by CRobT at line 9 (through p2, p1)")
        );
    }

    #[test]
    fn a_search_then_a_move_to_the_found_point() {
        let src = format!(
            "{HEAD}  VAR robtarget pFound;\n  PROC main()\n    SearchL \\Stop, diPart, pFound, pTaught, v100, tool0;\n    MoveL pFound, v100, fine, tool0;\n    MoveJ RelTool(pFound, 0, 0, -50), v100, z10, tool0;\n  ENDPROC\nENDMODULE\n"
        );
        let r = reasons(&src);
        // The search moves to its ToPoint, a taught target.
        assert_eq!(r[0], ("SearchL".into(), 5, None));
        let found = Some("pFound: the search result of SearchL at line 5".to_string());
        assert_eq!(r[1].2, found);
        assert_eq!(r[2].2, found);
    }

    #[test]
    fn a_reading_in_the_argument_itself() {
        let src = format!(
            "{HEAD}  PROC main()\n    MoveL Offs(CRobT(), 0, 0, 10), v100, fine, tool0;\n    MoveAbsJ CJointT(), v100, fine, tool0;\n  ENDPROC\nENDMODULE\n"
        );
        let r = reasons(&src);
        assert_eq!(
            r[0].2.as_deref(),
            Some("the robot's position read by CRobT at line 4")
        );
        assert_eq!(
            r[1].2.as_deref(),
            Some("the robot's joints read by CJointT at line 5")
        );
    }

    #[test]
    fn a_name_reused_in_another_routine_is_another_datum() {
        // p is main's own datum, read back; pick's p is its own, taught.
        let src = format!(
            "{HEAD}  PROC main()\n    VAR robtarget p;\n    p := CRobT();\n    MoveL p, v100, fine, tool0;\n  ENDPROC\n  PROC pick()\n    VAR robtarget p;\n    p := Offs(pTaught, 0, 0, 50);\n    MoveL p, v100, fine, tool0;\n  ENDPROC\nENDMODULE\n"
        );
        let r = reasons(&src);
        assert!(r[0].2.is_some());
        assert_eq!(r[1], ("MoveL".into(), 11, None));
    }

    #[test]
    fn module_data_is_one_datum_for_every_routine() {
        let src = format!(
            "{HEAD}  VAR robtarget pHere;\n  PROC main()\n    pHere := CRobT();\n  ENDPROC\n  PROC back()\n    MoveL pHere, v100, fine, tool0;\n  ENDPROC\nENDMODULE\n"
        );
        let r = reasons(&src);
        assert_eq!(
            r[0].2.as_deref(),
            Some("pHere: the robot's position read by CRobT at line 5")
        );
    }

    #[test]
    fn global_data_is_one_datum_across_modules_and_a_local_one_hides_it() {
        let data = "MODULE Data\n  PERS robtarget pHome := [[500,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\nENDMODULE\n";
        let teach = "MODULE Teach\n  PROC here()\n    pHome := CRobT();\n  ENDPROC\nENDMODULE\n";
        let cell = "MODULE Cell\n  PROC main()\n    MoveJ pHome, v100, fine, tool0;\n  ENDPROC\nENDMODULE\n";
        let other = "MODULE Other\n  LOCAL PERS robtarget pHome := [[500,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n  PROC go()\n    MoveJ pHome, v100, fine, tool0;\n  ENDPROC\nENDMODULE\n";
        let files = [
            ("data.mod", data.as_bytes()),
            ("teach.mod", teach.as_bytes()),
            ("cell.mod", cell.as_bytes()),
            ("other.mod", other.as_bytes()),
        ];
        let program = crate::rapid::parse_files(&files).unwrap();
        let from = FromRobot::new(&program);
        let mut got = Vec::new();
        each_move_instruction(&program, &mut |mv| {
            got.push((mv.module.to_string(), from.why(mv, 0)));
        });
        let cell = &got[0];
        assert_eq!(cell.0, "Cell");
        let why = cell.1.as_ref().expect("the global pHome is read back");
        assert_eq!((why.file.as_str(), why.line), ("teach.mod", 3));
        // Other's own LOCAL pHome is another datum: taught.
        assert_eq!(got[1], ("Other".to_string(), None));
    }

    #[test]
    fn through_funcs_and_inout_parameters() {
        let src = format!(
            "{HEAD}  VAR robtarget pA;\n  VAR robtarget pB;\n  FUNC robtarget here()\n    RETURN CRobT();\n  ENDFUNC\n  PROC keep(INOUT robtarget p)\n    p := here();\n  ENDPROC\n  PROC main()\n    keep pA;\n    pB := pA;\n    MoveL pB, v100, fine, tool0;\n  ENDPROC\nENDMODULE\n"
        );
        let r = reasons(&src);
        assert_eq!(
            r[0].2.as_deref(),
            Some("pB: the robot's position read by CRobT at line 6 (through pA, keep's parameter p, here)")
        );
    }

    #[test]
    fn nothing_read_back_nothing_found() {
        let src = format!(
            "{HEAD}  PROC main()\n    VAR robtarget p;\n    p := Offs(pTaught, 0, 0, 20);\n    MoveL p, v100, fine, tool0;\n    MoveL pTaught, v100, fine, tool0;\n  ENDPROC\nENDMODULE\n"
        );
        let program = crate::rapid::parse("t.mod", src.as_bytes()).unwrap();
        assert!(FromRobot::new(&program).is_empty());
        assert!(reasons(&src).iter().all(|(_, _, why)| why.is_none()));
    }
}
