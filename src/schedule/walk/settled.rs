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

use super::*;
use std::rc::Rc;

/// What one move statement settled, in the scope it did.
pub(super) struct Settled<'p> {
    /// [`Walker::scope`] when it was settled.
    scope: u64,
    motion: Motion<'p>,
    found: Found<'p>,
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

impl<'p> Walker<'p> {
    /// Some name may now stand for something else: what statements
    /// settled before is asked again.
    pub(super) fn rescope(&mut self) {
        self.scope += 1;
    }

    /// `call` run as a move with what it settled at its last turn in this
    /// scope; `false` where it is not a motion instruction.
    pub(super) fn exec_settled(
        &mut self,
        call: &'p Call,
        s: &Statement,
        frame: &mut Frame<'p>,
    ) -> Result<bool> {
        let key = std::ptr::from_ref(call);
        let scope = self.scope;
        // Boxed: taken out and put back at every move, moved as a pointer.
        let kept = match self.last_settled.take() {
            Some((k, st)) if k == key => Some(st),
            other => {
                if let Some((k, st)) = other {
                    self.settled.insert(k, st);
                }
                self.settled.remove(&key)
            }
        };
        let mut st = match kept {
            Some(st) if st.scope == scope => st,
            Some(mut st) => {
                st.scope = scope;
                st.found = Found::default();
                st
            }
            None => match call.motion() {
                Some(motion) => Box::new(Settled {
                    scope,
                    motion,
                    found: Found::default(),
                }),
                None => return Ok(false),
            },
        };
        let Settled { motion, found, .. } = &mut *st;
        self.exec_move(call, motion, s, frame, Some(found))?;
        // Settled in a scope that ended during the move (a FUNC called
        // from an argument) is never taken again: scopes only grow. A move
        // such a FUNC made left its own here: to the map with it.
        if let Some((k, inner)) = self.last_settled.take() {
            self.settled.insert(k, inner);
        }
        self.last_settled = Some((key, st));
        Ok(true)
    }
}
