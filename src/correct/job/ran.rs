//! What a job returns of each task it corrected.

use crate::correct::Outcome;
use crate::rapid::task::Task;

/// Files as read: the name each is known by in messages, and its bytes.
pub type Inputs = Vec<(String, Vec<u8>)>;

/// One task corrected: its files as read (name and bytes; none where the
/// run streamed them), the arm's name, and the outcome.
#[derive(Debug)]
pub struct Ran {
    pub task: Task,
    pub arm: String,
    pub inputs: Inputs,
    pub outcome: Outcome,
}

impl Ran {
    /// Whether any of its files changes.
    pub fn changed(&self) -> bool {
        self.outcome
            .outputs
            .iter()
            .zip(&self.inputs)
            .any(|(after, (_, before))| after != before)
    }
}
