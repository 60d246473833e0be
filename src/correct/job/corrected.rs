//! What a job returns of each task it corrected.

use crate::correct::Outcome;
use crate::rapid::task::Task;

/// Files as read: the name each is known by in messages, and its bytes.
pub type Inputs = Vec<(String, crate::rapid::Source)>;

/// One task corrected: its files as read (name and bytes), the arm's
/// name, the outcome, and whether it was streamed.
#[derive(Debug)]
pub struct CorrectedTask {
    pub task: Task,
    pub arm: String,
    pub inputs: Inputs,
    pub outcome: Outcome,
    pub streaming: Streaming,
}

/// How a task was corrected.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Streaming {
    /// In memory: the outcome holds every file's corrected bytes.
    InMemory,
    /// Written through the sink as corrected: the outcome holds no
    /// outputs; whether each file changes.
    Streamed { changed: Vec<bool> },
}

impl CorrectedTask {
    /// Whether any of its files changes.
    pub fn changed(&self) -> bool {
        match &self.streaming {
            Streaming::Streamed { changed } => changed.iter().any(|&c| c),
            Streaming::InMemory => self
                .outcome
                .outputs
                .iter()
                .zip(&self.inputs)
                .any(|(after, (_, before))| after.as_slice() != before.bytes()),
        }
    }
}
