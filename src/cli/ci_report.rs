//! The two gates, `correct --check` and `diff --fail-above`, reported for
//! CI systems: GitHub Actions workflow commands (an annotation on the file,
//! line and column of each target that fails) and JUnit XML (a test case
//! per target, for Jenkins, GitLab and the like). See `docs/ci.md`.
//!
//! Only a gate passes or fails: on anything else `--format github|junit`
//! is refused (exit 2) before any work is done.

use super::ci_suite::{Case, GateLevel, Suite};
use super::correct_words::{reason_words, shared_words};
use super::Format;
use rapidtherm::compare::{DataType, Diff, Gate, GateFailure};
use rapidtherm::correct::check::CheckRule;
use rapidtherm::correct::{Outcome, Reason};
use rapidtherm::error::{Error, Result};
use rapidtherm::rapid::Program;
use rapidtherm::report::mm;
use std::collections::{HashMap, HashSet};

/// `--format` of the two commands with a gate: the formats of every
/// command, and the two for CI.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum ReportFormat {
    #[default]
    Table,
    Csv,
    Json,
    /// GitHub Actions workflow commands: an annotation per failing target
    /// (gates only).
    Github,
    /// JUnit XML: a test case per target, per file for a backup (gates
    /// only).
    Junit,
    /// SARIF 2.1.0: a result per failing, accepted or noted target, for
    /// code-scanning dashboards (gates only).
    Sarif,
}

impl ReportFormat {
    /// The data format, `None` for the CI formats.
    pub fn data(self) -> Option<Format> {
        match self {
            ReportFormat::Table => Some(Format::Table),
            ReportFormat::Csv => Some(Format::Csv),
            ReportFormat::Json => Some(Format::Json),
            ReportFormat::Github | ReportFormat::Junit | ReportFormat::Sarif => None,
        }
    }

    fn name(self) -> &'static str {
        match self {
            ReportFormat::Table => "table",
            ReportFormat::Csv => "csv",
            ReportFormat::Json => "json",
            ReportFormat::Github => "github",
            ReportFormat::Junit => "junit",
            ReportFormat::Sarif => "sarif",
        }
    }
}

/// `correct`: the CI formats report `--check`, on standard output, where
/// `--diff` writes its diff.
pub fn refuse_outside_check(format: ReportFormat, check: bool, diff: bool) -> Result<()> {
    if format.data().is_some() {
        return Ok(());
    }
    let name = format.name();
    if !check {
        return Err(Error::usage(format!(
            "--format {name} reports what --check finds (a gate for CI): add --check, or use --format table, csv or json for the corrections"
        )));
    }
    if diff {
        return Err(Error::usage(format!(
            "--format {name} writes the check's report on standard output, where --diff writes the diff: drop one of them"
        )));
    }
    Ok(())
}

/// `diff`: the CI formats report the gate.
pub fn refuse_outside_gate(format: ReportFormat, gate: bool) -> Result<()> {
    match format.data() {
        None if !gate => Err(Error::usage(format!(
            "--format {} reports a gate (for CI): add --fail-above MM or --fail-above-deg DEG, or use --format table, csv or json for the comparison",
            format.name()
        ))),
        _ => Ok(()),
    }
}

/// One task `correct --check` checked.
pub struct CheckedTask<'a> {
    /// The task's name in a backup; `None` for files given one by one.
    pub task: Option<String>,
    /// Its files, as named on the command line (or found in the backup).
    pub files: Vec<&'a str>,
    pub outcome: &'a Outcome,
}

/// The report of `correct --check` in a CI format.
pub fn check(format: ReportFormat, tasks: &[CheckedTask], rule: &CheckRule) -> Result<String> {
    let mut suites: Vec<Suite> = Vec::new();
    let mut counts = [0usize; 3];
    let properties = check_properties(rule);
    for t in tasks {
        let mut cases = check_cases(t.outcome, rule, &mut counts);
        match &t.task {
            Some(label) => suites.push(Suite {
                name: label.clone(),
                properties: properties.clone(),
                per_file: true,
                cases,
            }),
            None => {
                // A suite per file, each with its own targets, in the order
                // given; a file without targets is an empty suite.
                for f in &t.files {
                    let (mine, rest): (Vec<Case>, Vec<Case>) =
                        cases.into_iter().partition(|c| c.file == *f);
                    cases = rest;
                    suites.push(Suite {
                        name: f.to_string(),
                        properties: properties.clone(),
                        per_file: false,
                        cases: mine,
                    });
                }
                for c in cases {
                    suite_for(&mut suites, &c.file, &properties).push(c);
                }
            }
        }
    }
    let [moves, cold, off] = counts;
    let corrected: usize = tasks.iter().map(|t| t.outcome.corrections.len()).sum();
    let mut failing = Vec::new();
    if moves > 0 {
        failing.push(format!(
            "{moves} target(s) would move more than {} mm",
            rule.tolerance
        ));
    }
    if cold > 0 {
        failing.push(format!("{cold} target(s) left cold"));
    }
    if off > 0 {
        failing.push(format!(
            "{off} use(s) with another tool or work object land more than {} mm off",
            rule.tolerance
        ));
    }
    let summary = if failing.is_empty() {
        format!(
            "{corrected} target(s) corrected; none moves more than {} mm and none is left cold: the check passes",
            rule.tolerance
        )
    } else {
        format!(
            "{corrected} target(s) corrected; {}: the check fails",
            failing.join(", ")
        )
    };
    render(format, "rapidtherm correct --check", &suites, &summary)
}

