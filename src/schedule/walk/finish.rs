//! The walk's end: bases reached only through derived targets get
//! those visits, and the targets never reached are counted in a note.

use super::walker::Walker;
use crate::schedule::Schedule;
use std::collections::HashSet;
use std::sync::Arc;

/// Targets never reached that the walk's note names (the rest counted).
const SHOWN_MISSED: usize = 8;

impl Walker<'_> {
    /// Bases reached only through derived targets get those visits;
    /// a summary of targets never reached.
    pub(crate) fn finish(&mut self) {
        let targets = self.program.targets();
        self.schedule.name_targets(|i| {
            let mut id = String::new();
            targets.id_into(i, &mut id);
            Arc::from(id)
        });
        let visits = std::mem::take(&mut self.base_visits);
        let visited = |s: &Schedule, i: usize| {
            let mut id = String::new();
            targets.id_into(i, &mut id).is_some() && s.times_of(i, &id).is_some()
        };
        let direct: HashSet<usize> = visits
            .iter()
            .map(|&(b, _)| b)
            .filter(|&b| visited(&self.schedule, b))
            .collect();
        for (b, t) in visits {
            if direct.contains(&b) || b >= targets.len() {
                continue;
            }
            self.schedule.visit_target(b, t, || {
                let mut id = String::new();
                targets.id_into(b, &mut id);
                Arc::from(id)
            });
        }
        let mut count = 0;
        let mut shown: Vec<String> = Vec::new();
        // Identifiers only: the targets' numbers are not read for this.
        let mut id = String::new();
        for i in 0..targets.len() {
            // Visited by number (nearly all): named above, found by
            // number, with no identifier to make.
            if self.schedule.has_number(i) {
                continue;
            }
            if targets.id_into(i, &mut id) == Some(true) && self.schedule.times_of(i, &id).is_none()
            {
                count += 1;
                if shown.len() < SHOWN_MISSED {
                    shown.push(id.clone());
                }
            }
        }
        if count > 0 {
            let more = if count > shown.len() {
                format!(", ... ({count} in all)")
            } else {
                String::new()
            };
            self.notes.push(format!(
                "{count} robtarget(s) never reached from the entry routine: {}{more}",
                shown.join(", ")
            ));
        }
    }
}
