//! JUnit XML of a gate's cases (`ci_report`): a `<testsuite>` per file or
//! task, a `<testcase>` per target (per file for a task of a backup), a
//! `<failure>` where it fails the gate. Valid under the Apache Ant JUnit
//! schema that Jenkins, GitLab and most readers follow
//! (`tests/data/ant-junit/JUnit.xsd`, docs/ci.md): every suite has its
//! timestamp, host name, time, properties, system-out and system-err, and
//! every case its time.

use super::ci_suite::{Case, GateLevel, Suite};
use quick_xml::events::{BytesDecl, BytesText, Event};
use quick_xml::Writer;
use rapidtherm::error::{Error, Result};
use std::collections::HashMap;
use std::sync::OnceLock;
use std::time::{Instant, SystemTime, UNIX_EPOCH};

/// When the run started: the suites' timestamp, and the start of their time.
static START: OnceLock<(Instant, SystemTime)> = OnceLock::new();

/// Note the run's start (called first thing by `cli::main`).
pub fn start_clock() {
    START.get_or_init(|| (Instant::now(), SystemTime::now()));
}

/// `2026-12-02T16:04:32`: UTC without a zone, as the Ant schema's
/// `ISO8601_DATETIME_PATTERN` wants it (a zone is not allowed).
fn timestamp(at: SystemTime) -> String {
    let secs = at.duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs());
    let (days, rest) = ((secs / 86_400) as i64, secs % 86_400);
    // Days since 1970-01-01 to a civil date: the interpreter's calendar
    // counts from 2000-01-01, 10,957 days later.
    let (year, month, day) = rapidtherm::interp::clock::civil_from_days(days - 10_957);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}",
        rest / 3600,
        rest % 3600 / 60,
        rest % 60
    )
}

/// The machine's name; `localhost` when it cannot be told, as the Ant
/// schema says.
fn hostname() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .ok()
        .or_else(|| std::env::var("HOSTNAME").ok())
        .or_else(|| std::env::var("COMPUTERNAME").ok())
        .map(|h| h.trim().to_string())
        .filter(|h| !h.is_empty())
        .unwrap_or_else(|| "localhost".to_string())
}

/// The document: `<testsuites>` and a suite each. The targets are checked
/// together, not one by one: each case's time is 0, and the run's time
/// (from its start to the report) is the first suite's, so that the
/// suites' times add up to it.
pub fn write(gate: &str, suites: &[Suite]) -> Result<String> {
    start_clock();
    let (started, at) = START
        .get()
        .copied()
        .unwrap_or((Instant::now(), SystemTime::now()));
    let elapsed = format!("{:.3}", started.elapsed().as_secs_f64());
    let stamp = timestamp(at);
    let host = xml_safe(&hostname());
    let merged: Vec<(&Suite, Vec<Target>)> = suites.iter().map(|s| (s, targets(s))).collect();
    let count = |targets: &[Target], level: GateLevel| -> usize {
        targets.iter().filter(|t| t.level == level).count()
    };
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    let io = |e: std::io::Error| Error::input(format!("writing JUnit XML: {e}"));
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))
        .map_err(io)?;
    // The Ant schema gives <testsuites> no attributes: the gate's name is
    // each suite's `package`'s prefix, its totals the suites'.
    w.create_element("testsuites")
        .write_inner_content(|w| {
            for (k, (suite, targets)) in merged.iter().enumerate() {
                let tests = targets.len().to_string();
                let failures = count(targets, GateLevel::Error).to_string();
                let skipped = count(targets, GateLevel::Skip).to_string();
                let id = k.to_string();
                let name = xml_safe(&suite.name);
                let package = format!("{} {name}", xml_safe(gate));
                let time = if k == 0 { elapsed.as_str() } else { "0" };
                w.create_element("testsuite")
                    .with_attributes([
                        ("name", name.as_str()),
                        ("package", package.as_str()),
                        ("id", id.as_str()),
                        ("timestamp", stamp.as_str()),
                        ("hostname", host.as_str()),
                        ("tests", tests.as_str()),
                        ("failures", failures.as_str()),
                        ("errors", "0"),
                        ("skipped", skipped.as_str()),
                        ("time", time),
                    ])
                    .write_inner_content(|w| {
                        w.create_element("properties").write_inner_content(|w| {
                            for (name, value) in &suite.properties {
                                w.create_element("property")
                                    .with_attributes([
                                        ("name", xml_safe(name).as_str()),
                                        ("value", xml_safe(value).as_str()),
                                    ])
                                    .write_empty()?;
                            }
                            Ok(())
                        })?;
                        for t in targets {
                            testcase(w, t)?;
                        }
                        // Notices have no place in an Ant test case: the
                        // suite's output holds them, a line each.
                        let notes: String = targets
                            .iter()
                            .flat_map(|t| &t.cases)
                            .filter(|c| c.level == GateLevel::Notice)
                            .map(|c| format!("{}{}\n", at_words(c), c.message))
                            .collect();
                        w.create_element("system-out")
                            .write_text_content(BytesText::new(&xml_safe(&notes)))?;
                        w.create_element("system-err")
                            .write_text_content(BytesText::new(""))?;
                        Ok(())
                    })?;
            }
            Ok(())
        })
        .map_err(io)?;
    let mut text = String::from_utf8(w.into_inner()).map_err(|e| Error::input(e.to_string()))?;
    text.push('\n');
    Ok(text)
}

