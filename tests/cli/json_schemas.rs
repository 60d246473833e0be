//! Every JSON output of the command line, on the repository's samples,
//! against its schema in `schemas/` (read from the file itself): an object
//! whose `schema` names its command and version, and whose fields have the
//! types and presence the schema lists. No JSON Schema crate builds
//! offline here, so this file applies the keywords the schemas use
//! (`type`, `required`, `properties`, `items`, `const`, `anyOf`) and
//! refuses a schema with any other, rather than skip it.
//!
//! Also: every number is rounded to the digits of its unit (docs/formats.md).

use serde_json::Value;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_rapidtherm");

/// The keywords `check` applies; the others only describe.
const APPLIED: &[&str] = &["type", "required", "properties", "items", "const", "anyOf"];
const DESCRIBING: &[&str] = &["$schema", "$id", "title", "description"];

fn type_ok(ty: &str, v: &Value) -> bool {
    match ty {
        "object" => v.is_object(),
        "array" => v.is_array(),
        "string" => v.is_string(),
        "number" => v.is_number(),
        "integer" => v.is_i64() || v.is_u64(),
        "boolean" => v.is_boolean(),
        "null" => v.is_null(),
        _ => panic!("type {ty} is not a JSON Schema type"),
    }
}

/// Whether `v` is valid under `schema`; the first fault otherwise.
fn check(schema: &Value, v: &Value, path: &str) -> Result<(), String> {
    let s = schema
        .as_object()
        .ok_or(format!("{path}: schema is no object"))?;
    for k in s.keys() {
        assert!(
            APPLIED.contains(&k.as_str()) || DESCRIBING.contains(&k.as_str()),
            "{path}: the schema uses {k}, which this test does not apply"
        );
    }
    if let Some(any) = s.get("anyOf") {
        let faults: Vec<String> = any
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|alt| check(alt, v, path).err())
            .collect();
        if faults.len() == any.as_array().unwrap().len() {
            return Err(format!("{path}: none of anyOf fits: {faults:?}"));
        }
    }
    if let Some(c) = s.get("const") {
        if c != v {
            return Err(format!("{path}: {v} is not {c}"));
        }
    }
    if let Some(t) = s.get("type") {
        let types: Vec<&str> = match t {
            Value::String(t) => vec![t.as_str()],
            Value::Array(ts) => ts.iter().map(|t| t.as_str().unwrap()).collect(),
            _ => panic!("{path}: type {t}"),
        };
        if !types.iter().any(|t| type_ok(t, v)) {
            return Err(format!("{path}: {v} is not of type {types:?}"));
        }
    }
    if let (Some(req), Some(o)) = (s.get("required"), v.as_object()) {
        for k in req.as_array().unwrap() {
            let k = k.as_str().unwrap();
            if !o.contains_key(k) {
                return Err(format!("{path}: required field {k} is missing"));
            }
        }
    }
    if let (Some(props), Some(o)) = (s.get("properties"), v.as_object()) {
        for (k, sub) in props.as_object().unwrap() {
            if let Some(x) = o.get(k) {
                check(sub, x, &format!("{path}.{k}"))?;
            }
        }
    }
    if let (Some(items), Some(a)) = (s.get("items"), v.as_array()) {
        for (i, x) in a.iter().enumerate() {
            check(items, x, &format!("{path}[{i}]"))?;
        }
    }
    Ok(())
}

/// Decimal places a number of field `key` may have (docs/formats.md).
fn places(key: &str) -> Option<i32> {
    if key.ends_with("_mm") || key.ends_with("_deg") {
        Some(6)
    } else if key.ends_with("_c") {
        Some(3)
    } else {
        None
    }
}

/// Every number under a `_mm`, `_deg` or `_c` field has no more digits
/// than its unit means.
fn rounded(v: &Value, key: &str, path: &str) -> Result<(), String> {
    match v {
        Value::Object(o) => o
            .iter()
            .try_for_each(|(k, x)| rounded(x, k, &format!("{path}.{k}"))),
        Value::Array(a) => a.iter().try_for_each(|x| rounded(x, key, path)),
        Value::Number(n) => {
            let (Some(p), Some(x)) = (places(key), n.as_f64()) else {
                return Ok(());
            };
            let scaled = x * 10f64.powi(p);
            // The decimal written is the shortest that reads back as the
            // rounded double: it has at most `p` places.
            let text = n.to_string();
            let decimals = text
                .split(['e', 'E'])
                .next()
                .and_then(|m| m.split_once('.'))
                .map_or(0, |(_, f)| f.len());
            if decimals as i32 > p && scaled.abs() < 1e15 && !text.contains(['e', 'E']) {
                return Err(format!("{path}: {text} has more than {p} decimals"));
            }
            Ok(())
        }
        _ => Ok(()),
    }
}

fn json_of(args: &[&str], code: i32) -> Value {
    let out = Command::new(BIN)
        .args(args)
        .args(["--format", "json"])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(code),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{args:?}: not JSON ({e})"))
}

