//! The correction streamed into its files against the correction in
//! memory, and timed by a schedule: a job that writes files corrects each
//! task into its sink as it goes (`job::Streaming::Streamed`), and writes the
//! bytes the in-memory run (`Streaming::InMemory`, the run that keeps every
//! row) makes, with the same report; a program read with the fast lane
//! is estimated as the grammar's program is (the same schedule, joint
//! schedule, notes and duration) and corrected by that schedule, or by a
//! user's file that times every other target, into the same bytes both
//! ways. The binary's file, standard output and `--in-place` runs write
//! as they correct.

use super::lanes::{self, held, program_with, same_both_ways, stmt, Stmt};
use super::rapidtherm;
use crate::ways;
use proptest::prelude::*;
use rapidtherm::correct::job::{self, Event, Host, OutputFile as Written, Sink, Streaming};
use rapidtherm::correct::plan::{
    Action, ArmChoice, CorrectPlan, Destination, ModelSource, TimeBasis,
};
use rapidtherm::correct::{Options, ScheduleSource, When};
use rapidtherm::model::warm::Moment;
use rapidtherm::rapid::Program;
use rapidtherm::robot::Robot;
use rapidtherm::schedule::{estimate, EstimateOptions, Schedule, WhichVisit};
use std::collections::HashMap;
use std::process::Output;
use std::sync::{Arc, Mutex};

/// When the targets of `program` are reached: its estimate from minute 20
/// (two cycles of the first module's routine, `entry`; the second
/// module's targets are not reached and take the default), or, `partial`,
/// a file of every other robtarget's visits and no jointtargets', the
/// rest at the default. `None` where the estimate is refused.
fn when_of(program: &Program, entry: &str, partial: bool) -> Option<When> {
    let est = estimate(program, &Robot::irb140(), &estimate_options(entry)).ok()?;
    let default = Some(Moment::Minute(45.0));
    if !partial {
        return Some(When::Schedule {
            schedule: est.schedule,
            joints: Some(est.joint_schedule),
            default,
            source: ScheduleSource::Estimate(Box::new(estimate_options(entry))),
        });
    }
    let mut file = Schedule::new();
    for id in est.schedule.targets().step_by(2) {
        for &t in est.schedule.times(id).unwrap_or(&[]) {
            file.visit(id, t);
        }
    }
    Some(When::Schedule {
        schedule: file,
        joints: None,
        default,
        source: ScheduleSource::File,
    })
}

/// The walk of [`when_of`].
fn estimate_options(entry: &str) -> EstimateOptions {
    EstimateOptions {
        entry: entry.to_string(),
        start_min: 20.0,
        cycles: 2,
        base_frame: None,
    }
}

/// The estimate's whole say, or its error's.
fn estimated(p: &Program, entry: &str) -> String {
    match estimate(p, &Robot::irb140(), &estimate_options(entry)) {
        Ok(e) => {
            let mut enc = rapidtherm::digest::Encoder::new("test");
            e.schedule.encode(&mut enc);
            format!(
                "{}\n{}\n{}\n{:?}\n{:?}",
                enc.finish(),
                e.to_csv(),
                e.joint_schedule.to_csv(),
                e.duration_min.to_bits(),
                e.notes
            )
        }
        Err(e) => format!("error: {e}"),
    }
}

/// Read every way, `src` is estimated alike, and corrected alike by that
/// estimate (or by every other target's times of it, `partial`). How
/// many targets the lane read.
fn scheduled_both_ways(src: &[u8], entry: &str, partial: bool) -> Result<usize, TestCaseError> {
    let Some(ways) = ways::same_every_way(src, |p| estimated(p, entry))? else {
        return same_both_ways(src, &Options::new(When::At(Moment::Minute(0.0))));
    };
    let Some(when) = when_of(ways.grammar(), entry, partial) else {
        return Ok(held(&ways));
    };
    same_both_ways(src, &Options::new(when))
}

