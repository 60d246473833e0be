//! Expressions: literals, data, components and elements, operators (on
//! num, bool, string, and the record arithmetic of pos and orient) and
//! calls of FUNCs and built-in functions.

use super::bounds::{STACK_RED_ZONE, STACK_SEGMENT};
use super::kin;
use super::place::Slot;
use super::raised::ERR_DIVZERO;
use super::state::{Interp, Precision};
use super::value::Value;
use crate::error::{Error, Result};
use crate::rapid::compare;
use crate::rapid::{BinaryOp, Expr, FunctionCall, RoutineKind, UnaryOp};
use std::collections::HashMap;

impl Interp {
    pub(super) fn eval(&mut self, e: &Expr) -> Result<Value> {
        self.ops.expressions += 1;
        let mut v = stacker::maybe_grow(STACK_RED_ZONE, STACK_SEGMENT, || self.eval_node(e))?;
        if self.precision == Precision::Single {
            // The controller computes num in single precision: each
            // operation's result is one.
            v.to_single();
        }
        Ok(v)
    }

    fn eval_node(&mut self, e: &Expr) -> Result<Value> {
        Ok(match e {
            Expr::Num(n) => Value::Num(n.value),
            Expr::Bool(b) => Value::Bool(*b),
            Expr::Str(s) => Value::Str(s.to_string()),
            Expr::Name(_) => {
                let p = self.place_of(e)?;
                self.read(&p)?.clone()
            }
            Expr::Component(c) if !rooted_in_data(&c.0) => {
                let (base, field) = c.as_ref();
                match self.eval(base)? {
                    Value::Rec(ty, mut f) => {
                        let i = self.types.field(&ty, field).ok_or_else(|| {
                            Error::input(format!("{ty} has no component `{field}`"))
                        })?;
                        f.swap_remove(i)
                    }
                    v => return Err(Error::input(format!("`.{field}` of a {}", v.kind()))),
                }
            }
            Expr::Component(_) | Expr::Index(_) => {
                let p = self.place_of(e)?;
                self.read(&p)?.clone()
            }
            Expr::Aggregate(a) => {
                let mut items = Vec::with_capacity(a.items.len());
                for it in &a.items {
                    items.push(self.eval(it)?);
                }
                Value::Arr(items)
            }
            Expr::Unary(op, x) => {
                let v = self.eval(x)?;
                unary(*op, v)?
            }
            Expr::Binary(b) => {
                let (op, l, r) = b.as_ref();
                let l = self.eval(l)?;
                // RAPID evaluates both sides (no short cut), as here.
                let r = self.eval(r)?;
                if matches!(op, BinaryOp::Div | BinaryOp::IntDiv | BinaryOp::Mod)
                    && r == Value::Num(0.0)
                {
                    return Err(self.raise(ERR_DIVZERO, Error::input("division by zero")));
                }
                binary(*op, l, r)?
            }
            Expr::Target(i) => {
                let t =
                    self.program.targets().get(*i).ok_or_else(|| {
                        Error::input("a robtarget literal the program does not hold")
                    })?;
                let v = t
                    .value
                    .as_ref()
                    .ok_or_else(|| Error::input(format!("robtarget `{}` has no numbers", t.id)))?;
                self.types
                    .coerce_to(kin::literal_robtarget(v), "robtarget")?
            }
            Expr::JointTarget(i) => {
                let j = self.program.jointtargets().get(*i).ok_or_else(|| {
                    Error::input("a jointtarget literal the program does not hold")
                })?;
                let v = kin::literal_jointtarget(j);
                self.types.coerce_to(v, "jointtarget")?
            }
            Expr::Call(c) => self.call_function(c)?,
            Expr::Placeholder(p) => return Err(self.unsupported(format!("the placeholder {p}"))),
        })
    }

    /// A function call: `Present`, a FUNC of the program, a built-in.
    fn call_function(&mut self, c: &FunctionCall) -> Result<Value> {
        if self.routines.contains_key(&c.name.to_ascii_lowercase()) {
            let v = self.call_routine(&c.name, &c.args, RoutineKind::Func)?;
            return v.ok_or_else(|| Error::input(format!("`{}` returned no value", c.name)));
        }
        self.ops.builtins += 1;
        match self.builtin(c)? {
            Some(v) => Ok(v),
            None => Err(self.unsupported(format!("the function `{}`", c.name))),
        }
    }

