//! Data mean what they say, and models are plausible or refused (issue
//! 53): each case a hostile sweep found accepted, run through the binary
//! as the user ran it. Every expectation is worked by hand from the file
//! the test writes, not read off the program's output.

use super::{assert_exit, rapidtherm};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/cmd/correct_data")
        .join(name)
}

/// A folder holding `cell.mod` (robtargets p10, p20 and `main#1`, no
/// jointtarget) and the files `files` give.
fn cell(files: &[(&str, &str)]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(data("cell.mod"), dir.path().join("cell.mod")).unwrap();
    for (name, text) in files {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    dir
}

fn stderr(out: &std::process::Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The embedded default model with `[heating] recording = "rec.csv"`.
fn model_with_recording() -> String {
    let model = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("data/irb140/model.toml"),
    )
    .unwrap();
    assert!(model.contains("profile = \"default\""));
    model.replace(
        "profile = \"default\"",
        "profile = \"default\"\nrecording = \"rec.csv\"",
    )
}

/// `correct cell.mod --model model.toml --at 60` on a recording.
fn correct_with_recording(rec: &str) -> std::process::Output {
    let dir = cell(&[("model.toml", &model_with_recording()), ("rec.csv", rec)]);
    let out = rapidtherm(
        &["correct", "cell.mod", "--model", "model.toml", "--at", "60"],
        dir.path(),
    );
    // Nothing written, whatever the outcome.
    assert_eq!(
        std::fs::read(dir.path().join("cell.mod")).unwrap(),
        std::fs::read(data("cell.mod")).unwrap()
    );
    out
}

const HEADER: &str = "time_min,t1_c,t2_c,t3_c,t4_c,t5_c,t6_c\n";

#[test]
fn a_good_recording_corrects() {
    let rec =
        format!("{HEADER}0,7,7,7,7,7,7\n60,20.5,21.5,22.5,23.5,24.5,25.5\n120,30,30,30,30,30,30\n");
    let out = correct_with_recording(&rec);
    assert_exit(&out, 0);
}

#[test]
fn decimal_commas_are_refused_at_the_first_field_without_a_column() {
    // `60,20,5,21,5,...`: 13 fields under 7 columns. The 8th field, `23`,
    // starts at character 19 of line 3 (6 + 7 fields of 2 and 1
    // characters with their commas: "60,20,5,21,5,22,5," is 18).
    let rec = format!("{HEADER}0,7,7,7,7,7,7\n60,20,5,21,5,22,5,23,5,24,5,25,5\n");
    let out = correct_with_recording(&rec);
    assert_exit(&out, 2);
    let e = stderr(&out);
    assert!(e.contains("rec.csv:3:19:"), "{e}");
    assert!(e.contains("decimal commas"), "{e}");
}

#[test]
fn a_column_named_twice_is_refused_at_its_second_name() {
    // `t1_c` again as the 8th column: character 40 of the header.
    let rec =
        "time_min,t1_c,t2_c,t3_c,t4_c,t5_c,t6_c,t1_c\n0,7,7,7,7,7,7,7\n60,20,20,20,20,20,20,90\n";
    let out = correct_with_recording(rec);
    assert_exit(&out, 2);
    let e = stderr(&out);
    assert!(e.contains("rec.csv:1:40:"), "{e}");
    assert!(e.contains("`t1_c` is named twice"), "{e}");
}

#[test]
fn a_recording_in_fahrenheit_is_refused_at_the_cold_start() {
    // A 20 °C room is 68 °F; at minute 0 the motors stand at the room's
    // temperature, which no robot's room reaches at 68 °C.
    let rec = format!("{HEADER}0,68,68,68,68,68,68\n60,80,82,84,86,88,90\n");
    let out = correct_with_recording(&rec);
    assert_exit(&out, 2);
    let e = stderr(&out);
    assert!(e.contains("rec.csv:2:3:"), "{e}");
    assert!(e.contains("68 °F is 20.0 °C"), "{e}");
}

#[test]
fn a_repeated_header_and_a_short_row_are_refused() {
    let rec = format!("{HEADER}0,7,7,7,7,7,7\n{HEADER}60,20,20,20,20,20,20\n");
    let out = correct_with_recording(&rec);
    assert_exit(&out, 2);
    assert!(stderr(&out).contains("rec.csv:3:1:"), "{}", stderr(&out));
    assert!(stderr(&out).contains("repeats the header"));
    let rec = format!("{HEADER}0,7,7,7,7,7,7\n60,20,20,20,20,20\n");
    let out = correct_with_recording(&rec);
    assert_exit(&out, 2);
    assert!(
        stderr(&out).contains("column `t6_c` is missing"),
        "{}",
        stderr(&out)
    );
}

/// `correct cell.mod --schedule s.csv` with `csv` as the schedule.
fn correct_with_schedule(csv: &str) -> std::process::Output {
    let dir = cell(&[("s.csv", csv)]);
    rapidtherm(&["correct", "cell.mod", "--schedule", "s.csv"], dir.path())
}

#[test]
fn a_schedule_row_of_a_jointtarget_the_program_lacks_is_refused() {
    // cell.mod has robtarget p10 and no jointtarget: the row of line 3 is
    // no visit of the robtarget.
    let csv =
        "target,time_min,kind\np10,120,robtarget\np10,77,jointtarget\np20,120,\nmain#1,120,\n";
    let out = correct_with_schedule(csv);
    assert_exit(&out, 2);
    let e = stderr(&out);
    assert!(e.contains("s.csv:3:1:"), "{e}");
    assert!(
        e.contains("jointtarget `p10`, which the program does not have"),
        "{e}"
    );
    // The same file with the row's kind right is taken.
    let out = correct_with_schedule(&csv.replace("p10,77,jointtarget\n", ""));
    assert_exit(&out, 0);
}

#[test]
fn idle_spans_that_touch_are_refused() {
    let csv =
        "target,time_min,kind,end_min\np10,90\n,100,idle,120\n,120,idle,150\np20,160\nmain#1,160\n";
    let out = correct_with_schedule(csv);
    assert_exit(&out, 2);
    let e = stderr(&out);
    assert!(e.contains("s.csv:4:2:"), "{e}");
    assert!(e.contains("touches"), "{e}");
}

#[test]
fn a_time_of_9e9_is_refused() {
    let csv = "target,time_min\np10,9E+09\np20,120\nmain#1,120\n";
    let out = correct_with_schedule(csv);
    assert_exit(&out, 2);
    let e = stderr(&out);
    assert!(e.contains("s.csv:2:5:"), "{e}");
    assert!(e.contains("9e9 min"), "{e}");
}

#[test]
fn a_schedule_column_ignored_is_said() {
    let csv = "target,time_min,speed\np10,120,v100\np20,120,v100\nmain#1,120,v100\n";
    let out = correct_with_schedule(csv);
    assert_exit(&out, 0);
    assert!(
        stderr(&out).contains("column `speed` ignored"),
        "{}",
        stderr(&out)
    );
}

/// The embedded default model with `extra` appended.
fn model_with(extra: &str) -> String {
    let model = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("data/irb140/model.toml"),
    )
    .unwrap();
    format!("{model}\n{extra}")
}

