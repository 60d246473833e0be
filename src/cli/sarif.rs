//! SARIF 2.1.0 of a gate's cases (`ci_report`), for code-scanning
//! dashboards (GitHub code scanning, GitLab, Azure DevOps): one run, the
//! tool `rapidtherm` with a rule per kind of finding, and a result per
//! case that does not plainly pass, at its file, line and column. See
//! docs/ci.md; the fields are those of the OASIS SARIF 2.1.0 standard's
//! minimal log (§3.13 sarifLog, §3.14 run, §3.19 tool, §3.27 result).

use super::ci_suite::{GateLevel, Suite};
use rapidtherm::error::Result;
use serde_json::{json, Value};

const SCHEMA: &str = "https://json.schemastore.org/sarif-2.1.0.json";

/// What each kind of finding means, for the rule's short description.
fn rule_words(kind: &str) -> String {
    match kind {
        "moves" => {
            "a target would move more than the tolerance if the program were corrected now".into()
        }
        "moved" => {
            "a target moved more than the gate, or its robconf or external axes changed".into()
        }
        "only-in-one" => "a target (or task) is in one program only".into(),
        "nothing-compared" => "the two programs have no target in common".into(),
        "shared-frames" => {
            "a target is moved to with another tool or work object than it is corrected for".into()
        }
        reason => format!("a target is left cold: {reason} (docs/correct.md)"),
    }
}

/// A file name as a URI reference relative to the repository root:
/// characters a URI cannot hold percent-encoded, `/` kept.
fn uri(file: &str) -> String {
    let mut out = String::new();
    for b in file.replace('\\', "/").bytes() {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'.' | b'_' | b'~' | b'/' => {
                out.push(b as char)
            }
            _ => out.push_str(&format!("%{b:02X}")),
        }
    }
    out
}

/// The log: a result per case that fails (`error`), is accepted cold
/// (`warning`) or is noted (`note`); cases that pass are not results.
pub fn write(gate: &str, suites: &[Suite]) -> Result<String> {
    let mut kinds: Vec<&str> = Vec::new();
    let mut results = Vec::new();
    for c in suites.iter().flat_map(|s| &s.cases) {
        let level = match c.level {
            GateLevel::Pass => continue,
            GateLevel::Notice => "note",
            GateLevel::Skip => "warning",
            GateLevel::Error => "error",
        };
        let rule_index = match kinds.iter().position(|k| *k == c.kind) {
            Some(k) => k,
            None => {
                kinds.push(c.kind);
                kinds.len() - 1
            }
        };
        let mut physical = json!({ "artifactLocation": { "uri": uri(&c.file) } });
        // SARIF's lines and columns start at 1: an unknown line has no region.
        if c.line > 0 {
            let mut region = json!({ "startLine": c.line });
            if c.col > 0 {
                region["startColumn"] = c.col.into();
            }
            physical["region"] = region;
        }
        results.push(json!({
            "ruleId": c.kind,
            "ruleIndex": rule_index,
            "level": level,
            "message": { "text": c.message },
            "locations": [{ "physicalLocation": physical }],
            "partialFingerprints": { "target/v1": format!("{}:{}", c.file, c.name) },
        }));
    }
    let rules: Vec<Value> = kinds
        .iter()
        .map(|k| json!({ "id": k, "shortDescription": { "text": rule_words(k) } }))
        .collect();
    let log = json!({
        "$schema": SCHEMA,
        "version": "2.1.0",
        "runs": [{
            "tool": { "driver": {
                "name": "rapidtherm",
                "version": env!("CARGO_PKG_VERSION"),
                "rules": rules,
            }},
            "automationDetails": { "id": format!("{gate}/") },
            "results": results,
        }],
    });
    Ok(rapidtherm::report::json::to_string(&log)? + "\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uris_are_percent_encoded_relative_references() {
        // RFC 3986: unreserved characters and `/` stay, the rest is %XX of
        // its UTF-8 bytes.
        assert_eq!(uri("RAPID/TASK1/a b,c.mod"), "RAPID/TASK1/a%20b%2Cc.mod");
        assert_eq!(uri("ü.mod"), "%C3%BC.mod");
    }
}