    /// Calls routine `name` of `kind` from the running routine.
    pub(super) fn call_routine(
        &mut self,
        name: &str,
        args: &[crate::rapid::Arg],
        kind: RoutineKind,
    ) -> Result<Option<Value>> {
        let from = self.frames.last().map(|f| f.module);
        let (m, k) = self.routine_named(name, from)?;
        let program = self.program.clone();
        let routine = &program.modules[m].routines[k];
        if routine.kind != kind {
            return Err(Error::input(format!("`{name}` is not a {kind:?}")));
        }
        let vars = self.bind(routine, args)?;
        let at = self.at;
        let v = self.run_routine(m, k, vars)?;
        self.at = at;
        Ok(v)
    }

    /// The parameters of `routine` bound to the arguments of a call made
    /// in the running routine.
    pub(super) fn bind(
        &mut self,
        routine: &crate::rapid::Routine,
        args: &[crate::rapid::Arg],
    ) -> Result<HashMap<String, Slot>> {
        let mut vars = HashMap::new();
        let mut positional = args.iter().filter(|a| !a.optional);
        for p in &routine.params {
            let arg = if p.optional {
                args.iter().find(|a| {
                    a.optional
                        && a.name
                            .as_deref()
                            .is_some_and(|n| n.eq_ignore_ascii_case(&p.name))
                })
            } else {
                Some(positional.next().ok_or_else(|| {
                    Error::input(format!("`{}` needs argument `{}`", routine.name, p.name))
                })?)
            };
            let Some(arg) = arg else { continue };
            // An optional parameter passed on that its caller did not get
            // (`\WObj?W`) is absent here too: `Present` follows the
            // caller's.
            if p.optional && arg.value.as_ref().is_some_and(|e| self.absent_argument(e)) {
                continue;
            }
            let key = p.name.to_ascii_lowercase();
            let by_ref = p
                .access
                .as_deref()
                .is_some_and(|a| !a.eq_ignore_ascii_case("IN"));
            let slot = match &arg.value {
                None => Slot::Value(Value::Bool(true)),
                Some(e) if by_ref => Slot::Ref(self.place_of(e)?),
                Some(e) => {
                    let v = self.eval(e)?;
                    Slot::Value(self.param_value(p, v)?)
                }
            };
            vars.insert(key, slot);
        }
        if positional.next().is_some() {
            return Err(Error::input(format!(
                "too many arguments to `{}`",
                routine.name
            )));
        }
        Ok(vars)
    }

    /// Whether `e` names an optional parameter of the running routine that
    /// its caller left out (an argument passed on as `\WObj?W`).
    pub(super) fn absent_argument(&self, e: &Expr) -> bool {
        e.as_name().is_some_and(|n| self.absent_optional(n))
    }

    /// Whether `name` is an optional parameter of the running routine that
    /// its caller left out.
    pub(super) fn absent_optional(&self, name: &str) -> bool {
        let Some(f) = self.frames.last() else {
            return false;
        };
        if f.vars.contains_key(&name.to_ascii_lowercase()) {
            return false;
        }
        self.routine_of_frame().is_some_and(|r| {
            r.params
                .iter()
                .any(|p| p.optional && p.name.eq_ignore_ascii_case(name))
        })
    }
}

/// Whether an expression's value is read through the data it names
/// (`a.b{i}.c`), not computed (`F(x).trans`).
fn rooted_in_data(e: &Expr) -> bool {
    match e {
        Expr::Name(_) => true,
        Expr::Component(c) => rooted_in_data(&c.0),
        Expr::Index(x) => rooted_in_data(&x.0),
        _ => false,
    }
}

fn unary(op: UnaryOp, v: Value) -> Result<Value> {
    Ok(match (op, v) {
        (UnaryOp::Neg, Value::Num(x)) => Value::Num(-x),
        (UnaryOp::Plus, Value::Num(x)) => Value::Num(x),
        (UnaryOp::Not, Value::Bool(b)) => Value::Bool(!b),
        (UnaryOp::Neg, Value::Rec(t, f)) if &*t == "pos" => Value::Rec(t, neg_all(f)),
        (op, v) => return Err(Error::input(format!("{op:?} of a {}", v.kind()))),
    })
}

