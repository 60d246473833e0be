//! The built-in instructions the interpreter runs beyond moves: the
//! operator's messages, the stopwatches and the program displacement,
//! each in its own file; this asks each in turn.

use super::state::Interp;
use crate::error::Result;
use crate::rapid::Call;

impl Interp {
    /// Built-in instruction `c` executed; `false` for one the
    /// interpreter does not know.
    pub(super) fn instruction(&mut self, c: &Call) -> Result<bool> {
        Ok(self.message_instruction(c)?
            || self.clock_instruction(c)?
            || self.progdisp_instruction(c)?)
    }
}
