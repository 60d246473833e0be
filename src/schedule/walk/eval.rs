//! Expressions and values in the walk: names, data, record paths,
//! functions (Offs, RelTool, CRobT, user FUNCs) as far as timing needs.

use super::decls::Decl;
use super::value::{Flow, Rob, Value};
use super::walker::{with_lower, FastMap, Frame, Walker};
use crate::error::Result;
use crate::rapid::compare;
use crate::rapid::{
    self, BinaryOp, DataDecl, Expr, FunctionCall, NoCase, Routine, RoutineKind, UnaryOp,
};
use crate::resolve::target_pose;
use crate::robot::frames::target_of_flange;
use crate::schedule::bounds::{STACK_RED_ZONE, STACK_SEGMENT};

impl<'p> Walker<'p> {
    pub(super) fn eval(&mut self, e: &Expr, frame: &mut Frame<'p>) -> Result<Value> {
        stacker::maybe_grow(STACK_RED_ZONE, STACK_SEGMENT, || self.eval_inner(e, frame))
    }

    pub(super) fn eval_inner(&mut self, e: &Expr, frame: &mut Frame<'p>) -> Result<Value> {
        Ok(match e {
            Expr::Num(n) => Value::Num(n.value),
            Expr::Bool(b) => Value::Bool(*b),
            Expr::Str(s) => Value::Str(s.to_string()),
            Expr::Placeholder(_) => Value::Unknown,
            Expr::Target(i) => self.target_value(*i)?,
            Expr::JointTarget(i) => self.joint_value(*i),
            Expr::Name(n) => self.name_value(n, frame)?,
            Expr::Index(b) => match self.element_of(b, frame, None)? {
                Some(i) => self.target_value(i)?,
                None => self.by_path(e, frame)?,
            },
            Expr::Component(_) => self.by_path(e, frame)?,
            Expr::Aggregate(a) => {
                let mut items = Vec::with_capacity(a.items.len());
                for it in &a.items {
                    items.push(self.eval(it, frame)?);
                }
                Value::Agg(items)
            }
            Expr::Unary(op, x) => {
                let v = self.eval(x, frame)?;
                match (op, v) {
                    (UnaryOp::Neg, Value::Num(v)) => Value::Num(-v),
                    (UnaryOp::Plus, Value::Num(v)) => Value::Num(v),
                    (UnaryOp::Not, Value::Bool(b)) => Value::Bool(!b),
                    _ => Value::Unknown,
                }
            }
            Expr::Binary(b) => {
                let (op, l, r) = b.as_ref();
                let l = self.eval(l, frame)?;
                let r = self.eval(r, frame)?;
                binary(*op, &l, &r)
            }
            Expr::Call(c) => self.call_value(c, frame)?,
        })
    }

    /// The value of the data an access path names (`arr{2}`, `p.trans`).
    fn by_path(&mut self, e: &Expr, frame: &mut Frame<'p>) -> Result<Value> {
        Ok(match self.path_of(e, frame)? {
            Some(path) => {
                let routine = frame.routine.map(|r| &*r.name);
                self.path_value(&path, (frame.module, routine))?
            }
            None => Value::Unknown,
        })
    }

