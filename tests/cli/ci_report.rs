//! The CI reports of the two gates (`--format github|junit` of `correct
//! --check` and `diff --fail-above`): every GitHub line parses as a
//! workflow command and says what it should, file names and messages
//! escaped; every JUnit report is valid under the Apache Ant JUnit schema,
//! `tests/data/ant-junit/JUnit.xsd` (read and applied by `tests/junit/xsd.rs`:
//! no system tool needed) and its counts add up; every SARIF log has the
//! fields SARIF 2.1.0 requires.

#[path = "../junit/xsd.rs"]
mod xsd;

use quick_xml::events::Event;
use quick_xml::Reader;
use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_rapidtherm");

struct Run {
    code: i32,
    stdout: String,
}

fn run(args: &[&str]) -> Run {
    let out = Command::new(BIN).args(args).output().unwrap();
    Run {
        code: out.status.code().unwrap(),
        stdout: String::from_utf8(out.stdout).unwrap(),
    }
}

/// A file name that needs every escape a property value has: `,`, `:`,
/// `%`, and a line break.
const ODD: &str = "odd, name: 50%\nof it.mod";

fn odd_copy(dir: &Path, from: &str, suffix: &str) -> PathBuf {
    let to = dir.join(format!("{ODD}{suffix}"));
    std::fs::copy(from, &to).unwrap();
    to
}

/// One workflow command: `::name key=value,...::data`, parsed by GitHub's
/// grammar, values and data unescaped.
#[derive(Debug)]
struct WorkflowCommand {
    name: String,
    properties: Vec<(String, String)>,
    data: String,
}

