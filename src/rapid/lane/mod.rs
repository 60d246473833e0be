//! The fast lane of the parse: the statements large programs are made of
//! (moves, robtarget and jointtarget declarations, arrays of robtarget
//! literals) read by hand, at the speed of the disk, into what the
//! grammar would make of them. The parse asks it first at each statement
//! and declaration; where it does not read one, the pest grammar does,
//! and stays the authority on what is RAPID. A statement it began and
//! left to the grammar is counted with its reason ([`Decline`]).

mod array;
mod cursor;
mod decline;
mod statement;

pub(crate) use cursor::{decimal_value, Cursor, Seen};
pub use decline::{Decline, Declined, LaneTally, Part, StoppedAt};
pub(crate) use statement::{read_decl, read_move, LaneDecl, LaneMove, Value};