    /// The target number of `arr{k}`, an element of a declared
    /// one-dimensional robtarget array with numbers, found through the
    /// array's declaration (the routine's, the module's, the task's, as a
    /// plain name is found) rather than by building and looking up the
    /// element's identifier: a FOR loop over an array of a million targets
    /// spent most of its walk making and hashing `pScan{k}`. `None` where
    /// the path does not name such an element (the identifier's lookup
    /// decides those). `settled`: where the move statement keeps the
    /// array's declaration (see [`settled`]), taken from there where kept.
    pub(super) fn element_of(
        &mut self,
        (base, index): &(Expr, Vec<Expr>),
        frame: &mut Frame<'p>,
        settled: Option<&mut Option<Option<&'p DataDecl>>>,
    ) -> Result<Option<usize>> {
        let (Expr::Name(name), [k]) = (base, index.as_slice()) else {
            return Ok(None);
        };
        let decl = match settled {
            Some(Some(d)) => *d,
            Some(slot) => *slot.insert(self.array_decl(name, frame)),
            None => self.array_decl(name, frame),
        };
        let Some(d) = decl else {
            return Ok(None);
        };
        let Some(k) = self.eval(k, frame)?.num() else {
            return Ok(None);
        };
        if k.fract() != 0.0 || k < 1.0 {
            return Ok(None);
        }
        // `k` is a whole number of at least 1 (below 2^53 as a float).
        let k = k as usize - 1;
        // An array's literals the fast lane holds: its elements' numbers,
        // its value not made.
        let element = match (self.program.elements_of(d), &d.init) {
            (Some(range), _) => (k < range.len()).then(|| range.start + k),
            (None, Some(Expr::Aggregate(a))) => match a.items.get(k) {
                Some(Expr::Target(i)) => Some(*i),
                _ => None,
            },
            _ => None,
        };
        let element = element.filter(|&i| self.program.targets().has_value(i));
        debug_assert!(
            element.is_none() || self.same_as_by_identifier(base, index, frame, element),
            "the element of {name} found by its declaration is not the one its identifier names"
        );
        Ok(element)
    }

    /// Whether looking `base{index}` up by its identifier finds target
    /// `element` (what [`Self::element_of`] is checked against in debug
    /// builds, on every walk the tests make).
    fn same_as_by_identifier(
        &mut self,
        base: &Expr,
        index: &[Expr],
        frame: &mut Frame<'p>,
        element: Option<usize>,
    ) -> bool {
        let e = Expr::Index(Box::new((base.clone(), index.to_vec())));
        match self.by_path(&e, frame) {
            Ok(Value::Rob(r)) => r.id == element,
            // Numbers that make no pose (a robconf not whole): the error
            // of the same target, found either way.
            Err(by_id) => element.is_some_and(|i| {
                (self.target_value(i).err())
                    .is_some_and(|e| format!("{e:?}") == format!("{by_id:?}"))
            }),
            _ => false,
        }
    }

