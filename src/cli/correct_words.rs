//! The words of a correction's results, shared by every report of it
//! (summary, per-target report, check list, CI formats): why a target is
//! left alone (with the flag that changes it), where a use with other
//! frames lands, and the run's summary.

use rapidtherm::correct::{FramesUse, Kind, Outcome, Reason, SharedUse};
use rapidtherm::report::mm;

/// A use with other frames in words: where, with what, how far off, and
/// what the target is corrected for.
pub fn shared_words(u: &SharedUse) -> String {
    let instruction = |f: &FramesUse| match &f.through {
        Some(expr) => format!("{} {expr}", f.instruction),
        None => f.instruction.clone(),
    };
    let (o, c) = (&u.other, &u.corrected_for);
    let off = match (u.residual_mm, u.residual_deg) {
        (Some(mm_off), Some(deg)) if deg >= 0.00005 => {
            format!("it lands {} mm, {}° off", mm(mm_off, 4), mm(deg, 4))
        }
        (Some(mm_off), _) => format!("it lands {} mm off", mm(mm_off, 4)),
        (None, _) => format!(
            "where it lands is known only at run time ({})",
            u.unknown.as_deref().unwrap_or("")
        ),
    };
    let mut text = format!(
        "at {} in {} line {} (tool {}, wobj {}) {off}; corrected for tool {}, wobj {} ({} in {} line {}, its first use)",
        instruction(o), o.routine, o.line, o.tool, o.wobj, c.tool, c.wobj, instruction(c), c.routine, c.line
    );
    if let Some(why) = &u.not_split {
        text.push_str(&format!("; not split: {why}"));
    }
    text
}

/// A reason's words, with what the user can do where the CLI has a flag
/// for it.
pub fn reason_words(reason: Reason, kind: Kind, detail: &str) -> String {
    match reason {
        Reason::Expression if kind.is_robtarget() => format!("{detail} (--expand-expressions)"),
        _ => detail.to_string(),
    }
}

/// The summary of a run, and a line for each target left alone, use
/// with other frames, split and note. `checked`: the run is a check
/// (`--check`), which writes nothing, so the summary says what a run
/// that writes would do.
pub fn summary_text(outcome: &Outcome, checked: bool) -> String {
    let s = &outcome.summary;
    let (corrected, rewritten) = if checked {
        ("would be corrected", "would be rewritten")
    } else {
        ("corrected", "rewritten")
    };
    let mut text = format!(
        "{} target(s) {corrected} ({} {rewritten}): max {} mm, RMS {} mm; largest drift {} mm",
        s.corrected,
        s.rewritten,
        mm(s.max_mm, 4),
        mm(s.rms_mm, 4),
        mm(s.max_drift_mm, 4)
    );
    if s.derived > 0 {
        text.push_str(&format!("; {} derived left as written", s.derived));
    }
    if s.left_alone > 0 {
        text.push_str(&format!("; {} left alone", s.left_alone));
    }
    if s.shared > 0 {
        text.push_str(&format!(
            "; {} use(s) with another tool or work object",
            s.shared
        ));
    }
    if s.split > 0 {
        text.push_str(&format!("; {} split", s.split));
    }
    text.push('\n');
    // Every move instruction, by where it ends.
    let m = &s.moves;
    if m.moves > 0 {
        text.push_str(&format!(
            "{} move instruction(s): {} corrected, {} derived, {} left alone\n",
            m.moves, m.corrected, m.derived, m.left_alone
        ));
    }
    for l in &outcome.left_alone {
        let level = if l.reason.leaves_target_cold() {
            "warning"
        } else {
            "note"
        };
        text.push_str(&format!(
            "{level}: left alone {} ({}:{}:{}) [{}]: {}\n",
            l.id,
            l.file,
            l.line,
            l.col,
            l.reason.code(),
            reason_words(l.reason, l.kind, &l.detail)
        ));
    }
    for u in &outcome.shared {
        // Below what a written number resolves it is a note, not a warning.
        let level = match u.residual_mm {
            Some(r) if r < 0.001 => "note",
            _ => "warning",
        };
        text.push_str(&format!(
            "{level}: other use of {} ({}:{}:{}) [{}]: {}\n",
            u.id,
            u.file,
            u.line,
            u.col,
            Reason::SharedFrames.code(),
            shared_words(u)
        ));
    }
    for s in &outcome.splits {
        text.push_str(&format!(
            "note: split {} ({}:{}): copy {} for tool {}, wobj {}\n",
            s.id, s.file, s.line, s.copy, s.tool, s.wobj
        ));
    }
    for note in &outcome.notes {
        text.push_str(&format!("note: {note}\n"));
    }
    text
}
