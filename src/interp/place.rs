//! Places a program can write: a datum, a routine's variable or a
//! parameter passed by reference (`INOUT`, `PERS`), and a component or
//! element inside it (`rtX{a,k}`, `out.trans`, `w.uframe.trans.x`).

use super::value::Value;

/// A routine's variable: its value, or the caller's place it stands for.
#[derive(Debug, Clone)]
pub(super) enum Slot {
    Value(Value),
    Ref(Place),
}

#[derive(Debug, Clone, PartialEq)]
pub(super) enum Root {
    /// A module datum: its name (lower case) and which of that name.
    Global(String, usize),
    /// A variable of frame `0`, by lower-case name.
    Local(usize, String),
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Step {
    Field(usize),
    Index(usize),
}

#[derive(Debug, Clone, PartialEq)]
pub(super) struct Place {
    pub(super) root: Root,
    pub(super) path: Vec<Step>,
}
