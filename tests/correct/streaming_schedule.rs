//! The streamed main job timed by a schedule (`--start`, `--schedule`):
//! the whole program read from the skeleton (`rapid::parse_skeleton`) is
//! estimated as the whole parse is, and the streamed run (`CutTimes`,
//! each cut target corrected for its own moment) writes the bytes and
//! says the summary of the whole-program path, on the generated programs
//! of `streaming`: an estimated schedule as `--start` makes it, and a
//! user's file that times every other target, the rest at a default.
//! `--start`'s own first pass, the skeleton read in runs of cut moves
//! walked from the file (`schedule::estimate_cuts`), times them as the
//! whole walk does, and the streamed run by it writes the same bytes.

use super::rapidtherm;
use super::streaming::{program_with, stmt, streamed_as_whole, warm, Stmt};
use proptest::prelude::*;
use rapidtherm::correct::{correct, CutTimes, Options, When};
use rapidtherm::model::warm::Moment;
use rapidtherm::rapid::fastmove::{skeleton, skeleton_with_poses};
use rapidtherm::rapid::{self, Program};
use rapidtherm::robot::Robot;
use rapidtherm::schedule::{estimate, estimate_cuts, EstimateOptions, Schedule};
use std::process::Output;

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
        });
    }
    let mut file = Schedule::new();
    for id in est.schedule.targets().iter().step_by(2) {
        for &t in est.schedule.times(id).unwrap_or(&[]) {
            file.visit(id, t);
        }
    }
    Some(When::Schedule {
        schedule: file,
        joints: None,
        default,
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

/// `--start`'s first pass: the skeleton read in runs, its cut moves walked
/// from the file. Where it does not decline, its schedule and cut
/// literals' visits are the whole estimate's, its notes too, and the
/// streamed run by them writes what the whole path writes (or declines,
/// where a cut literal is out of reach: the walk leaves that to the
/// correction). `Some(false)`: the streamed run declined; `None`: the
/// walk did.
fn estimated_in_runs_as_whole(src: &[u8], entry: &str) -> Option<bool> {
    let whole_program = rapid::parse("p.mod", src).expect("generated programs parse");
    // Cut as `--start` cuts, keeping the numbers of the cut literals:
    // each move's numbers are those it reads again with.
    let skel = skeleton_with_poses(src);
    let poses = skel.poses.as_ref().expect("asked for");
    for k in 0..skel.cuts.len() {
        let m = skel.reread(src, k).expect("a cut move reads again");
        let kept = poses.numbers_of(k, m.targets.len()).expect("kept");
        for ((_, v), n) in m.targets.iter().zip(kept) {
            let read: Vec<f64> = v
                .trans_values()
                .into_iter()
                .chain(v.rot_values())
                .chain(v.robconf_values())
                .collect();
            assert_eq!(&read[..], &n[..]);
        }
    }
    let program = rapid::parse("p.mod", &skel.bytes).expect("the skeleton parses");
    let runs = rapid::parse_skeleton_runs("p.mod", &skel, src).expect("the skeleton reads in runs");
    let opts = estimate_options(entry);
    let walked = estimate_cuts(&runs, (&skel, src), &Robot::irb140(), &opts, false).ok()??;
    let Ok(est) = estimate(&whole_program, &Robot::irb140(), &opts) else {
        // Refused for a target out of reach, which the walk of the runs
        // does not ask of cut literals: the correction does, and declines.
        let when = When::Schedule {
            schedule: walked.estimate.schedule,
            joints: Some(walked.estimate.joint_schedule),
            default: None,
        };
        let options = Options::new(when);
        let times = CutTimes::of_estimate(walked.literals, &runs, &program, &options)?;
        let streamed = streamed_as_whole(
            src,
            (&skel, &program),
            (&options, Some(&times)),
            Err(rapidtherm::error::Error::input("refused")),
        );
        assert!(
            !streamed,
            "the fast path corrected a program the whole estimate refuses"
        );
        return Some(false);
    };
    let encoded = |f: &dyn Fn(&mut rapidtherm::digest::Encoder)| {
        let mut e = rapidtherm::digest::Encoder::new("test");
        f(&mut e);
        e.finish()
    };
    assert_eq!(
        encoded(&|e| walked.literals.encode_whole(&walked.estimate.schedule, e)),
        encoded(&|e| est.schedule.encode(e)),
        "the walk of the runs timed the cut literals otherwise"
    );
    assert_eq!(walked.estimate.joint_schedule, est.joint_schedule);
    // `schedule FILE`'s CSV and counts, made from the walk of the runs.
    let (csv, targets, visits) = walked.to_csv();
    assert_eq!(csv, est.to_csv());
    assert_eq!(
        (targets, visits),
        (
            est.schedule.targets().len() + est.joint_schedule.targets().len(),
            est.schedule.visit_count() + est.joint_schedule.visit_count()
        )
    );
    assert_eq!(walked.estimate.notes, est.notes);
    assert_eq!(walked.estimate.duration_min, est.duration_min);
    let default = Some(Moment::Minute(45.0));
    let whole = correct(
        &whole_program,
        warm(),
        &Options::new(When::Schedule {
            schedule: est.schedule,
            joints: Some(est.joint_schedule),
            default,
        }),
        &mut |_, _| {},
    );
    let options = Options::new(When::Schedule {
        schedule: walked.estimate.schedule,
        joints: Some(walked.estimate.joint_schedule),
        default,
    });
    let times = CutTimes::of_estimate(walked.literals, &runs, &program, &options)
        .expect("the readings line up");
    Some(streamed_as_whole(
        src,
        (&skel, &program),
        (&options, Some(&times)),
        whole,
    ))
}

/// Whether the streamed run timed as [`when_of`] says wrote what the
/// whole path writes; `false` when either declined or the estimate was
/// refused.
fn scheduled_as_whole(src: &[u8], entry: &str, partial: bool) -> bool {
    let Ok(whole_program) = rapid::parse("p.mod", src) else {
        return false;
    };
    let Some(when) = when_of(&whole_program, entry, partial) else {
        return false;
    };
    let options = Options::new(when);
    let whole = correct(&whole_program, warm(), &options, &mut |_, _| {});
    let skel = skeleton(src);
    let program = rapid::parse("p.mod", &skel.bytes).expect("the skeleton parses");
    let read = rapid::parse_skeleton("p.mod", &skel, src).expect("the skeleton reads whole");
    // The first pass: the program read from the skeleton is timed as the
    // whole parse is.
    assert_eq!(when_of(&read, entry, partial), Some(options.when.clone()));
    let Some(times) = CutTimes::new(&read, &program, &skel, &options) else {
        return false;
    };
    streamed_as_whole(src, (&skel, &program), (&options, Some(&times)), whole)
}

#[test]
fn a_cam_program_streams_timed_by_its_schedule() {
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
        assert!(
            scheduled_as_whole(&src, entry, partial),
            "the fast path declined a CAM program (partial schedule: {partial}, one name: {one_name})"
        );
        assert_eq!(
            estimated_in_runs_as_whole(&src, entry),
            Some(true),
            "the walk of the runs or its streamed run declined a CAM program (one name: {one_name})"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    #[test]
    fn streamed_and_whole_write_the_same_bytes_by_a_schedule(
        bodies in prop::collection::vec(prop::collection::vec(stmt(), 0..40), 1..3),
        crlf in any::<bool>(),
        partial in any::<bool>(),
        one_name in any::<bool>(),
    ) {
        // With one routine name in every module, identifiers name their
        // module (`M1:main#3`).
        let src = program_with(&bodies, if crlf { "\r\n" } else { "\n" }, false, one_name);
        let entry = if one_name { "main" } else { "main0" };
        scheduled_as_whole(&src, entry, partial);
        estimated_in_runs_as_whole(&src, entry);
    }
}

/// What a run said on standard error, less the `-vv` timings.
fn said(o: &Output) -> Vec<String> {
    String::from_utf8_lossy(&o.stderr)
        .lines()
        .filter(|l| !l.starts_with("info:"))
        .map(str::to_string)
        .collect()
}

/// Whether a `-vv` run took the streamed path.
fn was_streamed(o: &Output) -> bool {
    String::from_utf8_lossy(&o.stderr).contains("info: correcting and writing")
}

/// `rapidtherm correct` on the CAM sample written to a file (streamed)
/// and to standard output (the whole-program path): the same bytes, the
/// same exit and the same messages (the estimate's notes, the summary),
/// for one moment, an estimate and a schedule file that times every
/// other target (the rest at a default).
#[test]
fn the_binary_streams_a_scheduled_run_as_it_corrects_it_whole() {
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
        assert!(
            was_streamed(&streamed),
            "{when:?} was not streamed:\n{}",
            String::from_utf8_lossy(&streamed.stderr)
        );
        assert_eq!(streamed.status.code(), whole.status.code(), "{when:?}");
        assert_eq!(said(&streamed), said(&whole), "{when:?}");
        let written = std::fs::read(dir.path().join("out.mod")).unwrap();
        assert!(written == whole.stdout, "{when:?}: the files differ");
    }
}

/// A schedule on standard input is read once: the run takes the
/// whole-program path (the streamed one, should it decline, would leave
/// the whole path nothing to read) and writes what the file gives.
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
    assert!(!said.contains("correcting and writing"), "{said}");
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

/// `--in-place` streams too: the file becomes what the whole-program
/// path writes (`-o -`), its backup the original, with the same exit and
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
        // is said (for the same moment it is no error), and neither the
        // file nor its backup changes.
        let again = run(&with(&["--in-place", "--backup", ".orig"]));
        let again_said = said(&again).join("\n");
        assert!(again_said.contains("already corrected"), "{again_said}");
        assert_eq!(
            again.status.code(),
            Some(if when[0] == "--at" { 0 } else { 2 })
        );
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