/// (command line, exit code, the schema's command).
const RUNS: &[(&[&str], i32, &str)] = &[
    (&["targets", "samples/control_flow.mod"], 0, "targets"),
    (&["targets", "samples/backup_multimove"], 0, "targets"),
    (
        &["targets", "--joints", "samples/service_positions.mod"],
        0,
        "targets-joints",
    ),
    (
        &["correct", "tests/cmd/correct_data/cell.mod", "--at", "60"],
        0,
        "correct",
    ),
    (
        &[
            "correct",
            "samples/backup_multimove",
            "--task",
            "T_ROB2",
            "--at",
            "120",
        ],
        0,
        "correct",
    ),
    (
        &[
            "correct",
            "tests/cmd/correct_data/cell.mod",
            "--at",
            "60",
            "--check",
        ],
        1,
        "correct-check",
    ),
    (
        &[
            "correct",
            "tests/cmd/correct_data/never_silent.mod",
            "--at",
            "120",
            "--check",
        ],
        1,
        "correct-check",
    ),
    (
        &[
            "correct",
            "samples/backup_multimove",
            "--task",
            "T_ROB2",
            "--task",
            "T_COM",
            "--at",
            "120",
            "--check",
        ],
        1,
        "correct-check",
    ),
    (
        &[
            "diff",
            "tests/cmd/correct_data/cell.mod",
            "tests/cmd/correct_data/cell_at60.mod",
        ],
        0,
        "diff",
    ),
    (
        &[
            "diff",
            "samples/backup_multimove",
            "samples/backup_multimove",
        ],
        0,
        "diff",
    ),
    (&["fk", "90", "0", "0", "0", "0", "0"], 0, "fk"),
    (
        &[
            "ik", "492.1012", "333.9077", "797.3712", "0.07631", "-0.31555", "-0.75926", "-0.56403",
        ],
        0,
        "ik",
    ),
    (
        &[
            "heating",
            "fit",
            "samples/heating_irb140_60pct.csv",
            "--model",
            "two-tau",
            "--axes",
            "6",
        ],
        0,
        "heating-fit",
    ),
    (
        &[
            "heating",
            "eval",
            "--measured",
            "tests/cmd/heating_small.csv",
            "--at",
            "3.5,168",
            "--hold-ends",
        ],
        0,
        "heating-eval",
    ),
    (&["gap", "tests/cmd/diag_gap.stdin"], 0, "gap"),
    (&["arms"], 0, "arms"),
    (
        &[
            "diagnose",
            "tests/cmd/diag_diagnose.stdin",
            "--assume-cold-start",
            "irb140",
        ],
        0,
        "diagnose",
    ),
];

#[test]
fn every_json_output_is_valid_under_its_schema_file() {
    let mut used = Vec::new();
    for (args, code, command) in RUNS {
        let v = json_of(args, *code);
        let name = format!("rapidtherm.{command}/1");
        assert_eq!(v["schema"], name.as_str(), "{args:?}");
        let file = format!("schemas/rapidtherm.{command}.v1.json");
        let schema: Value = serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
        if let Err(e) = check(&schema, &v, "$") {
            panic!("{args:?}: not valid under {file}: {e}");
        }
        if let Err(e) = rounded(&v, "", "$") {
            panic!("{args:?}: {e}");
        }
        used.push(file);
    }
    // Every schema file in the repository is one an output is checked by,
    // but the general chain's (its diagnosis takes minutes in a test build).
    for e in std::fs::read_dir("schemas").unwrap() {
        let file = format!("schemas/{}", e.unwrap().file_name().to_str().unwrap());
        if !file.contains("diagnose-chain") {
            assert!(used.contains(&file), "{file} checks no output");
        }
    }
}

#[test]
fn the_schema_check_bites() {
    let schema: Value = serde_json::from_str(
        &std::fs::read_to_string("schemas/rapidtherm.correct-check.v1.json").unwrap(),
    )
    .unwrap();
    let v = json_of(
        &[
            "correct",
            "tests/cmd/correct_data/cell.mod",
            "--at",
            "60",
            "--check",
        ],
        1,
    );
    assert!(check(&schema, &v, "$").is_ok());
    let mut bare = v.clone();
    bare["schema"] = "rapidtherm.correct-check/2".into();
    assert!(
        check(&schema, &bare, "$").is_err(),
        "another version accepted"
    );
    let mut no_id = v.clone();
    no_id["findings"][0].as_object_mut().unwrap().remove("id");
    assert!(
        check(&schema, &no_id, "$").is_err(),
        "a finding without id accepted"
    );
    let mut wrong = v.clone();
    wrong["findings"][0]["line"] = "4".into();
    assert!(
        check(&schema, &wrong, "$").is_err(),
        "a line as a string accepted"
    );
    // The old shape: a bare array.
    assert!(
        check(&schema, &v["findings"], "$").is_err(),
        "a bare array accepted"
    );
    // Unrounded: the old output's -0.06999999999999318.
    let raw: Value = serde_json::from_str(r#"{"correction_mm": [-0.06999999999999318]}"#).unwrap();
    assert!(rounded(&raw, "", "$").is_err());
}
