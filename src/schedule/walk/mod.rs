//! The program walker: RAPID executed as far as timing needs it (routine
//! calls, control flow, data), each move timed on the nominal robot. Split
//! by idea: the walker's state and the routine's frame ([`walker`]), the
//! values it follows ([`value`]), statements ([`statements`]), calls and
//! the instructions that take time without moving ([`calls`]), FOR loops
//! ([`for_loop`]), expressions ([`eval`]), data declarations ([`decls`]),
//! motion instructions ([`moves`]) and what a move statement settles for
//! its next turn ([`settled`]), whether a move's target can be reached at
//! all ([`check`], [`reach`]), statements that end the program ([`ends`]),
//! instructions that take no time ([`instant`]), and the walk's end
//! ([`finish`]).

mod calls;
mod check;
mod decls;
mod ends;
mod eval;
mod finish;
mod for_loop;
mod instant;
mod moves;
mod poses;
mod reach;
mod settled;
mod statements;
mod value;
mod walker;

pub use poses::TargetPoses;
pub(crate) use reach::ReachAhead;
pub(super) use value::Flow;
pub(super) use walker::Walker;
