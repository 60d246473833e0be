//! The marker covers all it claims (issue 53): its basis, model and arm
//! are sealed with the numbers; the marker and its seal are recognised
//! however they are spaced or cased, alone or together; a cold target or
//! move added after the correction fails `--check`, naming it. Each case
//! below passed silently before (named in its test).

use crate::rapidtherm;
use proptest::prelude::*;
use rapidtherm::correct::marker::{self, Distrust};
use rapidtherm::correct::{correct, Options, Reason, When};
use rapidtherm::model::warm::{Moment, WarmRobot};
use rapidtherm::model::Model;
use rapidtherm::rapid;
use rapidtherm::robot::Robot;
use std::path::Path;
use std::process::Output;

const COLD: &str = "MODULE Cell\n    CONST robtarget p10:=[[400,150,380],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n    CONST robtarget p20:=[[450,250,380],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n    PROC main()\n        MoveJ p10, v1000, z10, tool0;\n        MoveL p20, v100, fine, tool0;\n    ENDPROC\nENDMODULE\n";

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// A folder with `cold.mod` and its correction for minute 120,
/// `warm.mod`; the corrected text.
fn corrected() -> (tempfile::TempDir, String) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("cold.mod"), COLD).unwrap();
    let out = rapidtherm(
        &["correct", "cold.mod", "--at", "120", "-o", "warm.mod"],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out));
    let warm = std::fs::read_to_string(dir.path().join("warm.mod")).unwrap();
    (dir, warm)
}

fn write(dir: &Path, name: &str, text: &str) {
    std::fs::write(dir.join(name), text).unwrap();
}

/// `--check` of `name` fails (exit 1) saying `says`; a run writing it
/// refuses (exit 2) and writes nothing.
fn check_fails_and_write_refused(dir: &Path, name: &str, at: &str, says: &str) {
    let out = rapidtherm(&["correct", name, "--at", at, "--check"], dir);
    assert_eq!(out.status.code(), Some(1), "{name}: {}", text(&out));
    assert!(text(&out).contains(says), "{name}: {}", text(&out));
    let out = rapidtherm(&["correct", name, "--at", at, "-o", "again.mod"], dir);
    assert_eq!(out.status.code(), Some(2), "{name}: {}", text(&out));
    assert!(!dir.join("again.mod").exists(), "{name}");
}

// Before: `minute 120` edited to `minute 60` in the marker's text, and
// `--at 60 --check` passed, "nothing to do".
#[test]
fn a_basis_edited_in_the_marker_is_not_trusted() {
    let (dir, warm) = corrected();
    assert!(warm.contains("basis=minute 120;"), "{warm}");
    write(
        dir.path(),
        "e.mod",
        &warm.replace("minute 120", "minute 60"),
    );
    check_fails_and_write_refused(dir.path(), "e.mod", "60", "marker is not trusted");
}