fn check_properties(rule: &CheckRule) -> Vec<(String, String)> {
    let mut p = vec![("tolerance_mm".to_string(), rule.tolerance.to_string())];
    if !rule.accepted.is_empty() {
        let codes: Vec<&str> = rule.accepted.iter().map(|r| r.code()).collect();
        p.push(("accept".to_string(), codes.join(",")));
    }
    p
}

/// A case per corrected target, per target left alone and per use with
/// other frames; `counts` adds up the failures by kind (moves, left
/// cold, lands off).
fn check_cases(outcome: &Outcome, rule: &CheckRule, counts: &mut [usize; 3]) -> Vec<Case> {
    let mut cases = Vec::new();
    for c in &outcome.corrections {
        let when = match c.time_min {
            Some(t) => format!("minute {t}"),
            None => "the steady state".to_string(),
        };
        let moves = rule.moves(c);
        counts[0] += usize::from(moves);
        cases.push(Case {
            name: c.id.clone(),
            file: c.file.clone(),
            line: c.line,
            col: c.col,
            level: if moves { GateLevel::Error } else { GateLevel::Pass },
            kind: "moves",
            title: format!("{} would move {} mm", c.id, mm(c.correction_norm_mm, 4)),
            message: format!(
                "{} ({}) would move {} mm, corrected for {when}: more than the tolerance of {} mm (run rapidtherm correct to rewrite it)",
                c.id,
                c.kind,
                mm(c.correction_norm_mm, 4),
                rule.tolerance
            ),
        });
    }
    // Derived targets pass: left as written, their bases' correction
    // carries them.
    for d in &outcome.derived {
        cases.push(Case {
            name: d.id.clone(),
            file: d.file.clone(),
            line: d.line,
            col: 0,
            level: GateLevel::Pass,
            kind: "derived",
            title: String::new(),
            message: String::new(),
        });
    }
    for l in &outcome.left_alone {
        let cold = rule.left_cold(l);
        counts[1] += usize::from(cold);
        let code = l.reason.code();
        let words = reason_words(l.reason, l.kind, &l.detail);
        let (level, title, message) = if cold {
            (
                GateLevel::Error,
                format!("{} left cold ({code})", l.id),
                format!(
                    "{} ({}) left cold [{code}]: {words} (accept with --accept {code})",
                    l.id, l.kind
                ),
            )
        } else if l.reason.leaves_target_cold() {
            (
                GateLevel::Skip,
                format!("{} left cold ({code}), accepted", l.id),
                format!(
                    "{} ({}) left cold [{code}], accepted: {words}",
                    l.id, l.kind
                ),
            )
        } else {
            (
                GateLevel::Notice,
                format!("{} left alone ({code})", l.id),
                format!("{} ({}) left alone [{code}]: {words}", l.id, l.kind),
            )
        };
        cases.push(Case {
            name: l.id.clone(),
            file: l.file.clone(),
            line: l.line,
            col: l.col,
            level,
            kind: code,
            title,
            message,
        });
    }
    for u in &outcome.shared {
        let off = rule.lands_off(u);
        counts[2] += usize::from(off);
        // Within the tolerance it passes as a correction that small does;
        // beyond it, only because the user accepted shared frames.
        let level = match u.residual_mm {
            _ if off => GateLevel::Error,
            Some(r) if r <= rule.tolerance => GateLevel::Notice,
            _ => GateLevel::Skip,
        };
        let code = Reason::SharedFrames.code();
        cases.push(Case {
            name: u.id.clone(),
            file: u.file.clone(),
            line: u.line,
            col: u.col,
            level,
            kind: code,
            title: format!("{} used with other frames", u.id),
            message: format!("other use of {} [{code}]: {}", u.id, shared_words(u)),
        });
    }
    // An already-corrected program has nothing left to correct, but its
    // moves' targets still pass the check: a passing case each, at the
    // move, so that the report counts what was checked (not tests="0").
    if outcome.already_corrected.is_some() {
        let mut seen: HashSet<(String, String)> = cases
            .iter()
            .map(|c| (c.name.clone(), c.file.clone()))
            .collect();
        for m in &outcome.moves {
            if seen.insert((m.target.clone(), m.file.clone())) {
                cases.push(Case {
                    name: m.target.clone(),
                    file: m.file.clone(),
                    line: m.line,
                    col: m.col,
                    level: GateLevel::Pass,
                    kind: "already-corrected",
                    title: String::new(),
                    message: String::new(),
                });
            }
        }
    }
    cases
}

