//! The values a walk follows: numbers and truths where the program
//! writes them, robtargets and jointtargets with the literals they come
//! from, and what a statement list ends with ([`Flow`]).

use crate::robot::{Joints, RobConf};
use nalgebra::Isometry3;

/// A robtarget value met in the walk.
#[derive(Debug, Clone)]
pub(crate) struct Rob {
    /// TCP in the work object (the robtarget's own frame).
    pub(super) pose: Isometry3<f64>,
    pub(super) conf: RobConf,
    /// The literal target this value is (index into `Program::targets`):
    /// where set, `pose` and `conf` are that literal's as read
    /// ([`crate::resolve::target_pose`]).
    pub(super) id: Option<usize>,
    /// The derived target that computed it (`Offs(...)`).
    pub(super) derived: Option<usize>,
    /// Literal targets it was derived from.
    pub(super) bases: Vec<usize>,
}

#[derive(Debug, Clone)]
pub(crate) enum Value {
    Num(f64),
    Bool(bool),
    Str(String),
    Rob(Box<Rob>),
    /// Joint angles (rad) and the jointtarget literal they are.
    Joint(Box<(Joints, Option<usize>)>),
    Agg(Vec<Value>),
    /// A name the walk does not evaluate (tooldata, wobjdata, speeddata,
    /// signals): resolved by the instruction that uses it.
    Ref(String),
    Unknown,
}

impl Value {
    pub(super) fn num(&self) -> Option<f64> {
        match self {
            Value::Num(v) => Some(*v),
            _ => None,
        }
    }
    pub(super) fn boolean(&self) -> Option<bool> {
        match self {
            Value::Bool(b) => Some(*b),
            _ => None,
        }
    }
}

pub(crate) enum Flow {
    Normal,
    Return(Value),
    Exit,
    Goto(String),
}
