//! A place a program names found from the running routine (its own
//! variables, a caller's by reference, module data), read and written
//! (a value stored at the controller's precision).

use super::place::{Place, Root, Slot, Step};
use super::raised::ERR_OUTOFBND;
use super::state::{Interp, Precision};
use super::value::Value;
use crate::error::{Error, Result};
use crate::rapid::{Expr, Storage};

impl Interp {
    /// Where name `name` is, seen from the running routine.
    pub(super) fn place_of_name(&self, name: &str) -> Result<Place> {
        let key = name.to_ascii_lowercase();
        if let Some(n) = self.frames.len().checked_sub(1) {
            match self.frames[n].vars.get(&key) {
                Some(Slot::Ref(p)) => return Ok(p.clone()),
                Some(Slot::Value(_)) => {
                    return Ok(Place {
                        root: Root::Local(n, key),
                        path: Vec::new(),
                    })
                }
                None => {}
            }
        }
        let module = self.frames.last().map(|f| f.module);
        let slots = self
            .globals
            .get(&key)
            .ok_or_else(|| Error::input(format!("`{name}` is not declared")))?;
        let k = slots
            .iter()
            .position(|g| g.local && Some(g.module) == module)
            .or_else(|| slots.iter().position(|g| !g.local))
            .ok_or_else(|| Error::input(format!("`{name}` is not visible here")))?;
        Ok(Place {
            root: Root::Global(key, k),
            path: Vec::new(),
        })
    }

    /// The place an expression names (a name, a component, an element).
    pub(super) fn place_of(&mut self, e: &Expr) -> Result<Place> {
        match e {
            Expr::Name(n) => self.place_of_name(n),
            Expr::Component(c) => {
                let (base, field) = c.as_ref();
                let mut p = self.place_of(base)?;
                let ty = match self.read(&p)? {
                    Value::Rec(ty, _) => ty.clone(),
                    v => return Err(Error::input(format!("`.{field}` of a {}", v.kind()))),
                };
                let i = self
                    .types
                    .field(&ty, field)
                    .ok_or_else(|| Error::input(format!("{ty} has no component `{field}`")))?;
                p.path.push(Step::Field(i));
                Ok(p)
            }
            Expr::Index(x) => {
                let (base, idx) = x.as_ref();
                let mut p = self.place_of(base)?;
                for i in idx {
                    let i = self.index_of(i)?;
                    p.path.push(Step::Index(i));
                    if self.read(&p).is_err() {
                        let e = Error::input(format!("index {} is outside the array", i + 1));
                        return Err(self.raise(ERR_OUTOFBND, e));
                    }
                }
                Ok(p)
            }
            _ => Err(Error::input(
                "an expression that names no data where one is needed",
            )),
        }
    }

    /// A 1-based index expression as a 0-based index.
    pub(super) fn index_of(&mut self, e: &Expr) -> Result<usize> {
        let v = self.eval(e)?;
        match v.num() {
            Some(n) if n >= 1.0 && n.fract() == 0.0 => Ok(n as usize - 1),
            // Below the first element: out of bounds, as past the last.
            Some(n) if n.fract() == 0.0 => {
                let e = Error::input(format!("index {n} is outside the array"));
                Err(self.raise(ERR_OUTOFBND, e))
            }
            _ => Err(Error::input(format!(
                "index {v:?} is not a whole number from 1"
            ))),
        }
    }

    fn root_value(&self, root: &Root) -> Result<&Value> {
        match root {
            Root::Global(name, k) => Ok(&self.globals[name][*k].value),
            Root::Local(f, name) => match self.frames[*f].vars.get(name) {
                Some(Slot::Value(v)) => Ok(v),
                _ => Err(Error::input(format!("`{name}` has no value"))),
            },
        }
    }

    pub(super) fn read(&self, p: &Place) -> Result<&Value> {
        let mut v = self.root_value(&p.root)?;
        for step in &p.path {
            v = step_into(v, *step)?;
        }
        Ok(v)
    }

    /// Writes `value` to `p`, shaped as what is there and rounded as
    /// stored; a `CONST` is refused.
    pub(super) fn write(&mut self, p: &Place, value: Value) -> Result<()> {
        let old = self.read(p)?;
        let mut v = self.types.coerce(value, old)?;
        if self.precision == Precision::Single {
            v.to_single();
        }
        let slot = match &p.root {
            Root::Global(name, k) => {
                let g = &mut self.globals.get_mut(name).expect("a place's datum")[*k];
                if g.storage == Storage::Const {
                    return Err(Error::input(format!("`{name}` is a CONST")));
                }
                &mut g.value
            }
            Root::Local(f, name) => match self.frames[*f].vars.get_mut(name) {
                Some(Slot::Value(v)) => v,
                _ => return Err(Error::input(format!("`{name}` has no value"))),
            },
        };
        let mut target = slot;
        for step in &p.path {
            target = step_into_mut(target, *step)?;
        }
        *target = v;
        Ok(())
    }
}

fn step_into(v: &Value, step: Step) -> Result<&Value> {
    match (v, step) {
        (Value::Rec(_, f), Step::Field(i)) => f.get(i),
        (Value::Arr(a), Step::Index(i)) => a.get(i),
        _ => None,
    }
    .ok_or_else(|| Error::input(format!("no such component or element of a {}", v.kind())))
}

fn step_into_mut(v: &mut Value, step: Step) -> Result<&mut Value> {
    let kind = v.kind();
    match (v, step) {
        (Value::Rec(_, f), Step::Field(i)) => f.get_mut(i),
        (Value::Arr(a), Step::Index(i)) => a.get_mut(i),
        _ => None,
    }
    .ok_or_else(|| Error::input(format!("no such component or element of a {kind}")))
}