// The model and arm are sealed too: the marker edited to say the base
// model, and `--model base --check` passed.
#[test]
fn a_model_edited_in_the_marker_is_not_trusted() {
    let (dir, warm) = corrected();
    let edited = warm.replace("embedded default model", "embedded base model");
    assert_ne!(edited, warm);
    write(dir.path(), "e.mod", &edited);
    let out = rapidtherm(
        &[
            "correct", "e.mod", "--at", "120", "--model", "base", "--check",
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
    assert!(
        text(&out).contains("marker is not trusted"),
        "{}",
        text(&out)
    );
}

// Before: a move to a target decided at run time, added after the
// correction, passed `--check` ("none is left cold"), though the check of
// the cold original with it fails.
#[test]
fn a_move_to_a_cold_target_added_after_the_correction_fails_the_check() {
    let (dir, warm) = corrected();
    let added = warm
        .replace(
            "    PROC main()",
            "    VAR robtarget pAdded;\n    PROC main()",
        )
        .replace(
            "        MoveL p20, v100, fine, tool0;",
            "        MoveL p20, v100, fine, tool0;\n        MoveL pAdded, v100, fine, tool0;",
        );
    write(dir.path(), "added.mod", &added);
    let out = rapidtherm(
        &["correct", "added.mod", "--at", "120", "--check"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
    let log = text(&out);
    assert!(log.contains("pAdded"), "{log}");
    assert!(log.contains("left cold"), "{log}");
    // Only the added one: the corrected targets do not move again.
    assert!(!log.contains("would move"), "{log}");
}

// Before: a module with its own targets added beside a corrected one
// (given together, one task) was left cold: "already corrected".
#[test]
fn a_cold_module_beside_a_corrected_one_is_found() {
    let (dir, _) = corrected();
    let more = "MODULE More\n    CONST robtarget pMore:=[[500,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n    PROC more()\n        MoveL pMore, v100, fine, tool0;\n    ENDPROC\nENDMODULE\n";
    write(dir.path(), "more.mod", more);
    let out = rapidtherm(
        &["correct", "warm.mod", "more.mod", "--at", "120", "--check"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
    let log = text(&out);
    assert!(log.contains("pMore"), "{log}");
    assert!(
        !log.contains("p10 "),
        "the corrected targets do not move: {log}"
    );
    assert!(log.contains("more.mod has no rapidtherm marker"), "{log}");
}

// Before: `!rapidtherm` or upper case was not a marker, and the file was
// corrected a second time (with a second numbers line).
#[test]
fn a_marker_spaced_or_cased_otherwise_is_recognised() {
    let (dir, warm) = corrected();
    for (k, edited) in [
        warm.replace(
            "! rapidtherm 0.1.0 corrected:",
            "!rapidtherm 0.1.0 corrected:",
        ),
        warm.replace("! rapidtherm", "! RAPIDTHERM")
            .replace("corrected: basis", "CORRECTED: BASIS"),
        warm.replace("; model=", " ;  model = ")
            .replace("! rapidtherm numbers", "!RapidTherm  Numbers"),
    ]
    .into_iter()
    .enumerate()
    {
        assert_ne!(edited, warm);
        let name = format!("v{k}.mod");
        write(dir.path(), &name, &edited);
        let out = rapidtherm(
            &["correct", &name, "--at", "120", "-o", "again.mod"],
            dir.path(),
        );
        assert_eq!(out.status.code(), Some(0), "{name}: {}", text(&out));
        assert!(
            text(&out).contains("nothing to do"),
            "{name}: {}",
            text(&out)
        );
        let again = std::fs::read_to_string(dir.path().join("again.mod")).unwrap();
        assert_eq!(again, edited, "{name}: written as it is");
        let out = rapidtherm(&["correct", &name, "--at", "120", "--check"], dir.path());
        assert_eq!(out.status.code(), Some(0), "{name}: {}", text(&out));
    }
}

// Before: the marker deleted, its numbers line left, and the corrected
// numbers were corrected again, the file then holding two numbers lines.
#[test]
fn a_seal_without_its_marker_is_refused() {
    let (dir, warm) = corrected();
    let no_marker: String = warm
        .lines()
        .filter(|l| !l.contains("corrected:"))
        .map(|l| format!("{l}\n"))
        .collect();
    write(dir.path(), "n.mod", &no_marker);
    check_fails_and_write_refused(dir.path(), "n.mod", "120", "without its marker");
    // And written twice over: two seals.
    let numbers = warm
        .lines()
        .find(|l| l.contains("rapidtherm numbers"))
        .unwrap();
    let twice = warm.replace("ENDMODULE", &format!("{numbers}\nENDMODULE"));
    write(dir.path(), "t.mod", &twice);
    check_fails_and_write_refused(dir.path(), "t.mod", "120", "two seals");
}

// A file corrected before the seal covered the marker (`numbers v1`):
// what its marker says cannot be checked; it is made again from the cold
// original. Before this version the v1 seal was the trusted one.
#[test]
fn a_seal_of_the_older_format_is_not_trusted() {
    let (dir, warm) = corrected();
    let old = warm.replace("numbers v2 ", "numbers v1 ");
    assert_ne!(old, warm);
    write(dir.path(), "old.mod", &old);
    check_fails_and_write_refused(dir.path(), "old.mod", "120", "format v1");
}

// A robconf or an external axis changed after the correction is a number
// changed: the seal finds it, and `--check` fails.
#[test]
fn a_robconf_or_axis_changed_after_the_correction_fails_the_check() {
    let (dir, warm) = corrected();
    let conf = warm.replacen("[0,0,0,0]", "[0,-1,0,0]", 1);
    write(dir.path(), "conf.mod", &conf);
    check_fails_and_write_refused(dir.path(), "conf.mod", "120", "marker is not trusted");
    let axis = warm.replacen("[9E9,9E9", "[100,9E9", 1);
    write(dir.path(), "axis.mod", &axis);
    check_fails_and_write_refused(dir.path(), "axis.mod", "120", "marker is not trusted");
}

/// Cases per test: 20 (seconds on two cores), or `PROPTEST_CASES`.
fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20)
}

/// [`COLD`] corrected for minute 120 by the library.
fn warm_text() -> String {
    let program = rapid::parse("cold.mod", COLD.as_bytes()).unwrap();
    let warm = WarmRobot::new(Robot::irb140(), &Model::default(), 120.0).unwrap();
    let options = Options {
        model_label: "embedded default model, embedded IRB 140 arm".to_string(),
        ..Options::new(When::At(Moment::Minute(120.0)))
    };
    let out = correct(&program, &warm, &options, &mut |_, _| {}).unwrap();
    String::from_utf8(out.outputs[0].clone()).unwrap()
}

/// A line's words and separators, each with whether a space stood before
/// it: `! rapidtherm 0.1.0 corrected: basis=minute 120; …` →
/// `!`, `rapidtherm`, …, `corrected`, `:`, `basis`, `=`, `minute`, …
fn tokens(line: &str) -> Vec<(String, bool)> {
    let mut out = Vec::new();
    for word in line.split_ascii_whitespace() {
        let mut spaced = true;
        let mut cur = String::new();
        for c in word.chars() {
            let sep =
                matches!(c, '!' | ';' | '=') || (c == ':' && cur.eq_ignore_ascii_case("corrected"));
            if !sep {
                cur.push(c);
                continue;
            }
            if !cur.is_empty() {
                out.push((std::mem::take(&mut cur), spaced));
                spaced = false;
            }
            out.push((c.to_string(), spaced));
            spaced = false;
        }
        if !cur.is_empty() {
            out.push((cur, spaced));
        }
    }
    out
}

/// The line of `tokens` with `gaps[k]` spaces or tabs before token k
/// (at least one where the line had one), each token in the case
/// `cases[k]` says (0 as written, 1 upper, 2 lower).
fn respelled(tokens: &[(String, bool)], gaps: &[(u8, bool)], cases: &[u8]) -> String {
    let mut s = String::from("    ");
    for (k, (t, spaced)) in tokens.iter().enumerate() {
        let (n, tab) = gaps[k % gaps.len()];
        let n = usize::from(n) + usize::from(*spaced);
        if k > 0 {
            s.push_str(&(if tab { "\t" } else { " " }).repeat(n));
        }
        match cases[k % cases.len()] {
            1 => s.push_str(&t.to_ascii_uppercase()),
            2 => s.push_str(&t.to_ascii_lowercase()),
            _ => s.push_str(t),
        }
    }
    s
}

/// What is done to the corrected file.
#[derive(Debug, Clone)]
enum Edit {
    /// The marker and its seal respelled only.
    Respell,
    DeleteMarker,
    DeleteSeal,
    /// Both deleted: a cold file again (the way out the refusal names).
    DeleteBoth,
    SealTwice,
    MarkerTwice,
    /// The basis in the marker's text set to another minute.
    Basis(u32),
    /// A target added: with numbers (`true`), or decided at run time and
    /// moved to (`false`).
    Added(bool),
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        2 => Just(Edit::Respell),
        1 => Just(Edit::DeleteMarker),
        1 => Just(Edit::DeleteSeal),
        1 => Just(Edit::DeleteBoth),
        1 => Just(Edit::SealTwice),
        1 => Just(Edit::MarkerTwice),
        1 => (0u32..1000).prop_filter("another minute", |m| *m != 120).prop_map(Edit::Basis),
        2 => any::<bool>().prop_map(Edit::Added),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    /// Whatever the spelling of the two lines, the state the file is in is
    /// told from what was done to it alone: respelled, it is corrected
    /// (nothing to do); one line deleted, doubled or a field edited, it is
    /// not trusted; both deleted, it is cold; a target added, its numbers
    /// or the run's own analysis find it.
    #[test]
    fn markers_are_read_whatever_their_spelling(
        gaps in prop::collection::vec((0u8..3, any::<bool>()), 1..40),
        letter_cases in prop::collection::vec(0u8..3, 1..40),
        edit in edit(),
    ) {
        let warm = warm_text();
        let lines: Vec<&str> = warm.lines().collect();
        let m = lines.iter().position(|l| l.contains("corrected:")).unwrap();
        let n = lines.iter().position(|l| l.contains("rapidtherm numbers")).unwrap();
        let marker_line = respelled(&tokens(lines[m]), &gaps, &letter_cases);
        let seal_line = respelled(&tokens(lines[n]), &gaps, &letter_cases);
        let mut out: Vec<String> = Vec::new();
        for (k, l) in lines.iter().enumerate() {
            let l = l.to_string();
            match (k == m, k == n, &edit) {
                (true, _, Edit::DeleteMarker | Edit::DeleteBoth) => {}
                (_, true, Edit::DeleteSeal | Edit::DeleteBoth) => {}
                (true, _, Edit::MarkerTwice) => out.extend([marker_line.clone(), marker_line.clone()]),
                (_, true, Edit::SealTwice) => out.extend([seal_line.clone(), seal_line.clone()]),
                (true, _, Edit::Basis(b)) => {
                    let low = marker_line.to_ascii_lowercase();
                    let at = low.find("minute").unwrap();
                    let at = at + low[at..].find("120").unwrap();
                    out.push(format!("{}{b}{}", &marker_line[..at], &marker_line[at + 3..]));
                }
                (true, ..) => out.push(marker_line.clone()),
                (_, true, _) => out.push(seal_line.clone()),
                (false, false, Edit::Added(true)) if l.starts_with("    PROC main()") => {
                    out.push("    CONST robtarget pAdded:=[[300,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];".into());
                    out.push(l);
                    out.push("        MoveL pAdded, v100, fine, tool0;".into());
                }
                (false, false, Edit::Added(false)) if l.starts_with("    PROC main()") => {
                    out.push("    VAR robtarget pAdded;".into());
                    out.push(l);
                    out.push("        MoveL pAdded, v100, fine, tool0;".into());
                }
                _ => out.push(l),
            }
        }
        let text = out.join("\n") + "\n";
        let program = rapid::parse("w.mod", text.as_bytes()).unwrap();
        let distrust = marker::untrusted(&program).map(|u| u.why);
        match &edit {
            Edit::Respell | Edit::Added(false) => {
                prop_assert_eq!(&distrust, &None, "{}", text);
                let found = marker::find(&program).expect("a marker");
                prop_assert_eq!(found.marker.basis.to_string().to_ascii_lowercase(), "minute 120");
            }
            Edit::DeleteBoth => {
                prop_assert_eq!(&distrust, &None);
                prop_assert!(marker::find(&program).is_none());
            }
            Edit::DeleteMarker => prop_assert_eq!(&distrust, &Some(Distrust::NoMarker), "{}", text),
            Edit::DeleteSeal => prop_assert_eq!(&distrust, &Some(Distrust::NoFingerprint), "{}", text),
            Edit::SealTwice | Edit::MarkerTwice => {
                prop_assert!(matches!(distrust, Some(Distrust::Twice { .. })), "{:?} {}", distrust, text)
            }
            Edit::Basis(_) | Edit::Added(true) => {
                prop_assert!(matches!(distrust, Some(Distrust::NumbersChanged { .. })), "{:?} {}", distrust, text)
            }
        }
        if let Edit::Added(false) = edit {
            // The run finds the added target left cold, and moves nothing
            // of the corrected ones.
            let warm = WarmRobot::new(Robot::irb140(), &Model::default(), 120.0).unwrap();
            let options = Options {
                model_label: "embedded default model, embedded IRB 140 arm".to_string(),
                ..Options::new(When::At(Moment::Minute(120.0)))
            };
            let o = correct(&program, &warm, &options, &mut |_, _| {}).unwrap();
            prop_assert!(o.corrections.is_empty());
            prop_assert!(o.left_alone.iter().any(|l| l.id == "pAdded" && l.reason == Reason::Runtime));
            prop_assert_eq!(&o.outputs[0], &text.as_bytes().to_vec());
        }
    }
}