    /// The declaration of the one-dimensional robtarget array `name`
    /// where a plain name is looked up ([`Self::name_value`]), unless a
    /// variable of the routine or a value the walk assigned stands for it.
    fn array_decl(&self, name: &str, frame: &Frame<'p>) -> Option<&'p DataDecl> {
        let shadowed = |key: &str| frame.vars.contains_key(key) || self.globals.contains_key(key);
        if with_lower(name, shadowed) {
            return None;
        }
        let decl = match frame
            .routine
            .and_then(|r| r.data.iter().find(|d| d.name.eq_ignore_ascii_case(name)))
        {
            Some(d) => d,
            None => match self.module_decl(name, frame.module)? {
                (_, Decl::Tree(d)) => d,
                (_, Decl::Run { .. }) => return None,
            },
        };
        (decl.type_name.eq_ignore_ascii_case("robtarget") && decl.dims.len() == 1).then_some(decl)
    }

    pub(super) fn target_value(&self, i: usize) -> Result<Value> {
        if let Some((pose, conf)) = self.poses.get(i) {
            return Ok(Value::Rob(Box::new(Rob {
                pose,
                conf,
                id: Some(i),
                derived: None,
                bases: Vec::new(),
            })));
        }
        // A target of a run is read into one slot, not made anew for every
        // move (a million moves made a million targets).
        let targets = self.program.targets();
        let mut slot = self.slot.borrow_mut();
        let t: &crate::rapid::Target = match targets.one_by_one(i) {
            Some(t) => t,
            None if targets.fill(i, &mut slot) => &slot,
            None => return Ok(Value::Unknown),
        };
        Ok(match target_pose(self.program, t)? {
            Some((pose, conf)) => Value::Rob(Box::new(Rob {
                pose,
                conf,
                id: Some(i),
                derived: None,
                bases: Vec::new(),
            })),
            None => Value::Unknown,
        })
    }

    pub(super) fn joint_value(&self, i: usize) -> Value {
        match self.program.jointtargets().get(i) {
            Some(j) => Value::Joint(Box::new((
                j.robax.each_ref().map(|n| n.value.to_radians()),
                Some(i),
            ))),
            None => Value::Unknown,
        }
    }

    /// `arr{2}.pos` with its indices evaluated, or `None` where an index is
    /// not known or the root is a routine's own variable.
    pub(super) fn path_of(&mut self, e: &Expr, frame: &mut Frame<'p>) -> Result<Option<String>> {
        Ok(match e {
            Expr::Name(n) => {
                if frame.vars.contains_key(&n.to_ascii_lowercase()) {
                    None
                } else {
                    Some(n.to_string())
                }
            }
            Expr::Index(b) => {
                let (base, idx) = b.as_ref();
                let Some(base) = self.path_of(base, frame)? else {
                    return Ok(None);
                };
                let mut parts = Vec::new();
                for i in idx {
                    match self.eval(i, frame)?.num() {
                        Some(v) if v.fract() == 0.0 && v.abs() < 1e12 => {
                            parts.push((v as i64).to_string())
                        }
                        _ => return Ok(None),
                    }
                }
                Some(format!("{base}{{{}}}", parts.join(",")))
            }
            Expr::Component(b) => {
                let (base, field) = b.as_ref();
                self.path_of(base, frame)?.map(|p| format!("{p}.{field}"))
            }
            _ => None,
        })
    }

    /// The target or jointtarget with this path, seen from `module`.
    /// The value of the target an access path names in `routine` of
    /// `module`: the routine's own data first (`r1/pA` where `pA` is
    /// declared elsewhere too), then the module's, then the task's.
    pub(super) fn path_value(
        &mut self,
        path: &str,
        (module, routine): (usize, Option<&str>),
    ) -> Result<Value> {
        let lower = path.to_ascii_lowercase();
        let module_name = match self.program.modules.get(module) {
            Some(m) if self.ids_qualified => m.name.to_ascii_lowercase(),
            _ => String::new(),
        };
        // Scoped and qualified keys only where some id has them: this runs
        // for every move by name.
        let own = routine
            .filter(|_| self.ids_scoped)
            .map(|r| format!("{}/{lower}", r.to_ascii_lowercase()));
        let own_qualified = own
            .as_ref()
            .filter(|_| self.ids_qualified)
            .map(|o| format!("{module_name}:{o}"));
        let qualified = self.ids_qualified.then(|| format!("{module_name}:{lower}"));
        let candidates = || {
            own.iter()
                .chain(&own_qualified)
                .chain(&qualified)
                .chain([&lower])
        };
        let hit = candidates().find_map(|k| self.target_ids.get(k));
        if let Some(i) = hit {
            // Whether it has numbers, without reading them: the value
            // reads them next.
            if self.program.targets().has_value(i) {
                return self.target_value(i);
            }
        }
        let jhit = candidates().find_map(|k| self.joint_ids.get(k)).copied();
        if let Some(i) = jhit {
            return Ok(self.joint_value(i));
        }
        Ok(Value::Unknown)
    }

    pub(super) fn name_value(&mut self, name: &str, frame: &mut Frame<'p>) -> Result<Value> {
        // Lowered on the stack: a FOR loop's variable is read at every
        // turn.
        if let Some(v) = with_lower(name, |key| frame.vars.get(key).cloned()) {
            return Ok(v);
        }
        if let Some(r) = frame.routine {
            if let Some(d) = r.data.iter().find(|d| d.name.eq_ignore_ascii_case(name)) {
                return self.decl_value(frame.module, Some(r), d);
            }
        }
        let global = with_lower(name, |key| {
            self.globals.get(key).cloned().or(match key {
                "true" => Some(Value::Bool(true)),
                "false" => Some(Value::Bool(false)),
                _ => None,
            })
        });
        if let Some(v) = global {
            return Ok(v);
        }
        match self.module_decl(name, frame.module) {
            Some((m, Decl::Tree(d))) => self.decl_value(m, None, d),
            Some((_, Decl::Run { target, .. })) => self.target_value(target),
            None => Ok(Value::Ref(name.to_string())),
        }
    }

    /// The module data `name` names, seen from module `module`: that
    /// module's own, else a task-wide one (not LOCAL elsewhere).
    fn module_decl(&self, name: &str, module: usize) -> Option<(usize, Decl<'p>)> {
        // The declaration after the last one found, asked first: a
        // RobotStudio export moves to its targets in the order it
        // declares them, and the table's answer is a cache miss or two
        // (most of walking a million moves by name).
        let guess = self.next_decl.get();
        if let Some(found) = self.guessed_decl(guess, name, module) {
            self.next_decl.set(guess + 1);
            return found;
        }
        let list = self.decls.get(&NoCase(name.as_bytes()))?;
        let found = list
            .iter()
            .find(|(m, _)| *m == module)
            .or_else(|| list.iter().find(|(_, d)| !d.local()))
            .copied();
        if let Some((_, Decl::Run { target, .. })) = found {
            self.next_decl.set(target.saturating_add(1));
        }
        found
    }

    /// What [`Self::module_decl`] answers for `name` from `module`, where
    /// target `t` is a declaration of a run named `name` and the only
    /// declaration of that name (the table's list is that one): `None`
    /// where it is not.
    fn guessed_decl(
        &self,
        t: usize,
        name: &str,
        module: usize,
    ) -> Option<Option<(usize, Decl<'p>)>> {
        if t == usize::MAX || self.shadowed.contains(&t) {
            return None;
        }
        let at = self
            .run_decls
            .partition_point(|r| r.first <= t)
            .checked_sub(1)?;
        let r = *self.run_decls.get(at)?;
        if t >= r.first + r.len {
            return None;
        }
        let written = r.batch.name(t - r.first)?;
        if !written.eq_ignore_ascii_case(name) {
            return None;
        }
        let d = Decl::Run {
            local: r.local,
            target: t,
        };
        Some((r.module == module || !r.local).then_some((r.module, d)))
    }

    pub(super) fn decl_value(
        &mut self,
        module: usize,
        routine: Option<&'p Routine>,
        d: &'p DataDecl,
    ) -> Result<Value> {
        let ty = d.type_name.to_ascii_lowercase();
        match ty.as_str() {
            "robtarget" | "jointtarget" if d.dims.is_empty() => {
                let v = self.path_value(&d.name, (module, routine.map(|r| &*r.name)))?;
                if !matches!(v, Value::Unknown) {
                    return Ok(v);
                }
                // A declared derived target: evaluate its expression.
                if d.storage == rapid::Storage::Const {
                    if let Some(init) = &d.init {
                        return self.eval_decl(module, routine, d, init);
                    }
                }
                Ok(Value::Unknown)
            }
            "num" | "dnum" | "bool" | "string" if d.storage == rapid::Storage::Const => {
                match &d.init {
                    Some(init) if d.dims.is_empty() => self.eval_decl(module, routine, d, init),
                    _ => Ok(Value::Unknown),
                }
            }
            "num" | "dnum" | "bool" | "string" | "robtarget" | "jointtarget" => Ok(Value::Unknown),
            _ => Ok(Value::Ref(d.name.clone())),
        }
    }

    pub(super) fn eval_decl(
        &mut self,
        module: usize,
        routine: Option<&'p Routine>,
        d: &DataDecl,
        init: &Expr,
    ) -> Result<Value> {
        let key = format!("{module}:{}", d.name.to_ascii_lowercase());
        if !self.evaluating.insert(key.clone()) {
            return Ok(Value::Unknown);
        }
        let mut f = Frame {
            module,
            routine,
            vars: FastMap::default(),
        };
        let v = self.eval(init, &mut f);
        self.evaluating.remove(&key);
        v
    }

    pub(super) fn call_value(&mut self, c: &FunctionCall, frame: &mut Frame<'p>) -> Result<Value> {
        let name = c.name.to_ascii_lowercase();
        let positional: Vec<&Expr> = c.positional().collect();
        let file = self.program.modules.get(frame.module).map_or(0, |m| m.file);
        let derived = self.derived_at.get(&(file, c.span.start)).copied();
        match name.as_str() {
            "offs" | "reltool" => self.derived_value(c, &name, derived, frame),
            "crobt" => self.current_target(c, derived, frame),
            "cjointt" => Ok(match self.current_joints() {
                Some(q) => Value::Joint(Box::new((q, None))),
                None => Value::Unknown,
            }),
            "present" => Ok(match positional.first().and_then(|e| e.as_name()) {
                Some(n) => {
                    if frame.vars.contains_key(&n.to_ascii_lowercase()) {
                        Value::Bool(true)
                    } else if frame.routine.is_some_and(|r| {
                        r.params
                            .iter()
                            .any(|p| p.optional && p.name.eq_ignore_ascii_case(n))
                    }) {
                        Value::Bool(false)
                    } else {
                        Value::Unknown
                    }
                }
                None => Value::Unknown,
            }),
            "dim" => self.dim_value(&positional, frame),
            "abs" | "sqrt" | "round" | "trunc" | "sin" | "cos" | "tan" => {
                let x = match positional.first() {
                    Some(e) => self.eval(e, frame)?.num(),
                    None => None,
                };
                Ok(match x {
                    Some(x) => Value::Num(match name.as_str() {
                        "abs" => x.abs(),
                        "sqrt" => x.sqrt(),
                        "round" => x.round(),
                        "trunc" => x.trunc(),
                        "sin" => x.to_radians().sin(),
                        "cos" => x.to_radians().cos(),
                        _ => x.to_radians().tan(),
                    }),
                    None => Value::Unknown,
                })
            }
            _ => match self.find_routine(frame.module, &c.name) {
                Some((mi, r)) if r.kind == RoutineKind::Func => {
                    self.func_value(mi, r, c, derived, frame)
                }
                _ => Ok(Value::Unknown),
            },
        }
    }

    /// `Offs` and `RelTool` of a robtarget the walk follows: the pose
    /// moved, its bases kept, the derived target it is (by its place).
    fn derived_value(
        &mut self,
        c: &FunctionCall,
        name: &str,
        derived: Option<usize>,
        frame: &mut Frame<'p>,
    ) -> Result<Value> {
        let positional: Vec<&Expr> = c.positional().collect();
        let optional = |n: &str| optional(c, n);
        let mut vals = Vec::new();
        for e in &positional {
            vals.push(self.eval(e, frame)?);
        }
        let (Some(Value::Rob(p)), Some(dx), Some(dy), Some(dz)) = (
            vals.first(),
            vals.get(1).and_then(Value::num),
            vals.get(2).and_then(Value::num),
            vals.get(3).and_then(Value::num),
        ) else {
            return Ok(Value::Unknown);
        };
        let pose = if name == "offs" {
            rapid::builtins::offs(&p.pose, [dx, dy, dz])
        } else {
            let mut rot = [0.0; 3];
            for (k, axis) in ["Rx", "Ry", "Rz"].iter().enumerate() {
                if let Some(a) = optional(axis).and_then(|a| a.value.as_ref()) {
                    match self.eval(a, frame)?.num() {
                        Some(v) => rot[k] = v,
                        None => return Ok(Value::Unknown),
                    }
                }
            }
            rapid::builtins::reltool(&p.pose, [dx, dy, dz], rot)
        };
        let bases = match p.id {
            Some(i) => vec![i],
            None => p.bases.clone(),
        };
        Ok(Value::Rob(Box::new(Rob {
            pose,
            conf: p.conf,
            id: None,
            derived,
            bases,
        })))
    }

    /// `CRobT`: the robot's TCP where the walk left it, in the tool and
    /// work object named.
    fn current_target(
        &mut self,
        c: &FunctionCall,
        derived: Option<usize>,
        frame: &mut Frame<'p>,
    ) -> Result<Value> {
        let optional = |n: &str| optional(c, n);
        let tool = optional("Tool").and_then(|a| a.value.as_ref());
        let wobj = optional("WObj").and_then(|a| a.value.as_ref());
        let frames = self.frame_names(tool, wobj, frame, 0, None)?;
        Ok(
            match target_of_flange(&self.arm.flange, &frames.0, &frames.1) {
                Ok(pose) => Value::Rob(Box::new(Rob {
                    pose,
                    conf: self.arm.conf,
                    id: None,
                    derived,
                    bases: Vec::new(),
                })),
                Err(_) => Value::Unknown,
            },
        )
    }

    /// `Dim`: an array's size as its declaration gives it.
    fn dim_value(&mut self, positional: &[&Expr], frame: &mut Frame<'p>) -> Result<Value> {
        let which = match positional.get(1) {
            Some(e) => self.eval(e, frame)?.num(),
            None => None,
        };
        let Some(n) = positional.first().and_then(|e| e.as_name()) else {
            return Ok(Value::Unknown);
        };
        let decl = frame
            .routine
            .and_then(|r| {
                r.data
                    .iter()
                    .find(|d| d.name.eq_ignore_ascii_case(n))
                    .map(|d| (frame.module, d))
            })
            .or_else(|| {
                self.decls.get(&NoCase(n.as_bytes())).and_then(|l| {
                    l.iter()
                        .find(|(m, _)| *m == frame.module)
                        .or_else(|| l.first())
                        .and_then(|&(m, d)| match d {
                            Decl::Tree(d) => Some((m, d)),
                            Decl::Run { .. } => None,
                        })
                })
            });
        let (Some((m, d)), Some(k)) = (decl, which) else {
            return Ok(Value::Unknown);
        };
        let Some(dim) = (k >= 1.0).then(|| d.dims.get(k as usize - 1)).flatten() else {
            return Ok(Value::Unknown);
        };
        let mut f = Frame {
            module: m,
            routine: None,
            vars: FastMap::default(),
        };
        self.eval(dim, &mut f)
    }

    /// A FUNC of the program called: its value, a robtarget it makes
    /// taken as the derived target the call is.
    fn func_value(
        &mut self,
        mi: usize,
        r: &'p Routine,
        c: &FunctionCall,
        derived: Option<usize>,
        frame: &mut Frame<'p>,
    ) -> Result<Value> {
        let vars = self.bind(r, &c.args, frame)?;
        let v = match self.call_routine(mi, r, vars, r.pos.line)? {
            Flow::Return(v) => v,
            _ => Value::Unknown,
        };
        Ok(match v {
            Value::Rob(mut rob) if rob.id.is_none() => {
                rob.derived = derived.or(rob.derived);
                Value::Rob(rob)
            }
            v => v,
        })
    }
}

/// The optional argument `\n` of a call, where given.
fn optional<'c>(c: &'c FunctionCall, n: &str) -> Option<&'c rapid::Arg> {
    c.args
        .iter()
        .find(|a| a.optional && a.name.as_deref().is_some_and(|x| x.eq_ignore_ascii_case(n)))
}

