//! The interpreter's values: num, bool, string, records of RAPID's data
//! types (and of the program's own RECORDs) and arrays, with the record
//! types it knows by their components.

use crate::error::{Error, Result};
use std::borrow::Cow;
use std::collections::HashMap;
use std::rc::Rc;

/// A RAPID value. Aggregates (`[1, 2, 3]`) are arrays until they are
/// stored where a record is expected ([`Types::coerce`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Num(f64),
    Bool(bool),
    Str(String),
    /// A record: its type (as declared, lower case) and components in
    /// declaration order.
    Rec(Rc<str>, Vec<Value>),
    /// An array, or an aggregate not yet given a type.
    Arr(Vec<Value>),
}

impl Value {
    pub fn num(&self) -> Option<f64> {
        match self {
            Value::Num(v) => Some(*v),
            _ => None,
        }
    }
    pub fn boolean(&self) -> Option<bool> {
        match self {
            Value::Bool(b) => Some(*b),
            _ => None,
        }
    }
    pub fn string(&self) -> Option<&str> {
        match self {
            Value::Str(s) => Some(s),
            _ => None,
        }
    }
    /// The numbers of a record or array, depth first (a pos's x, y, z).
    pub fn numbers(&self) -> Vec<f64> {
        let mut out = Vec::new();
        self.collect_numbers(&mut out);
        out
    }
    fn collect_numbers(&self, out: &mut Vec<f64>) {
        match self {
            Value::Num(v) => out.push(*v),
            Value::Rec(_, items) | Value::Arr(items) => {
                items.iter().for_each(|i| i.collect_numbers(out))
            }
            Value::Bool(_) | Value::Str(_) => {}
        }
    }
    /// Every num rounded to single precision (the controller's `num`).
    /// A `clock`'s inner state is the controller's own (its reads are
    /// nums, rounded where they are stored).
    pub fn to_single(&mut self) {
        match self {
            Value::Num(v) => *v = f64::from(*v as f32),
            Value::Rec(t, _) if &**t == "clock" => {}
            Value::Rec(_, items) | Value::Arr(items) => items.iter_mut().for_each(Value::to_single),
            Value::Bool(_) | Value::Str(_) => {}
        }
    }
    /// What the value is, for messages.
    pub fn kind(&self) -> String {
        match self {
            Value::Num(_) => "num".into(),
            Value::Bool(_) => "bool".into(),
            Value::Str(_) => "string".into(),
            Value::Rec(t, _) => t.to_string(),
            Value::Arr(_) => "array".into(),
        }
    }
}

/// RAPID's own record types the interpreter knows: (type, components as
/// (name, type)). From the data types chapter of the RAPID reference.
const BUILTIN_RECORDS: &[(&str, &[(&str, &str)])] = &[
    ("pos", &[("x", "num"), ("y", "num"), ("z", "num")]),
    (
        "orient",
        &[("q1", "num"), ("q2", "num"), ("q3", "num"), ("q4", "num")],
    ),
    ("pose", &[("trans", "pos"), ("rot", "orient")]),
    (
        "confdata",
        &[
            ("cf1", "num"),
            ("cf4", "num"),
            ("cf6", "num"),
            ("cfx", "num"),
        ],
    ),
    (
        "robjoint",
        &[
            ("rax_1", "num"),
            ("rax_2", "num"),
            ("rax_3", "num"),
            ("rax_4", "num"),
            ("rax_5", "num"),
            ("rax_6", "num"),
        ],
    ),
    (
        "extjoint",
        &[
            ("eax_a", "num"),
            ("eax_b", "num"),
            ("eax_c", "num"),
            ("eax_d", "num"),
            ("eax_e", "num"),
            ("eax_f", "num"),
        ],
    ),
    (
        "robtarget",
        &[
            ("trans", "pos"),
            ("rot", "orient"),
            ("robconf", "confdata"),
            ("extax", "extjoint"),
        ],
    ),
    (
        "jointtarget",
        &[("robax", "robjoint"), ("extax", "extjoint")],
    ),
    ("progdisp", &[("pdisp", "pose"), ("eoffs", "extjoint")]),
    // A stopwatch (`VAR clock`): its components are not RAPID's (a
    // program cannot read them) but the interpreter's: whether it runs,
    // the controller's time (s) it was started at, and the seconds it
    // counted before.
    (
        "clock",
        &[("running", "bool"), ("since", "num"), ("counted", "num")],
    ),
    (
        "loaddata",
        &[
            ("mass", "num"),
            ("cog", "pos"),
            ("aom", "orient"),
            ("ix", "num"),
            ("iy", "num"),
            ("iz", "num"),
        ],
    ),
    (
        "tooldata",
        &[
            ("robhold", "bool"),
            ("tframe", "pose"),
            ("tload", "loaddata"),
        ],
    ),
    (
        "wobjdata",
        &[
            ("robhold", "bool"),
            ("ufprog", "bool"),
            ("ufmec", "string"),
            ("uframe", "pose"),
            ("oframe", "pose"),
        ],
    ),
    (
        "speeddata",
        &[
            ("v_tcp", "num"),
            ("v_ori", "num"),
            ("v_leax", "num"),
            ("v_reax", "num"),
        ],
    ),
    (
        "zonedata",
        &[
            ("finep", "bool"),
            ("pzone_tcp", "num"),
            ("pzone_ori", "num"),
            ("pzone_eax", "num"),
            ("zone_ori", "num"),
            ("zone_leax", "num"),
            ("zone_reax", "num"),
        ],
    ),
];