/// One pair of programs `diff` compared: the whole files, or one task of
/// two backups.
pub struct Compared<'a> {
    /// The task's name in a backup; `None` for two files.
    pub task: Option<String>,
    /// The two programs as named on the command line.
    pub names: (&'a str, &'a str),
    pub programs: (&'a Program, &'a Program),
    pub diff: &'a Diff,
}

/// The report of `diff --fail-above` in a CI format; `unpaired` are the
/// tasks of one backup that the other lacks (each fails the gate).
pub fn gate(
    format: ReportFormat,
    gate: Option<&Gate>,
    pairs: &[Compared],
    unpaired: &[String],
) -> Result<String> {
    refuse_outside_gate(format, gate.is_some())?;
    let Some(gate) = gate else {
        return Err(Error::usage("no gate to report"));
    };
    let limits = limits(gate);
    let properties = vec![
        ("max_mm".to_string(), gate.max_mm.to_string()),
        ("max_deg".to_string(), gate.max_deg.to_string()),
    ];
    let mut suites = Vec::new();
    let mut failed = 0;
    for p in pairs {
        let failures = p.diff.gate(gate);
        failed += failures.len();
        let (a, b) = (places(p.programs.0), places(p.programs.1));
        let (na, nb) = p.names;
        let moved: HashSet<&str> = failures
            .iter()
            .filter_map(|f| match f {
                GateFailure::Moved(t) => Some(t.id.as_str()),
                _ => None,
            })
            .collect();
        let mut cases = Vec::new();
        for t in &p.diff.targets {
            let fails = moved.contains(t.id.as_str());
            let (moved, title) = if t.kind == DataType::Jointtarget {
                let turned = format!("a joint turned {}°", mm(t.dangle, 6));
                (turned.clone(), format!("{} {turned}", t.id))
            } else {
                (
                    format!("moved {} mm, turned {}°", mm(t.dist, 4), mm(t.dangle, 6)),
                    format!("{} moved {} mm", t.id, mm(t.dist, 4)),
                )
            };
            cases.push(located(
                &b,
                &t.id,
                nb,
                if fails {
                    GateLevel::Error
                } else {
                    GateLevel::Pass
                },
                "moved",
                title,
                format!(
                    "{} ({}) {moved}{} from {na} to {nb}: {}",
                    t.id,
                    t.kind,
                    t.also_changed()
                        .iter()
                        .map(|w| format!(", {w}"))
                        .collect::<String>(),
                    if t.also_changed().is_empty() {
                        format!("more than the gate of {limits}")
                    } else {
                        "a thermal correction changes neither robconf nor external axes".to_string()
                    }
                ),
            ));
        }
        for f in &failures {
            let (program, id, name, other) = match f {
                GateFailure::OnlyInFirst(id) => (&a, id, na, nb),
                GateFailure::OnlyInSecond(id) => (&b, id, nb, na),
                GateFailure::NothingCompared => {
                    cases.push(Case {
                        name: "targets in common".to_string(),
                        file: nb.to_string(),
                        line: 0,
                        col: 0,
                        level: GateLevel::Error,
                        kind: "nothing-compared",
                        title: "no target in common".to_string(),
                        message: format!(
                            "{na} and {nb} have no target in common: nothing was compared, the gate fails"
                        ),
                    });
                    continue;
                }
                GateFailure::Moved(_) => continue,
            };
            cases.push(located(
                program,
                id,
                name,
                GateLevel::Error,
                "only-in-one",
                format!("{id} is only in {name}"),
                format!("{id} is only in {name}, not in {other}: its change is unknown"),
            ));
        }
        suites.push(Suite {
            name: p.task.clone().unwrap_or_else(|| nb.to_string()),
            properties: properties.clone(),
            per_file: p.task.is_some(),
            cases,
        });
    }
    for u in unpaired {
        failed += 1;
        suites.push(Suite {
            name: u.clone(),
            properties: properties.clone(),
            per_file: true,
            cases: vec![Case {
                name: u.clone(),
                file: String::new(),
                line: 0,
                col: 0,
                level: GateLevel::Error,
                kind: "only-in-one",
                title: u.clone(),
                message: format!("{u}: its targets were not compared"),
            }],
        });
    }
    let compared: usize = pairs.iter().map(|p| p.diff.summary.compared).sum();
    let summary = if failed == 0 {
        format!("{compared} target(s) compared, all within the gate of {limits}")
    } else {
        format!("{compared} target(s) compared; {failed} fail the gate of {limits}")
    };
    render(format, "rapidtherm diff", &suites, &summary)
}