fn binary(op: BinaryOp, l: &Value, r: &Value) -> Value {
    use BinaryOp::*;
    match (l, r) {
        (Value::Num(a), Value::Num(b)) => {
            let (a, b) = (*a, *b);
            match op {
                Add => Value::Num(a + b),
                Sub => Value::Num(a - b),
                Mul => Value::Num(a * b),
                Div if b != 0.0 => Value::Num(a / b),
                IntDiv if b != 0.0 => Value::Num((a / b).trunc()),
                Mod if b != 0.0 => Value::Num(a % b),
                op => compare(op, a, b).map_or(Value::Unknown, Value::Bool),
            }
        }
        (Value::Bool(a), Value::Bool(b)) => match op {
            And => Value::Bool(*a && *b),
            Or => Value::Bool(*a || *b),
            Xor => Value::Bool(a != b),
            Eq => Value::Bool(a == b),
            Ne => Value::Bool(a != b),
            _ => Value::Unknown,
        },
        // FALSE AND anything, TRUE OR anything.
        (Value::Bool(false), _) | (_, Value::Bool(false)) if op == And => Value::Bool(false),
        (Value::Bool(true), _) | (_, Value::Bool(true)) if op == Or => Value::Bool(true),
        (Value::Str(a), Value::Str(b)) => match op {
            Add => Value::Str(format!("{a}{b}")),
            Eq => Value::Bool(a == b),
            Ne => Value::Bool(a != b),
            _ => Value::Unknown,
        },
        _ => Value::Unknown,
    }
}