/// A record type: its name (lower case) and components as (name, type).
type Record = (Rc<str>, Vec<(String, String)>);

/// The record types in scope: RAPID's and the program's RECORDs, and the
/// aliases (`ALIAS num angle`), by lower-case name.
#[derive(Debug, Clone)]
pub struct Types {
    records: HashMap<String, Record>,
    aliases: HashMap<String, String>,
}

impl Default for Types {
    fn default() -> Self {
        let mut t = Types {
            records: HashMap::new(),
            aliases: HashMap::new(),
        };
        for (name, fields) in BUILTIN_RECORDS {
            t.add_record(
                name,
                fields
                    .iter()
                    .map(|(n, ty)| (n.to_string(), ty.to_string()))
                    .collect(),
            );
        }
        t
    }
}

impl Types {
    pub fn add_record(&mut self, name: &str, fields: Vec<(String, String)>) {
        let key = name.to_ascii_lowercase();
        self.records
            .insert(key.clone(), (Rc::from(key.as_str()), fields));
    }
    pub fn add_alias(&mut self, alias: &str, of: &str) {
        self.aliases
            .insert(alias.to_ascii_lowercase(), of.to_ascii_lowercase());
    }
    /// The type `ty` names, in lower case, through its aliases (no copy
    /// where it is one already: every component read asks).
    fn resolve<'a>(&self, ty: &'a str) -> Cow<'a, str> {
        let mut t = if ty.bytes().any(|b| b.is_ascii_uppercase()) {
            Cow::Owned(ty.to_ascii_lowercase())
        } else {
            Cow::Borrowed(ty)
        };
        for _ in 0..8 {
            match self.aliases.get(t.as_ref()) {
                Some(of) => t = Cow::Owned(of.clone()),
                None => break,
            }
        }
        t
    }

    /// The value a declaration of `ty` without an initial value holds.
    pub fn default_of(&self, ty: &str) -> Result<Value> {
        let t = self.resolve(ty);
        Ok(match t.as_ref() {
            "num" | "dnum" | "byte" => Value::Num(0.0),
            "bool" | "switch" => Value::Bool(false),
            "string" => Value::Str(String::new()),
            _ => {
                let (name, fields) = self
                    .records
                    .get(t.as_ref())
                    .ok_or_else(|| Error::input(format!("data type `{ty}` is not known")))?;
                let items = fields
                    .iter()
                    .map(|(_, fty)| self.default_of(fty))
                    .collect::<Result<Vec<_>>>()?;
                Value::Rec(name.clone(), items)
            }
        })
    }

    /// An array of `dims` (sizes) of `ty`'s default.
    pub fn default_array(&self, ty: &str, dims: &[usize]) -> Result<Value> {
        match dims.split_first() {
            None => self.default_of(ty),
            Some((&n, rest)) => {
                let one = self.default_array(ty, rest)?;
                Ok(Value::Arr(vec![one; n]))
            }
        }
    }

    /// The index of component `field` of record type `ty`.
    pub fn field(&self, ty: &str, field: &str) -> Option<usize> {
        self.records
            .get(self.resolve(ty).as_ref())
            .and_then(|(_, f)| f.iter().position(|(n, _)| n.eq_ignore_ascii_case(field)))
    }

    /// `v` stored where a value shaped like `like` is: an aggregate
    /// becomes that record or array; the shapes must agree.
    pub fn coerce(&self, v: Value, like: &Value) -> Result<Value> {
        match (v, like) {
            (Value::Arr(items), Value::Rec(ty, fields)) if items.len() == fields.len() => {
                let items = items
                    .into_iter()
                    .zip(fields)
                    .map(|(i, f)| self.coerce(i, f))
                    .collect::<Result<Vec<_>>>()?;
                Ok(Value::Rec(ty.clone(), items))
            }
            (Value::Arr(items), Value::Arr(like)) if items.len() == like.len() => {
                let items = items
                    .into_iter()
                    .zip(like)
                    .map(|(i, f)| self.coerce(i, f))
                    .collect::<Result<Vec<_>>>()?;
                Ok(Value::Arr(items))
            }
            (v @ Value::Num(_), Value::Num(_))
            | (v @ Value::Bool(_), Value::Bool(_))
            | (v @ Value::Str(_), Value::Str(_)) => Ok(v),
            (v @ Value::Rec(..), Value::Rec(ty, _)) if matches!(&v, Value::Rec(t, _) if t == ty) => {
                Ok(v)
            }
            (v, like) => Err(Error::input(format!(
                "a {} where a {} is expected",
                v.kind(),
                like.kind()
            ))),
        }
    }

    /// `v` as a value of type `ty`.
    pub fn coerce_to(&self, v: Value, ty: &str) -> Result<Value> {
        let like = self.default_of(ty)?;
        self.coerce(v, &like)
    }
}