impl WorkflowCommand {
    fn get(&self, key: &str) -> Option<&str> {
        self.properties
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
}

/// Undo GitHub's escapes; anything else after a `%` is not an escape
/// GitHub writes, and fails.
fn unescape(text: &str, escapes: &[(&str, char)]) -> Result<String, String> {
    let mut out = String::new();
    let mut rest = text;
    while let Some(i) = rest.find('%') {
        out.push_str(&rest[..i]);
        let code = rest.get(i + 1..i + 3).unwrap_or("");
        let Some((_, c)) = escapes.iter().find(|(e, _)| *e == code) else {
            return Err(format!("`%{code}` is no escape in {text:?}"));
        };
        out.push(*c);
        rest = &rest[i + 3..];
    }
    out.push_str(rest);
    Ok(out)
}

const DATA: &[(&str, char)] = &[("25", '%'), ("0D", '\r'), ("0A", '\n')];
const PROPERTY: &[(&str, char)] = &[
    ("25", '%'),
    ("0D", '\r'),
    ("0A", '\n'),
    ("3A", ':'),
    ("2C", ','),
];

fn parse(line: &str) -> Result<WorkflowCommand, String> {
    let rest = line
        .strip_prefix("::")
        .ok_or_else(|| format!("does not start with `::`: {line:?}"))?;
    // The first `::` ends the command and its properties: a value can
    // hold no `:` unescaped.
    let end = rest
        .find("::")
        .ok_or_else(|| format!("no `::` before the message: {line:?}"))?;
    let (head, data) = (&rest[..end], &rest[end + 2..]);
    if data.contains(['\r', '\n']) {
        return Err(format!("raw line break in the message: {line:?}"));
    }
    let (name, props) = head.split_once(' ').unwrap_or((head, ""));
    if !["error", "warning", "notice"].contains(&name) {
        return Err(format!("`{name}` is not an annotation command"));
    }
    let mut properties = Vec::new();
    for p in props.split(',').filter(|p| !p.is_empty()) {
        let (k, v) = p
            .split_once('=')
            .ok_or_else(|| format!("property without `=`: {p:?}"))?;
        if !["file", "line", "endLine", "col", "endColumn", "title"].contains(&k) {
            return Err(format!("unknown property `{k}`"));
        }
        if k != "title" && k != "file" && v.parse::<u32>().map_or(true, |n| n == 0) {
            return Err(format!("`{k}={v}` is not a line or column number"));
        }
        // GitHub's escapeProperty leaves no `:` in a value.
        if v.contains(':') {
            return Err(format!("raw `:` in `{k}={v}`"));
        }
        properties.push((k.to_string(), unescape(v, PROPERTY)?));
    }
    Ok(WorkflowCommand {
        name: name.to_string(),
        properties,
        data: unescape(data, DATA)?,
    })
}

fn commands(run: &Run) -> Vec<WorkflowCommand> {
    run.stdout
        .lines()
        .map(|l| parse(l).unwrap_or_else(|e| panic!("{e}\n{}", run.stdout)))
        .collect()
}

#[test]
fn the_grammar_refuses_what_github_would_misread() {
    assert!(parse("::error file=a.mod,line=3::x").is_ok());
    assert!(
        parse("::error file=a:b.mod::x").is_err(),
        "`:` in a value ends the properties"
    );
    assert!(parse("::error title=50%::x").is_err(), "a bare `%`");
    assert!(parse("::error line=x::x").is_err());
    assert!(parse("::debug::x").is_err());
    assert!(parse("error::x").is_err());
}

#[test]
fn github_check_annotates_each_target_at_its_place_with_names_escaped() {
    let dir = tempfile::tempdir().unwrap();
    let cell = odd_copy(dir.path(), "tests/cmd/correct_data/cell.mod", "");
    let cell = cell.to_str().unwrap();
    let r = run(&[
        "correct", cell, "--at", "60", "--check", "--format", "github",
    ]);
    assert_eq!(r.code, 1, "{}", r.stdout);
    let c = commands(&r);
    let errors: Vec<&WorkflowCommand> = c.iter().filter(|c| c.name == "error").collect();
    let places: Vec<(Option<&str>, Option<&str>, Option<&str>)> = errors
        .iter()
        .map(|e| (e.get("file"), e.get("line"), e.get("col")))
        .collect();
    // p10, p20 and the inline target of main, where the table puts them.
    assert_eq!(
        places,
        [
            (Some(cell), Some("4"), Some("26")),
            (Some(cell), Some("5"), Some("26")),
            (Some(cell), Some("9"), Some("15")),
        ]
    );
    assert!(errors[0].data.contains("p10") && errors[0].data.contains("0.0616 mm"));
    assert_eq!(c.last().unwrap().name, "notice");
    assert!(c.last().unwrap().data.contains("the check fails"));

    // Left cold: each target with its reason; accepted ones warn.
    let silent = odd_copy(dir.path(), "tests/cmd/correct_data/never_silent.mod", "2");
    let silent = silent.to_str().unwrap();
    let r = run(&[
        "correct", silent, "--at", "0", "--check", "--format", "github",
    ]);
    assert_eq!(r.code, 1);
    let c = commands(&r);
    let cold: Vec<&str> = c
        .iter()
        .filter(|c| c.name == "error")
        .map(|c| c.get("title").unwrap())
        .collect();
    assert_eq!(
        cold,
        [
            "pNamed left cold (expression)",
            "pExpr left cold (expression)",
            "pUnloadA left cold (runtime)",
            "pApproach left cold (runtime)",
            "jNamed left cold (expression)",
        ]
    );
    assert!(c.iter().all(|c| c.get("file").is_none_or(|f| f == silent)));
    let r = run(&[
        "correct",
        silent,
        "--at",
        "0",
        "--check",
        "--accept",
        "runtime,expression",
        "--format",
        "github",
    ]);
    assert_eq!(r.code, 0);
    let c = commands(&r);
    assert!(c.iter().all(|c| c.name != "error"), "{}", r.stdout);
    assert_eq!(c.iter().filter(|c| c.name == "warning").count(), 5);
}

#[test]
fn github_diff_names_the_file_a_target_is_in() {
    let dir = tempfile::tempdir().unwrap();
    let a = odd_copy(dir.path(), "tests/cmd/diff_data/joint_a.mod", "a");
    let b = odd_copy(dir.path(), "tests/cmd/diff_data/renamed.mod", "b");
    let (a, b) = (a.to_str().unwrap(), b.to_str().unwrap());
    let r = run(&["diff", a, b, "--fail-above", "0.15", "--format", "github"]);
    assert_eq!(r.code, 1);
    let c = commands(&r);
    let errors: Vec<(&str, &str)> = c
        .iter()
        .filter(|c| c.name == "error")
        .map(|c| (c.get("file").unwrap(), c.data.as_str()))
        .collect();
    assert_eq!(errors.len(), 2, "{}", r.stdout);
    // The names, `%` and line break and all, in properties and messages.
    assert!(r.stdout.contains("50%25%0Aof it.mod"), "{}", r.stdout);
    assert!(r.stdout.contains("odd%2C name%3A 50%25%0Aof it.moda"));
    assert_eq!(errors[0].0, a);
    assert_eq!(
        errors[0].1,
        format!("pCheck is only in {a}, not in {b}: its change is unknown")
    );
    assert_eq!(errors[1].0, b);
    assert!(errors[1].1.starts_with("pCheck2 is only in"));
    // Within the gate: the verdict alone.
    let r = run(&[
        "diff",
        "tests/cmd/correct_data/cell.mod",
        "tests/cmd/correct_data/cell_at60.mod",
        "--fail-above",
        "0.1",
        "--format",
        "github",
    ]);
    assert_eq!(r.code, 0);
    let c = commands(&r);
    assert_eq!(c.len(), 1);
    assert!(c[0].data.contains("all within the gate"), "{}", c[0].data);
}

/// Validate against our schema, read from the schema file itself.
fn validate(xml: &str) -> Result<(), String> {
    let text = std::fs::read_to_string(SCHEMA).unwrap();
    xsd::Schema::parse(&text)
        .unwrap_or_else(|e| panic!("{SCHEMA}: {e}"))
        .validate(xml)
}

const SCHEMA: &str = "tests/data/ant-junit/JUnit.xsd";

/// Counts of one element as its attributes say and as its children are.
#[derive(Debug, Default, PartialEq)]
struct Counts {
    tests: usize,
    failures: usize,
    skipped: usize,
}

/// The counts of each `<testsuite>` and their sums (the Ant schema's
/// `<testsuites>` has none of its own): said, and found.
fn counts(xml: &str) -> Vec<(Counts, Counts)> {
    let mut reader = Reader::from_str(xml);
    let mut out = Vec::new();
    let mut total = (Counts::default(), Counts::default());
    let attr = |e: &quick_xml::events::BytesStart, k: &str| -> usize {
        e.try_get_attribute(k)
            .unwrap()
            .map_or(0, |a| a.unescape_value().unwrap().parse().unwrap())
    };
    loop {
        match reader.read_event().unwrap() {
            Event::Start(e) | Event::Empty(e) => match e.name().as_ref() {
                b"testsuite" => {
                    total.0.tests += attr(&e, "tests");
                    total.0.failures += attr(&e, "failures");
                    out.push((
                        Counts {
                            tests: attr(&e, "tests"),
                            failures: attr(&e, "failures"),
                            skipped: attr(&e, "skipped"),
                        },
                        Counts::default(),
                    ))
                }
                b"testcase" => {
                    out.last_mut().unwrap().1.tests += 1;
                    total.1.tests += 1;
                }
                b"failure" => {
                    out.last_mut().unwrap().1.failures += 1;
                    total.1.failures += 1;
                }
                b"skipped" => {
                    out.last_mut().unwrap().1.skipped += 1;
                    total.1.skipped += 1;
                }
                _ => {}
            },
            Event::Eof => break,
            _ => {}
        }
    }
    total.0.skipped = total
        .1
        .skipped
        .min(out.iter().map(|(s, _)| s.skipped).sum());
    out.push(total);
    out
}

#[test]
fn junit_reports_are_valid_and_add_up() {
    let dir = tempfile::tempdir().unwrap();
    let odd = odd_copy(dir.path(), "tests/cmd/correct_data/never_silent.mod", "");
    let odd = odd.to_str().unwrap();
    let cases: &[(&[&str], i32, usize)] = &[
        // (arguments, exit code, failures)
        (
            &[
                "correct",
                "tests/cmd/correct_data/cell.mod",
                "--at",
                "60",
                "--check",
            ],
            1,
            3,
        ),
        (
            &[
                "correct",
                "tests/cmd/correct_data/cell.mod",
                "--at",
                "0",
                "--check",
            ],
            0,
            0,
        ),
        (&["correct", odd, "--at", "0", "--check"], 1, 5),
        (
            &[
                "correct",
                odd,
                "--at",
                "0",
                "--check",
                "--accept",
                "runtime,expression",
            ],
            0,
            0,
        ),
        (
            &[
                "correct",
                "samples/backup_multimove",
                "--task",
                "T_ROB2",
                "--at",
                "120",
                "--check",
            ],
            // A case per file in a backup: T_ROB2's three targets that
            // move are in its one module.
            1,
            1,
        ),
        (
            &[
                "diff",
                "tests/cmd/correct_data/cell.mod",
                "tests/cmd/correct_data/cell_at60.mod",
                "--fail-above",
                "0.05",
            ],
            1,
            3,
        ),
        (
            &[
                "diff",
                "tests/cmd/diff_data/joint_a.mod",
                "tests/cmd/diff_data/other.mod",
                "--fail-above",
                "0.15",
            ],
            1,
            6,
        ),
    ];
    for (args, code, failures) in cases {
        let mut args = args.to_vec();
        args.extend(["--format", "junit"]);
        let r = run(&args);
        assert_eq!(r.code, *code, "{args:?}\n{}", r.stdout);
        if let Err(e) = validate(&r.stdout) {
            panic!("{args:?}: not valid under {SCHEMA}:\n{e}\n{}", r.stdout);
        }
        let counts = counts(&r.stdout);
        for (said, found) in &counts {
            assert_eq!(said, found, "{args:?}\n{}", r.stdout);
        }
        assert_eq!(
            counts.last().unwrap().0.failures,
            *failures,
            "{args:?}\n{}",
            r.stdout
        );
    }
}

#[test]
fn the_schema_bites() {
    let r = run(&[
        "correct",
        "tests/cmd/correct_data/cell.mod",
        "--at",
        "60",
        "--check",
        "--format",
        "junit",
    ]);
    assert!(validate(&r.stdout).is_ok());
    // A failure that does not say what, a suite without its count of
    // failures, its time, its host or its timestamp, a case without its
    // time: each refused by the Ant schema.
    for (element, attribute) in [
        ("failure", "type"),
        ("testsuite", "failures"),
        ("testsuite", "hostname"),
        ("testsuite", "timestamp"),
        ("testsuite", "time"),
        ("testcase", "time"),
    ] {
        let re = regex::Regex::new(&format!(r#"(<{element} [^>]*?) {attribute}="[^"]*""#)).unwrap();
        assert!(re.is_match(&r.stdout), "{element} {attribute}");
        let broken = re.replace(&r.stdout, "$1");
        assert!(
            validate(&broken).is_err(),
            "accepted <{element}> without {attribute}:\n{broken}"
        );
    }
    // A timestamp with a time zone: the Ant schema's pattern has none.
    let host = r.stdout.find("\" hostname=").unwrap();
    let zoned = format!("{}Z{}", &r.stdout[..host], &r.stdout[host..]);
    assert!(validate(&zoned).is_err(), "a zoned timestamp accepted");
    // What xmllint would also refuse: a count that is not a number, an
    // attribute the schema does not declare, an empty name, an element
    // it does not know, and children out of order.
    for (from, to) in [
        (" failures=\"", " failures=\"x"),
        ("<testsuite ", "<testsuite color=\"red\" "),
        ("<testcase name=\"", "<testcase name=\"\" was=\""),
        ("<testcase ", "<bogus/><testcase "),
    ] {
        assert!(r.stdout.contains(from), "{from}");
        let broken = r.stdout.replacen(from, to, 1);
        assert!(validate(&broken).is_err(), "accepted with {to}:\n{broken}");
    }
    let props = r
        .stdout
        .find("<properties>")
        .expect("a suite has properties");
    let props_end = r.stdout.find("</properties>").unwrap() + "</properties>".len();
    let mut moved = r.stdout.clone();
    let block = moved[props..props_end].to_string();
    moved.replace_range(props..props_end, "");
    let at = moved.rfind("</testsuite>").unwrap();
    moved.insert_str(at, &block);
    assert!(validate(&moved).is_err(), "properties after the test cases");
}

/// The validator reads the schema it is given, and refuses a construct it
/// does not implement rather than skip it.
#[test]
fn the_validator_reads_only_what_it_understands() {
    let schema = std::fs::read_to_string(SCHEMA).unwrap();
    assert!(xsd::Schema::parse(&schema).is_ok());
    let grown = schema.replacen(
        "<xs:minLength value=\"1\"/>",
        "<xs:minLength value=\"1\"/><xs:maxLength value=\"9\"/>",
        1,
    );
    let e = xsd::Schema::parse(&grown)
        .err()
        .expect("xs:maxLength refused");
    assert!(e.contains("xs:maxLength"), "{e}");
}

/// An already-corrected program is checked, not empty: its targets are
/// passing test cases (it was `tests="0"`).
#[test]
fn an_already_corrected_program_has_its_cases() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("cell.mod");
    std::fs::copy("tests/cmd/correct_data/cell.mod", &file).unwrap();
    let file = file.to_str().unwrap();
    let r = run(&["correct", file, "--at", "60", "--in-place"]);
    assert_eq!(r.code, 0);
    let r = run(&[
        "correct", file, "--at", "60", "--check", "--format", "junit",
    ]);
    assert_eq!(r.code, 0, "{}", r.stdout);
    validate(&r.stdout).unwrap();
    // cell.mod moves to p10, p20 and one inline target.
    assert!(
        r.stdout.contains(" tests=\"3\" failures=\"0\""),
        "{}",
        r.stdout
    );
    for name in ["p10", "p20", "main#1"] {
        assert!(
            r.stdout.contains(&format!("<testcase name=\"{name}\"")),
            "{name}"
        );
    }
}

/// A task of a backup is a suite with a test case per module file, not
/// per target (the backup's ScanPath.mod alone has 20 000 targets).
#[test]
fn a_backup_has_a_case_per_file() {
    let r = run(&[
        "correct",
        "samples/backup_multimove",
        "--task",
        "T_ROB1",
        "--at",
        "60",
        "--check",
        "--format",
        "junit",
    ]);
    assert_eq!(r.code, 1);
    validate(&r.stdout).unwrap();
    let cases: Vec<&str> = r
        .stdout
        .lines()
        .filter_map(|l| l.trim().strip_prefix("<testcase name=\""))
        .map(|l| &l[..l.find('"').unwrap()])
        .collect();
    let mut files: Vec<String> = std::fs::read_dir("samples/backup_multimove/RAPID/TASK1/PROGMOD")
        .unwrap()
        .map(|e| {
            format!(
                "samples/backup_multimove/RAPID/TASK1/PROGMOD/{}",
                e.unwrap().file_name().to_str().unwrap()
            )
        })
        .collect();
    files.sort();
    let mut found: Vec<String> = cases.iter().map(|c| c.to_string()).collect();
    found.sort();
    found.dedup();
    assert_eq!(found.len(), cases.len(), "a file twice: {cases:?}");
    assert!(
        found.iter().all(|c| files.contains(c)),
        "{found:?} not among {files:?}"
    );
    // A message names three targets and counts the rest.
    assert!(
        r.stdout.contains("more\" type=\"moves\""),
        "no count of the rest"
    );
}

/// The SARIF 2.1.0 fields a code-scanning upload needs (OASIS SARIF
/// 2.1.0: sarifLog.version and runs; run.tool.driver.name; result.message
/// .text; physicalLocation.artifactLocation.uri; region lines from 1).
#[test]
fn sarif_logs_have_the_required_fields() {
    for (args, code, errors) in [
        (
            vec![
                "correct",
                "tests/cmd/correct_data/cell.mod",
                "--at",
                "60",
                "--check",
            ],
            1,
            3,
        ),
        (
            vec![
                "correct",
                "tests/cmd/correct_data/cell.mod",
                "--at",
                "0",
                "--check",
            ],
            0,
            0,
        ),
        (
            vec![
                "diff",
                "tests/cmd/correct_data/cell.mod",
                "tests/cmd/correct_data/cell_at60.mod",
                "--fail-above",
                "0.05",
            ],
            1,
            3,
        ),
    ] {
        let mut args = args.clone();
        args.extend(["--format", "sarif"]);
        let r = run(&args);
        assert_eq!(r.code, code, "{args:?}");
        let log: serde_json::Value = serde_json::from_str(&r.stdout).unwrap();
        assert_eq!(log["version"], "2.1.0");
        let run0 = &log["runs"][0];
        assert_eq!(run0["tool"]["driver"]["name"], "rapidtherm");
        let rules: Vec<&str> = run0["tool"]["driver"]["rules"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r["id"].as_str().unwrap())
            .collect();
        let results = run0["results"].as_array().unwrap();
        let mut failing = 0;
        for res in results {
            let rule = res["ruleId"].as_str().unwrap();
            assert!(
                rules.contains(&rule),
                "{rule} not among the rules {rules:?}"
            );
            let level = res["level"].as_str().unwrap();
            assert!(["error", "warning", "note"].contains(&level), "{level}");
            failing += usize::from(level == "error");
            assert!(!res["message"]["text"].as_str().unwrap().is_empty());
            let place = &res["locations"][0]["physicalLocation"];
            let uri = place["artifactLocation"]["uri"].as_str().unwrap();
            assert!(uri.starts_with("tests/cmd/correct_data/cell"), "{uri}");
            assert!(place["region"]["startLine"].as_u64().unwrap() >= 1);
            assert!(place["region"]["startColumn"].as_u64().unwrap() >= 1);
        }
        assert_eq!(failing, errors, "{args:?}\n{}", r.stdout);
    }
    // Outside a gate, refused as the other CI formats are.
    let r = run(&[
        "correct",
        "tests/cmd/correct_data/cell.mod",
        "--at",
        "60",
        "--format",
        "sarif",
    ]);
    assert_eq!(r.code, 2);
}
