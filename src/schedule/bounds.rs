//! How far a walk of a program goes before it gives up, and what it
//! assumes where a program leaves a number unresolved: the walk's
//! bounds, shared by the walk and its estimate.

/// Statements executed before the walk gives up (a FOR loop of a billion
/// turns would otherwise run for hours).
pub(super) const STEP_BUDGET: u64 = 50_000_000;
/// Nested routine calls followed (the controller's own limit is lower).
pub(super) const MAX_DEPTH: usize = 256;
/// Stack left before the walk grows it, and by how much.
pub(super) const STACK_RED_ZONE: usize = 64 * 1024;
pub(super) const STACK_SEGMENT: usize = 1024 * 1024;
/// The speed assumed where a move's speeddata cannot be resolved.
pub(super) const FALLBACK_SPEED: &str = "v1000";
