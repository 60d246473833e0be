//! Where a run writes its corrected files, and which of its report rows
//! it keeps: the caller's writers, one per file.

use std::io::Write;

/// Which of a run's report rows are kept.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReportRows {
    /// Every target's (a report, a check, pictures).
    Every,
    /// The summary's figures alone (a file written: a million rows is
    /// what the run need not hold).
    SummaryOnly,
}

/// Where a run writes: one writer per file, in the program's file order,
/// and the report rows it keeps.
pub struct Writers<'a, 'w> {
    pub outs: &'a mut [&'w mut (dyn Write + Send)],
    pub rows: ReportRows,
}

impl<'a, 'w> Writers<'a, 'w> {
    pub fn new(outs: &'a mut [&'w mut (dyn Write + Send)], rows: ReportRows) -> Self {
        Writers { outs, rows }
    }
}
