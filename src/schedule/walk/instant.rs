//! RAPID instructions that take no time worth counting.

/// Instructions that take no time worth counting (I/O, messages,
/// settings, interrupts): not noted when met.
pub(super) fn is_instant_builtin(name: &str) -> bool {
    crate::rapid::builtins::is_instant_instruction(name)
}