#[test]
fn a_cam_program_is_timed_and_corrected_the_same_both_ways() {
    let body: Vec<Stmt> = (0..300)
        .map(|i| {
            Stmt::Inline(
                ["MoveL", "MoveJ", "MoveC"][(i % 3) as usize],
                i,
                (i % 4) as u8,
                i % 5 == 0,
                "",
            )
        })
        .chain([Stmt::Named(0), Stmt::Named(3), Stmt::ConfOff])
        .collect();
    let second = vec![Stmt::Named(1), Stmt::Inline("MoveL", 5, 0, false, "")];
    for (partial, one_name) in [(false, false), (true, false), (false, true), (true, true)] {
        // With one routine name in both modules, identifiers name their
        // module (`M1:main#3`).
        let src = program_with(&[body.clone(), second.clone()], "\r\n", true, one_name);
        let entry = if one_name { "main" } else { "main0" };
        let read = scheduled_both_ways(&src, entry, partial).unwrap();
        // Every move literal (a MoveC has two).
        assert_eq!(read, 300 + 100 + 1, "the lane read {read} move literals");
    }
}

#[test]
fn generated_programs_are_timed_and_corrected_the_same_both_ways() {
    ways::counted(
        "timed by their estimate",
        32,
        9,
        (
            prop::collection::vec(prop::collection::vec(stmt(), 0..40), 1..3),
            any::<bool>(),
            any::<bool>(),
            any::<bool>(),
        ),
        |(bodies, crlf, partial, one_name)| {
            // With one routine name in every module, identifiers name
            // their module (`M1:main#3`).
            let src = program_with(&bodies, if crlf { "\r\n" } else { "\n" }, false, one_name);
            let entry = if one_name { "main" } else { "main0" };
            scheduled_both_ways(&src, entry, partial)
        },
    );
}

/// Corrected files kept in memory, by name.
#[derive(Default, Clone)]
struct Memory(Arc<Mutex<HashMap<String, Vec<u8>>>>);

struct Kept {
    name: String,
    bytes: Vec<u8>,
    to: Memory,
}

