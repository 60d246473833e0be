//! A message told to the operator, and which log it went to.

/// Which log a message went to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MessageKind {
    /// `ErrWrite` without a switch.
    Error,
    /// `ErrWrite \W`.
    Warning,
    /// `ErrWrite \I`.
    Info,
    /// `TPWrite`: the FlexPendant's operator window.
    Pendant,
}

/// A message told to the operator.
#[derive(Debug, Clone, PartialEq)]
pub struct OperatorMessage {
    pub kind: MessageKind,
    /// ErrWrite's header; TPWrite's line.
    pub header: String,
    /// ErrWrite's reason lines (none for TPWrite).
    pub reasons: Vec<String>,
}