/// The cases of one target (its correction and its uses with other
/// frames), or of one file of a backup's task, as one test case: it fails
/// if any of them fails.
struct Target<'a> {
    name: &'a str,
    classname: &'a str,
    level: GateLevel,
    cases: Vec<&'a Case>,
}

fn targets(suite: &Suite) -> Vec<Target<'_>> {
    let mut out: Vec<Target> = Vec::new();
    // A backup's program may have tens of thousands of targets.
    let mut index: HashMap<(&str, &str), usize> = HashMap::new();
    for c in &suite.cases {
        // Per file: the file is the case's name, the task its class.
        let (name, classname) = if suite.per_file {
            (c.file.as_str(), suite.name.as_str())
        } else {
            (c.name.as_str(), c.file.as_str())
        };
        match index.get(&(name, classname)) {
            Some(&k) => {
                out[k].level = out[k].level.max(c.level);
                out[k].cases.push(c);
            }
            None => {
                index.insert((name, classname), out.len());
                out.push(Target {
                    name,
                    classname,
                    level: c.level,
                    cases: vec![c],
                });
            }
        }
    }
    out
}

/// `file:line:col: `, as much of it as is known.
fn at_words(c: &Case) -> String {
    match (c.line, c.col) {
        (0, _) => format!("{}: ", c.file),
        (l, 0) => format!("{}:{l}: ", c.file),
        (l, col) => format!("{}:{l}:{col}: ", c.file),
    }
}

fn testcase(w: &mut Writer<Vec<u8>>, t: &Target) -> std::io::Result<()> {
    let of = |level: GateLevel| -> Vec<&Case> {
        t.cases
            .iter()
            .copied()
            .filter(|c| c.level == level)
            .collect()
    };
    // A case without a name (a file given as `-`) still needs one.
    let name = if t.name.is_empty() { "-" } else { t.name };
    let element = w.create_element("testcase").with_attributes([
        ("name", xml_safe(name).as_str()),
        ("classname", xml_safe(t.classname).as_str()),
        ("time", "0"),
    ]);
    // The worst verdict is the test's; the message names every case at it.
    let worst = match t.level {
        GateLevel::Error => of(GateLevel::Error),
        GateLevel::Skip => of(GateLevel::Skip),
        _ => Vec::new(),
    };
    if worst.is_empty() {
        element.write_empty()?;
        return Ok(());
    }
    element.write_inner_content(|w| {
        // A file of a backup may fail with thousands of targets: the
        // message names the first three, the text every one.
        let mut message: Vec<String> = worst.iter().take(3).map(|c| c.message.clone()).collect();
        if worst.len() > 3 {
            message.push(format!("and {} more", worst.len() - 3));
        }
        let body: String = worst
            .iter()
            .map(|c| format!("{}{}\n", at_words(c), c.message))
            .collect();
        let message = xml_safe(&message.join("; "));
        let body = xml_safe(&body);
        if t.level == GateLevel::Error {
            w.create_element("failure")
                .with_attributes([("message", message.as_str()), ("type", worst[0].kind)])
                .write_text_content(BytesText::new(&body))?;
        } else {
            // The Ant schema's <skipped> has a message and no type.
            w.create_element("skipped")
                .with_attributes([("message", message.as_str())])
                .write_text_content(BytesText::new(&body))?;
        }
        Ok(())
    })?;
    Ok(())
}

/// XML 1.0 has no way to write most control characters, escaped or not (a
/// file name may hold one): each becomes U+FFFD.
fn xml_safe(text: &str) -> String {
    text.chars()
        .map(|c| match c {
            '\t' | '\n' | '\r' => c,
            c if c < ' ' || c == '\u{FFFE}' || c == '\u{FFFF}' => '\u{FFFD}',
            c => c,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timestamps_are_civil_dates_in_utc() {
        // 1e9 s after the epoch: 2001-09-09 01:46:40 UTC (date -u -d @1000000000).
        let at = UNIX_EPOCH + std::time::Duration::from_secs(1_000_000_000);
        assert_eq!(timestamp(at), "2001-09-09T01:46:40");
        // A leap day: 2024-02-29 00:00:00 UTC is 1709164800.
        let at = UNIX_EPOCH + std::time::Duration::from_secs(1_709_164_800);
        assert_eq!(timestamp(at), "2024-02-29T00:00:00");
    }

    #[test]
    fn control_characters_are_replaced_not_written() {
        assert_eq!(
            xml_safe("a\u{1}b\tc\nd\u{FFFF}"),
            "a\u{FFFD}b\tc\nd\u{FFFD}"
        );
    }
}