impl std::io::Write for Kept {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        self.bytes.extend_from_slice(b);
        Ok(b.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl Written for Kept {
    fn restart(&mut self) -> std::io::Result<()> {
        self.bytes.clear();
        Ok(())
    }
    fn finish(self: Box<Self>, _changed: bool) -> rapidtherm::error::Result<()> {
        let kept = *self;
        kept.to.0.lock().unwrap().insert(kept.name, kept.bytes);
        Ok(())
    }
}

impl Sink for Memory {
    fn create(&mut self, name: &str) -> rapidtherm::error::Result<Box<dyn Written>> {
        Ok(Box::new(Kept {
            name: name.to_string(),
            bytes: Vec::new(),
            to: self.clone(),
        }))
    }
}

/// A host that keeps nothing.
struct Quiet;

impl Host for Quiet {
    fn event(&mut self, _: Event<'_>) {}
}

/// The job run on the file `path` timed by `when`, written to `-o OUT`,
/// keeping every row (in memory) or not (streamed): how it ran, what it
/// said, what it wrote.
fn job_run(
    path: &std::path::Path,
    when: TimeBasis,
    keep_rows: bool,
) -> (Streaming, String, Vec<u8>) {
    let plan = CorrectPlan {
        when,
        visit: WhichVisit::default(),
        arms: ArmChoice {
            model: ModelSource::Default,
            specs: Vec::new(),
            irb140_thermal: false,
            placing: Default::default(),
        },
        expand_expressions: false,
        split_shared: false,
        action: Action::Write(Destination::File("OUT".into())),
        keep_rows,
    };
    let tasks = rapidtherm::rapid::task::discover(&[path.to_path_buf()]).unwrap();
    let memory = Memory::default();
    let mut ran = job::run(&plan, tasks, &mut Quiet, &mut memory.clone()).unwrap();
    let ran = ran.remove(0);
    let mut outcome = ran.outcome;
    // Streamed, the run keeps no row of a move or a target.
    outcome.moves.clear();
    outcome.corrections.clear();
    outcome.derived.clear();
    outcome.residuals.clear();
    let written = memory.0.lock().unwrap().remove("OUT").expect("written");
    (ran.streaming, lanes::said(&outcome), written)
}

/// The job writes what it corrects as it goes unless it keeps every row,
/// and the bytes and the report are those of the run in memory, on the
/// samples, for one moment and for an estimate.
#[test]
fn the_job_streams_what_it_corrects_in_memory() {
    let samples = concat!(env!("CARGO_MANIFEST_DIR"), "/samples");
    let mut streamed = 0;
    for name in [
        "cam_contour.mod",
        "control_flow.mod",
        "arc_pendant.mod",
        "fixtures.mod",
    ] {
        let path = std::path::Path::new(samples).join(name);
        for when in [
            TimeBasis::At(Moment::Minute(120.0)),
            TimeBasis::Start {
                start_min: 0.0,
                entry: "main".to_string(),
                cycles: 1,
                default: Some(Moment::Minute(60.0)),
            },
        ] {
            let (way, said_streamed, bytes_streamed) = job_run(&path, when.clone(), false);
            let (in_memory, said_whole, bytes_whole) = job_run(&path, when.clone(), true);
            assert!(
                matches!(way, Streaming::Streamed { .. }),
                "{name} {when:?}: {way:?}"
            );
            assert_eq!(in_memory, Streaming::InMemory);
            assert_eq!(said_streamed, said_whole, "{name} {when:?}");
            assert!(
                bytes_streamed == bytes_whole,
                "{name} {when:?}: the files differ"
            );
            streamed += 1;
        }
    }
    eprintln!("streamed and in memory alike: {streamed} runs");
}

/// What a run said on standard error, less the `-vv` timings.
fn said(o: &Output) -> Vec<String> {
    // `wrote FILE` names the file only the file run has.
    String::from_utf8_lossy(&o.stderr)
        .lines()
        .filter(|l| !l.starts_with("info:") && !l.starts_with("wrote "))
        .map(str::to_string)
        .collect()
}

/// Whether a `-vv` run wrote its files as it corrected them.
fn was_streamed(o: &Output) -> bool {
    String::from_utf8_lossy(&o.stderr).contains(": correcting and writing:")
}

/// `rapidtherm correct` on the CAM sample written to a file and to
/// standard output, both as it is corrected: the same bytes, the same
/// exit and the same messages (the estimate's notes, the summary), for
/// one moment, an estimate and a schedule file that times every other
/// target (the rest at a default).
#[test]
fn a_file_and_standard_output_get_the_same_run() {
    let dir = tempfile::tempdir().unwrap();
    let sample = concat!(env!("CARGO_MANIFEST_DIR"), "/samples/cam_contour.mod");
    std::fs::copy(sample, dir.path().join("cam.mod")).unwrap();
    let run = |args: &[&str]| rapidtherm(args, dir.path());
    let estimate = run(&["schedule", "cam.mod", "--start", "10"]);
    let csv = String::from_utf8(estimate.stdout).unwrap();
    let every_other: String = csv
        .lines()
        .enumerate()
        .filter(|(i, _)| i % 2 == 0)
        .map(|(_, l)| format!("{l}\n"))
        .collect();
    std::fs::write(dir.path().join("half.csv"), every_other).unwrap();
    for when in [
        &["--at", "120"][..],
        &["--start", "0"],
        &["--start", "45", "--cycles", "3", "--visit", "last"],
        &["--schedule", "half.csv", "--default-time", "200"],
    ] {
        let args = |out: &str| -> Vec<String> {
            ["correct", "cam.mod", "-vv", "-o", out]
                .iter()
                .chain(when)
                .map(|s| s.to_string())
                .collect()
        };
        let streamed = run(&args("out.mod")
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>());
        let whole = run(&args("-").iter().map(String::as_str).collect::<Vec<_>>());
        for o in [&streamed, &whole] {
            assert!(
                was_streamed(o),
                "{when:?} was not streamed:\n{}",
                String::from_utf8_lossy(&o.stderr)
            );
        }
        assert_eq!(streamed.status.code(), whole.status.code(), "{when:?}");
        assert_eq!(said(&streamed), said(&whole), "{when:?}");
        let written = std::fs::read(dir.path().join("out.mod")).unwrap();
        assert!(written == whole.stdout, "{when:?}: the files differ");
    }
}

/// A schedule on standard input is read once and gives what the same
/// schedule by file gives.
#[test]
fn a_schedule_on_standard_input_is_read_once() {
    use std::io::Write;
    let dir = tempfile::tempdir().unwrap();
    let sample = concat!(env!("CARGO_MANIFEST_DIR"), "/samples/cam_contour.mod");
    std::fs::copy(sample, dir.path().join("cam.mod")).unwrap();
    let bin = env!("CARGO_BIN_EXE_rapidtherm");
    let run = |args: &[&str], stdin: &[u8]| {
        let mut child = std::process::Command::new(bin)
            .args(args)
            .current_dir(dir.path())
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        child.stdin.take().unwrap().write_all(stdin).unwrap();
        child.wait_with_output().unwrap()
    };
    let csv = run(&["schedule", "cam.mod", "--start", "10"], b"").stdout;
    std::fs::write(dir.path().join("s.csv"), &csv).unwrap();
    let piped = run(
        &[
            "correct",
            "cam.mod",
            "--schedule",
            "-",
            "-o",
            "a.mod",
            "-vv",
        ],
        &csv,
    );
    let said = String::from_utf8_lossy(&piped.stderr);
    assert!(piped.status.success(), "{said}");
    let by_file = run(
        &["correct", "cam.mod", "--schedule", "s.csv", "-o", "b.mod"],
        b"",
    );
    assert!(by_file.status.success());
    let a = std::fs::read(dir.path().join("a.mod")).unwrap();
    let b = std::fs::read(dir.path().join("b.mod")).unwrap();
    // The marker names the schedule by its times, not by its file.
    assert!(
        a == b,
        "a schedule piped and the same schedule by file differ"
    );
}

/// `--in-place` streams too: the file becomes what `-o -` writes, its
/// backup the original, with the same exit and
/// messages; a second run says the file is corrected already and changes
/// neither it nor its backup; and a run that changes nothing leaves the
/// file as it is, with no backup.
#[test]
fn in_place_streams_and_writes_what_the_whole_path_writes() {
    let dir = tempfile::tempdir().unwrap();
    let sample = concat!(env!("CARGO_MANIFEST_DIR"), "/samples/cam_contour.mod");
    let original = std::fs::read(sample).unwrap();
    let run = |args: &[String]| rapidtherm(args, dir.path());
    for when in [&["--at", "120"][..], &["--start", "0"]] {
        std::fs::write(dir.path().join("cam.mod"), &original).unwrap();
        let _ = std::fs::remove_file(dir.path().join("cam.mod.orig"));
        let with = |more: &[&str]| -> Vec<String> {
            ["correct", "cam.mod", "-vv"]
                .iter()
                .chain(more)
                .chain(when)
                .map(|s| s.to_string())
                .collect()
        };
        let whole = run(&with(&["-o", "-"]));
        let in_place = run(&with(&["--in-place", "--backup", ".orig"]));
        assert!(was_streamed(&in_place), "{when:?} was not streamed");
        assert_eq!(in_place.status.code(), whole.status.code(), "{when:?}");
        assert_eq!(said(&in_place), said(&whole), "{when:?}");
        let written = std::fs::read(dir.path().join("cam.mod")).unwrap();
        assert!(written == whole.stdout, "{when:?}: the files differ");
        let backup = std::fs::read(dir.path().join("cam.mod.orig")).unwrap();
        assert!(
            backup == original,
            "{when:?}: the backup is not the original"
        );
        // Again, its backup there: the file is corrected already, which
        // is said (for the same moment, or the same estimate's request, it
        // is no error: before, `--start` refused its own output as
        // another basis), and neither the file nor its backup changes.
        let again = run(&with(&["--in-place", "--backup", ".orig"]));
        let again_said = said(&again).join("\n");
        assert!(again_said.contains("already corrected"), "{again_said}");
        assert_eq!(again.status.code(), Some(0), "{when:?}: {again_said}");
        assert!(std::fs::read(dir.path().join("cam.mod")).unwrap() == written);
        assert!(std::fs::read(dir.path().join("cam.mod.orig")).unwrap() == original);
    }
    // Cold at minute 0: nothing changes, nothing is written.
    std::fs::write(dir.path().join("cold.mod"), &original).unwrap();
    let before = std::fs::metadata(dir.path().join("cold.mod"))
        .unwrap()
        .modified()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(20));
    let cold = run(&[
        "correct",
        "cold.mod",
        "-vv",
        "--at",
        "0",
        "--in-place",
        "--backup",
        ".orig",
    ]
    .map(String::from));
    assert!(was_streamed(&cold), "the cold run was not streamed");
    assert_eq!(cold.status.code(), Some(0));
    assert!(std::fs::read(dir.path().join("cold.mod")).unwrap() == original);
    let after = std::fs::metadata(dir.path().join("cold.mod"))
        .unwrap()
        .modified()
        .unwrap();
    assert_eq!(before, after, "an unchanged file was written");
    assert!(!dir.path().join("cold.mod.orig").exists());
}