/// Each model beyond data/plausible_effects.toml: refused by every
/// command that reads a model, at its key, exit 2.
#[test]
fn implausible_models_are_refused_wherever_a_model_is_read() {
    let k0 = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("data/irb140/model.toml"),
    )
    .unwrap()
    .replace("k0 = 0.33699", "k0 = 80.0");
    let cases = [
        (
            model_with("[[effects]]\nname = \"arm-bending\"\n[effects.params]\nlower_urad_per_k = 3000.0\n"),
            "effects[1].params.lower_urad_per_k",
        ),
        (
            model_with("[[effects]]\nname = \"joint-offset-drift\"\n[effects.params]\nc2_urad_per_k = 5000.0\n"),
            "effects[1].params.c2_urad_per_k",
        ),
        (
            model_with("[[effects]]\nname = \"expansion-scale\"\n[effects.params]\ndk_lower = 80.0\n"),
            "effects[1].params.dk_lower",
        ),
        (k0, "thermal.k0"),
    ];
    let meas = "time_min,j1_deg,j2_deg,j3_deg,j4_deg,j5_deg,j6_deg,x_mm,y_mm,z_mm\n0,0,0,0,0,30,0,515,0,712\n";
    for (model, key) in cases {
        let dir = cell(&[("model.toml", &model), ("m.csv", meas)]);
        for args in [
            vec![
                "correct",
                "cell.mod",
                "--model",
                "model.toml",
                "--at",
                "120",
            ],
            vec!["gap", "m.csv", "--model", "model.toml"],
            vec![
                "simulate",
                "--model",
                "model.toml",
                "--poses",
                "random:3",
                "-o",
                "out.csv",
            ],
            vec!["diagnose", "m.csv", "--model", "model.toml"],
        ] {
            let out = rapidtherm(&args, dir.path());
            assert_exit(&out, 2);
            let e = stderr(&out);
            assert!(e.contains(&format!("`{key}`")), "{args:?}: {e}");
            assert!(e.contains("model.toml:"), "{args:?}: {e}");
            assert!(!dir.path().join("out.csv").exists());
        }
    }
}

#[test]
fn a_noise_of_1e300_is_refused_before_anything_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let out = rapidtherm(
        &[
            "simulate", "--noise", "1e300", "--poses", "random:3", "-o", "out.csv",
        ],
        dir.path(),
    );
    assert_exit(&out, 2);
    assert!(stderr(&out).contains("at most 10 mm"), "{}", stderr(&out));
    assert!(!dir.path().join("out.csv").exists());
    let out = rapidtherm(
        &[
            "simulate", "--noise", "0.02", "--poses", "random:3", "-o", "out.csv",
        ],
        dir.path(),
    );
    assert_exit(&out, 0);
    // A noise the diagnosis is told is bounded alike: 1e300 mm made
    // every gap noise.
    let out = rapidtherm(&["diagnose", "out.csv", "--noise", "1e300"], dir.path());
    assert_exit(&out, 2);
    assert!(stderr(&out).contains("at most 10"), "{}", stderr(&out));
}
