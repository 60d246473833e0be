//! The values of a program's `CONST num` declarations, and numeric
//! expressions over them: what a literal written as `[[nX,0,300],...]` or
//! `[[400,0,-300+600],...]`, or an offset `Offs(p, 0, 0, nLift)`, means
//! before the program runs.
//!
//! Only `CONST` counts: a `VAR` or `PERS` num can change at run time, so
//! an expression reading one has no static value.

use super::{BinaryOp, Expr, Program, Storage, UnaryOp};
use std::collections::HashMap;

/// Nesting allowed through constants defined by constants (a cycle, which
/// the controller refuses, ends here too).
const MAX_DEPTH: usize = 32;

/// The program's numeric constants by scope.
pub struct Constants<'p> {
    /// (module, name) → value expression, lowercase keys.
    module: HashMap<(String, String), &'p Expr>,
    /// (module, routine, name) → value expression.
    routine: HashMap<(String, String, String), &'p Expr>,
    /// name → value expression, for constants of other modules (a task's
    /// modules share their global data).
    global: HashMap<String, &'p Expr>,
}

/// Where an expression is written: its module and routine (names as
/// written; compared without case, as RAPID does).
#[derive(Debug, Clone, Copy)]
pub struct Site<'a> {
    pub module: &'a str,
    pub routine: Option<&'a str>,
}

impl<'p> Constants<'p> {
    pub fn of(program: &'p Program) -> Constants<'p> {
        let mut c = Constants {
            module: HashMap::new(),
            routine: HashMap::new(),
            global: HashMap::new(),
        };
        let is_num_const = |d: &&super::DataDecl| {
            d.storage == Storage::Const
                && d.type_name.eq_ignore_ascii_case("num")
                && d.dims.is_empty()
        };
        for m in &program.modules {
            let module = m.name.to_lowercase();
            for d in m.data.iter().filter(is_num_const) {
                let Some(init) = &d.init else { continue };
                let name = d.name.to_lowercase();
                c.module.insert((module.clone(), name.clone()), init);
                if d.scope.is_none() {
                    c.global.entry(name).or_insert(init);
                }
            }
            for r in &m.routines {
                for d in r.data.iter().filter(is_num_const) {
                    let Some(init) = &d.init else { continue };
                    let key = (module.clone(), r.name.to_lowercase(), d.name.to_lowercase());
                    c.routine.insert(key, init);
                }
            }
        }
        c
    }

    /// The value of a numeric expression, or `None` when it reads anything
    /// that only the run knows (a variable, a function, a string).
    pub fn num(&self, e: &Expr, scope: Site) -> Option<f64> {
        self.eval(e, scope, 0).filter(|v| v.is_finite())
    }

    fn lookup(&self, name: &str, scope: Site) -> Option<&'p Expr> {
        let name = name.to_lowercase();
        let module = scope.module.to_lowercase();
        if let Some(r) = scope.routine {
            let key = (module.clone(), r.to_lowercase(), name.clone());
            if let Some(e) = self.routine.get(&key) {
                return Some(e);
            }
        }
        self.module
            .get(&(module, name.clone()))
            .or_else(|| self.global.get(&name))
            .copied()
    }

    fn eval(&self, e: &Expr, scope: Site, depth: usize) -> Option<f64> {
        if depth > MAX_DEPTH {
            return None;
        }
        match e {
            Expr::Num(n) => Some(n.value),
            Expr::Unary(UnaryOp::Neg, x) => self.eval(x, scope, depth + 1).map(|v| -v),
            Expr::Unary(UnaryOp::Plus, x) => self.eval(x, scope, depth + 1),
            Expr::Name(n) => {
                let def = self.lookup(n, scope)?;
                // A constant is read in its own declaration's scope: a
                // module constant cannot see a routine's.
                let outer = Site {
                    module: scope.module,
                    routine: None,
                };
                self.eval(def, outer, depth + 1)
            }
            Expr::Binary(b) => {
                let (op, l, r) = b.as_ref();
                let a = self.eval(l, scope, depth + 1)?;
                let b = self.eval(r, scope, depth + 1)?;
                match op {
                    BinaryOp::Add => Some(a + b),
                    BinaryOp::Sub => Some(a - b),
                    BinaryOp::Mul => Some(a * b),
                    BinaryOp::Div if b != 0.0 => Some(a / b),
                    // DIV and MOD are integer operations in RAPID.
                    BinaryOp::IntDiv if b != 0.0 && a.fract() == 0.0 && b.fract() == 0.0 => {
                        Some((a / b).trunc())
                    }
                    BinaryOp::Mod if b != 0.0 && a.fract() == 0.0 && b.fract() == 0.0 => {
                        Some(a % b)
                    }
                    _ => None,
                }
            }
            _ => None,
        }
    }
}

/// The names an expression reads (for messages: `nX`).
pub fn names_read(e: &Expr) -> Vec<String> {
    use super::visit::{walk_expr, Visit};
    struct Names(Vec<String>);
    impl<'a> Visit<'a> for Names {
        // An expression's walk: no list of statements in it.
        fn program(&self) -> Option<&'a crate::rapid::Program> {
            None
        }
        fn visit_expr(&mut self, e: &'a Expr) {
            if let Expr::Name(n) = e {
                if !self.0.iter().any(|x| x.eq_ignore_ascii_case(n)) {
                    self.0.push(n.to_string());
                }
            }
            walk_expr(self, e);
        }
    }
    let mut names = Names(Vec::new());
    names.visit_expr(e);
    names.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn program(src: &str) -> Program {
        crate::rapid::parse("t.mod", src.as_bytes()).unwrap()
    }

    fn init<'p>(p: &'p Program, name: &str) -> &'p Expr {
        p.modules[0]
            .data
            .iter()
            .find(|d| d.name == name)
            .and_then(|d| d.init.as_ref())
            .unwrap()
    }

    #[test]
    fn constants_through_constants_and_arithmetic() {
        let p = program(
            "MODULE M\n CONST num a := 400;\n CONST num b := a - 2*50 + 8 DIV 3;\n VAR num v := 1;\n CONST num c := v + 1;\nENDMODULE\n",
        );
        let c = Constants::of(&p);
        let s = Site {
            module: "m",
            routine: None,
        };
        assert_eq!(c.num(init(&p, "b"), s), Some(302.0));
        // A VAR can change at run time: no static value.
        assert_eq!(c.num(init(&p, "c"), s), None);
    }

    #[test]
    fn a_cycle_has_no_value() {
        let p = program("MODULE M\n CONST num a := b;\n CONST num b := a;\nENDMODULE\n");
        let c = Constants::of(&p);
        let s = Site {
            module: "M",
            routine: None,
        };
        assert_eq!(c.num(init(&p, "a"), s), None);
    }
}