fn neg_all(f: Vec<Value>) -> Vec<Value> {
    f.into_iter()
        .map(|v| match v {
            Value::Num(x) => Value::Num(-x),
            v => v,
        })
        .collect()
}

fn nums(f: &[Value]) -> Option<Vec<f64>> {
    f.iter().map(Value::num).collect()
}

fn pos_of(t: &str, f: &[Value]) -> Option<[f64; 3]> {
    if t != "pos" {
        return None;
    }
    let n = nums(f)?;
    Some([n[0], n[1], n[2]])
}

fn pos(p: [f64; 3]) -> Value {
    Value::Rec("pos".into(), p.iter().map(|&x| Value::Num(x)).collect())
}

/// An integer operand of `DIV` and `MOD` (RAPID refuses others).
fn int(v: f64) -> Result<f64> {
    if v.fract() == 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(Error::input(format!(
            "DIV or MOD of {v}, which is not an integer"
        )))
    }
}

fn binary(op: BinaryOp, l: Value, r: Value) -> Result<Value> {
    use BinaryOp::*;
    Ok(match (op, &l, &r) {
        (_, Value::Num(a), Value::Num(b)) => {
            let (a, b) = (*a, *b);
            match op {
                Add => Value::Num(a + b),
                Sub => Value::Num(a - b),
                Mul => Value::Num(a * b),
                Div | IntDiv | Mod if b == 0.0 => return Err(Error::input("division by zero")),
                Div => Value::Num(a / b),
                // Truncated toward zero, as RAPID's DIV and MOD.
                IntDiv => Value::Num((int(a)? / int(b)?).trunc()),
                Mod => Value::Num(int(a)? % int(b)?),
                op => Value::Bool(
                    compare(op, a, b).ok_or_else(|| Error::input(format!("{op:?} of two nums")))?,
                ),
            }
        }
        (And, Value::Bool(a), Value::Bool(b)) => Value::Bool(*a && *b),
        (Or, Value::Bool(a), Value::Bool(b)) => Value::Bool(*a || *b),
        (Xor, Value::Bool(a), Value::Bool(b)) => Value::Bool(a != b),
        (Add, Value::Str(a), Value::Str(b)) => Value::Str(format!("{a}{b}")),
        (Eq, _, _) => Value::Bool(l == r),
        (Ne, _, _) => Value::Bool(l != r),
        (Add | Sub, Value::Rec(ta, fa), Value::Rec(tb, fb)) => {
            match (pos_of(ta, fa), pos_of(tb, fb)) {
                (Some(a), Some(b)) => {
                    let s = if op == Add { 1.0 } else { -1.0 };
                    pos(std::array::from_fn(|i| a[i] + s * b[i]))
                }
                _ => return Err(Error::input(format!("{op:?} of a {ta} and a {tb}"))),
            }
        }
        (Mul, Value::Num(k), Value::Rec(t, f)) | (Mul, Value::Rec(t, f), Value::Num(k)) => {
            match pos_of(t, f) {
                Some(p) => pos(p.map(|x| k * x)),
                None => return Err(Error::input(format!("a num times a {t}"))),
            }
        }
        (Mul, Value::Rec(ta, fa), Value::Rec(tb, fb)) if &**ta == "orient" && &**tb == "orient" => {
            let (a, b) = (
                nums(fa).ok_or_else(|| Error::input("an orient without numbers"))?,
                nums(fb).ok_or_else(|| Error::input("an orient without numbers"))?,
            );
            let qa = nalgebra::Quaternion::new(a[0], a[1], a[2], a[3]);
            let qb = nalgebra::Quaternion::new(b[0], b[1], b[2], b[3]);
            let q = qa * qb;
            Value::Rec(
                "orient".into(),
                [q.w, q.i, q.j, q.k]
                    .iter()
                    .map(|&x| Value::Num(x))
                    .collect(),
            )
        }
        _ => {
            return Err(Error::input(format!(
                "{op:?} of a {} and a {}",
                l.kind(),
                r.kind()
            )))
        }
    })
}
