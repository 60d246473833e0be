//! What a move statement finds the same at every turn of a loop: which
//! of its arguments is which ([`Call::motion`]), its speed and its tool
//! and work object by their names, the declaration of the target array
//! it indexes. A FOR loop over an array of a million targets asked each
//! of these again at every turn: lower-cased names looked up in the
//! routine's variables and the walk's data, then compared with the last
//! move's (a third of the walk).
//!
//! Each is what the statement's own lookup finds, kept only where the
//! lookup itself would keep it ([`Walker::speed_of`], [`Walker::frame_names`]:
//! plain names that no variable shadows, found without a note) and only
//! while [`Walker::scope`] is unchanged: no variable has been made or
//! dropped, no data assigned for the first time, no routine entered
//! since. Within one scope a statement runs in one routine and module,
//! and its names find the same declarations.

use crate::rapid::{DataDecl, Motion};
use crate::robot::{ToolFrame, WobjFrames};
use crate::schedule::timing::MoveSpeed;
use std::rc::Rc;

/// What one move statement settled, in the scope it did.
pub(super) struct Settled<'p> {
    /// [`Walker::scope`] when it was settled.
    pub(super) scope: u64,
    pub(super) motion: Motion<'p>,
    pub(super) found: Found<'p>,
}

/// What a move's lookups found and keep, each where found.
#[derive(Default)]
pub(super) struct Found<'p> {
    pub(super) speed: Option<MoveSpeed>,
    pub(super) frames: Option<Rc<(ToolFrame, WobjFrames)>>,
    /// The declaration of the array the target indexes, where looked up
    /// ([`Walker::element_of`]).
    pub(super) array: Option<Option<&'p DataDecl>>,
}

/// Where a move's settled parts are kept while it runs: `None` for moves
/// that are not statements of the program's tree (the fast lane's runs,
/// whose statements are made anew for each move).
pub(super) type SettledSlot<'a, 'p> = Option<&'a mut Found<'p>>;
