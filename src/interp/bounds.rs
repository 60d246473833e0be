//! How far the interpreter goes before it gives up: its own bounds, the
//! same numbers as the walk's (`schedule`'s), which the interpreter no
//! longer reaches into.

/// Statements executed before the interpreter gives up (a FOR loop of a
/// billion turns would otherwise run for hours).
pub(super) const STEP_BUDGET: u64 = 50_000_000;
/// Stack left before an evaluation grows it, and by how much.
pub(super) const STACK_RED_ZONE: usize = 64 * 1024;
pub(super) const STACK_SEGMENT: usize = 1024 * 1024;
