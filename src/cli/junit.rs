//! JUnit XML of a gate's cases (`ci_report`): a `<testsuite>` per file or
//! task, a `<testcase>` per target, a `<failure>` where it fails the gate.
//! The dialect Jenkins and GitLab read; `tests/junit/junit.xsd` pins it.

use super::ci_suite::{Case, GateLevel, Suite};
use quick_xml::events::{BytesDecl, BytesText, Event};
use quick_xml::Writer;
use rapidtherm::error::{Error, Result};
use std::collections::HashMap;

/// The document: `<testsuites name="{gate}">` and a suite each.
pub fn write(gate: &str, suites: &[Suite]) -> Result<String> {
    let merged: Vec<(&Suite, Vec<Target>)> = suites.iter().map(|s| (s, targets(s))).collect();
    let count = |targets: &[Target], level: GateLevel| -> usize {
        targets.iter().filter(|t| t.level == level).count()
    };
    let all: Vec<&Target> = merged.iter().flat_map(|(_, t)| t).collect();
    let total = all.len().to_string();
    let failures = all
        .iter()
        .filter(|t| t.level == GateLevel::Error)
        .count()
        .to_string();
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    let io = |e: std::io::Error| Error::input(format!("writing JUnit XML: {e}"));
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))
        .map_err(io)?;
    w.create_element("testsuites")
        .with_attributes([
            ("name", xml_safe(gate).as_str()),
            ("tests", total.as_str()),
            ("failures", failures.as_str()),
            ("errors", "0"),
        ])
        .write_inner_content(|w| {
            for (suite, targets) in &merged {
                let tests = targets.len().to_string();
                let failures = count(targets, GateLevel::Error).to_string();
                let skipped = count(targets, GateLevel::Skip).to_string();
                w.create_element("testsuite")
                    .with_attributes([
                        ("name", xml_safe(&suite.name).as_str()),
                        ("tests", tests.as_str()),
                        ("failures", failures.as_str()),
                        ("errors", "0"),
                        ("skipped", skipped.as_str()),
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

/// The cases of one target (its correction and its uses with other frames)
/// as one test case: it fails if any of them fails.
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
        match index.get(&(c.name.as_str(), c.file.as_str())) {
            Some(&k) => {
                out[k].level = out[k].level.max(c.level);
                out[k].cases.push(c);
            }
            None => {
                index.insert((&c.name, &c.file), out.len());
                out.push(Target {
                    name: &c.name,
                    classname: &c.file,
                    level: c.level,
                    cases: vec![c],
                });
            }
        }
    }
    out
}

fn testcase(w: &mut Writer<Vec<u8>>, t: &Target) -> std::io::Result<()> {
    let at = |c: &Case| match (c.line, c.col) {
        (0, _) => format!("{}: ", c.file),
        (l, 0) => format!("{}:{l}: ", c.file),
        (l, col) => format!("{}:{l}:{col}: ", c.file),
    };
    let of = |level: GateLevel| -> Vec<&Case> {
        t.cases
            .iter()
            .copied()
            .filter(|c| c.level == level)
            .collect()
    };
    let element = w.create_element("testcase").with_attributes([
        ("name", xml_safe(t.name).as_str()),
        ("classname", xml_safe(t.classname).as_str()),
    ]);
    if t.cases.iter().all(|c| c.level == GateLevel::Pass) {
        element.write_empty()?;
        return Ok(());
    }
    element.write_inner_content(|w| {
        // The worst verdict is the test's; the message names every case at it.
        let (tag, worst) = match t.level {
            GateLevel::Error => ("failure", of(GateLevel::Error)),
            GateLevel::Skip => ("skipped", of(GateLevel::Skip)),
            _ => ("", Vec::new()),
        };
        if !worst.is_empty() {
            let message: Vec<&str> = worst.iter().map(|c| c.message.as_str()).collect();
            let body: String = worst
                .iter()
                .map(|c| format!("{}{}\n", at(c), c.message))
                .collect();
            w.create_element(tag)
                .with_attributes([
                    ("message", xml_safe(&message.join("; ")).as_str()),
                    ("type", worst[0].kind),
                ])
                .write_text_content(BytesText::new(&xml_safe(&body)))?;
        }
        let notes: String = of(GateLevel::Notice)
            .iter()
            .map(|c| format!("{}{}\n", at(c), c.message))
            .collect();
        if !notes.is_empty() {
            w.create_element("system-out")
                .write_text_content(BytesText::new(&xml_safe(&notes)))?;
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
    fn control_characters_are_replaced_not_written() {
        assert_eq!(
            xml_safe("a\u{1}b\tc\nd\u{FFFF}"),
            "a\u{FFFD}b\tc\nd\u{FFFD}"
        );
    }
}