/// The gate's limits in words: `0.05 mm and 0.0286°`.
fn limits(gate: &Gate) -> String {
    let mut parts = Vec::new();
    if gate.max_mm.is_finite() {
        parts.push(format!("{} mm", gate.max_mm));
    }
    if gate.max_deg.is_finite() {
        parts.push(format!("{}°", mm(gate.max_deg, 4)));
    }
    parts.join(" and ")
}

/// Where each robtarget and jointtarget of a program is, by identifier
/// (RAPID's are case-insensitive): file, line, column.
type Places = HashMap<String, (String, u32, u32)>;

fn places(program: &Program) -> Places {
    let origins = program
        .targets()
        .iter()
        .map(|t| (t.id.clone(), t.origin.clone()))
        .chain(
            program
                .jointtargets()
                .iter()
                .map(|j| (j.id.clone(), j.origin.clone())),
        );
    let mut places = Places::new();
    for (id, origin) in origins {
        let l = program.location(&origin);
        // The first of a name, as `Program::target` finds it.
        places
            .entry(id.to_ascii_lowercase())
            .or_insert((l.file, l.line as u32, l.col as u32));
    }
    places
}

/// A case for target `id`, at its place (`file` and no line when the
/// program has no target of that name).
fn located(
    places: &Places,
    id: &str,
    file: &str,
    level: GateLevel,
    kind: &'static str,
    title: String,
    message: String,
) -> Case {
    let (file, line, col) = places
        .get(&id.to_ascii_lowercase())
        .cloned()
        .unwrap_or_else(|| (file.to_string(), 0, 0));
    Case {
        name: id.to_string(),
        file,
        line,
        col,
        level,
        kind,
        title,
        message,
    }
}

fn suite_for<'s>(
    suites: &'s mut Vec<Suite>,
    name: &str,
    properties: &[(String, String)],
) -> &'s mut Vec<Case> {
    let k = match suites.iter().position(|s| s.name == name) {
        Some(k) => k,
        None => {
            suites.push(Suite {
                name: name.to_string(),
                properties: properties.to_vec(),
                per_file: false,
                cases: Vec::new(),
            });
            suites.len() - 1
        }
    };
    &mut suites[k].cases
}

fn render(format: ReportFormat, gate: &str, suites: &[Suite], summary: &str) -> Result<String> {
    match format {
        ReportFormat::Github => Ok(github(gate, suites, summary)),
        ReportFormat::Junit => super::junit::write(gate, suites),
        ReportFormat::Sarif => super::sarif::write(gate, suites),
        other => Err(Error::usage(format!(
            "--format {} is not a CI report",
            other.name()
        ))),
    }
}

/// GitHub Actions workflow commands, one per case that is not a plain
/// pass, then the verdict as a notice.
fn github(gate: &str, suites: &[Suite], summary: &str) -> String {
    let mut out = String::new();
    for c in suites.iter().flat_map(|s| &s.cases) {
        let command = match c.level {
            GateLevel::Pass => continue,
            GateLevel::Notice => "notice",
            GateLevel::Skip => "warning",
            GateLevel::Error => "error",
        };
        let mut properties = Vec::new();
        if !c.file.is_empty() {
            properties.push(format!("file={}", escape_property(&c.file)));
        }
        if c.line > 0 {
            properties.push(format!("line={}", c.line));
            if c.col > 0 {
                properties.push(format!("col={}", c.col));
            }
        }
        properties.push(format!("title={}", escape_property(&c.title)));
        out.push_str(&format!(
            "::{command} {}::{}\n",
            properties.join(","),
            escape_data(&c.message)
        ));
    }
    out.push_str(&format!(
        "::notice title={}::{}\n",
        escape_property(gate),
        escape_data(summary)
    ));
    out
}

/// A workflow command's message: `%`, CR and LF escaped (GitHub's
/// `escapeData`).
fn escape_data(text: &str) -> String {
    text.replace('%', "%25")
        .replace('\r', "%0D")
        .replace('\n', "%0A")
}

/// A workflow command's property value: as data, and `:` and `,`, which
/// end a value (GitHub's `escapeProperty`).
fn escape_property(text: &str) -> String {
    escape_data(text).replace(':', "%3A").replace(',', "%2C")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_as_github_does() {
        assert_eq!(escape_data("50% a:b,c\r\nd"), "50%25 a:b,c%0D%0Ad");
        assert_eq!(escape_property("50% a:b,c\r\nd"), "50%25 a%3Ab%2Cc%0D%0Ad");
        // `%` first: an escape is not escaped again.
        assert_eq!(escape_property("%3A"), "%253A");
    }
}
