//! What the CI reports are made of, whatever their format (GitHub
//! annotations, JUnit XML): a suite per file or task, a case per target
//! at the gate.

/// How a case fares at the gate, and how a CI system shows it; from the
/// best to the worst.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum GateLevel {
    /// Passes; not annotated.
    Pass,
    /// Passes; worth a notice (a target nothing of the arm drifts in).
    Notice,
    /// Passes, but stays wrong on the warm robot: the user accepted it
    /// (a warning; a skipped test in JUnit).
    Skip,
    /// Fails the gate.
    Error,
}

/// One target (or use of one) at the gate.
pub struct Case {
    /// The target's identifier.
    pub name: String,
    pub file: String,
    /// 0: unknown.
    pub line: u32,
    pub col: u32,
    pub level: GateLevel,
    /// Why it fails: the failure's type in JUnit.
    pub kind: &'static str,
    pub title: String,
    pub message: String,
}

/// The cases of one file, or of one task of a backup.
pub struct Suite {
    pub name: String,
    pub properties: Vec<(String, String)>,
    /// A task of a backup (or a task folder): JUnit writes a test case per
    /// file, not per target (a backup has tens of thousands of targets).
    pub per_file: bool,
    pub cases: Vec<Case>,
}
