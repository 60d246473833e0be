//! The run's progress, counted in the targets whose correction costs
//! time: each robtarget when it is solved (a derived one when its residual
//! is computed, after the others), each jointtarget corrected. Reported in
//! steps small enough for a steady estimate of the time left.

/// Targets between two reports.
const EVERY: usize = 1024;

pub(super) struct Progress<'f> {
    done: usize,
    total: usize,
    report: &'f mut dyn FnMut(usize, usize),
}

impl<'f> Progress<'f> {
    /// Starts at 0 of `total` (and says so).
    pub(super) fn new(total: usize, report: &'f mut dyn FnMut(usize, usize)) -> Progress<'f> {
        report(0, total);
        Progress {
            done: 0,
            total,
            report,
        }
    }

    /// One more target done.
    pub(super) fn step(&mut self) {
        self.done += 1;
        if self.done.is_multiple_of(EVERY) {
            (self.report)(self.done, self.total);
        }
    }

    /// `n` more targets done.
    pub(super) fn add(&mut self, n: usize) {
        let before = self.done / EVERY;
        self.done += n;
        if self.done / EVERY != before {
            (self.report)(self.done, self.total);
        }
    }

    /// Every target done.
    pub(super) fn finish(&mut self) {
        (self.report)(self.total, self.total);
    }
}
