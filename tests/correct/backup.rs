//! `rapidtherm correct` on a whole controller backup
//! (`samples/backup_multimove`: two IRB 140 motion tasks, a background
//! task, tools in `user.sys`, a run-time placeholder, a 20,000-element
//! robtarget array, conditional arguments, `1THEN`, `MODULE 1_T_ROB2`).

use super::common::copy_tree;
use super::rapidtherm;
use std::path::{Path, PathBuf};
use std::process::Output;

fn sample() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("samples/backup_multimove")
}

/// Every file of a tree, by path relative to its root, with its bytes.
fn files(root: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push((
                    p.strip_prefix(root).unwrap().to_path_buf(),
                    std::fs::read(&p).unwrap(),
                ));
            }
        }
    }
    out.sort();
    out
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

#[test]
fn at_minute_zero_every_file_of_the_backup_stays_byte_identical() {
    let dir = tempfile::tempdir().unwrap();
    let bk = dir.path().join("bk");
    copy_tree(&sample(), &bk);
    let out = rapidtherm(&["correct", "bk", "--at", "0", "--in-place"], dir.path());
    assert!(out.status.success(), "{}", text(&out));
    assert_eq!(files(&bk), files(&sample()));
}

#[test]
fn one_command_corrects_both_motion_tasks_and_rewrites_only_edited_files() {
    let dir = tempfile::tempdir().unwrap();
    let bk = dir.path().join("bk");
    copy_tree(&sample(), &bk);
    let out = rapidtherm(&["correct", "bk", "--at", "120", "--in-place"], dir.path());
    assert!(out.status.success(), "{}", text(&out));
    let log = text(&out);
    assert!(log.contains("task T_COM is not a motion task"), "{log}");
    assert!(
        log.contains("20003 target(s) corrected (20003 rewritten)"),
        "{log}"
    );
    assert!(log.contains("3 target(s) corrected (3 rewritten)"), "{log}");
    // The run-time placeholder is reported, not corrected.
    assert!(
        log.contains("left alone pCamera") && log.contains("[runtime]"),
        "{log}"
    );
    let changed: Vec<PathBuf> = files(&bk)
        .into_iter()
        .zip(files(&sample()))
        .filter(|((_, a), (_, b))| a != b)
        .map(|((p, _), _)| p)
        .collect();
    assert_eq!(
        changed,
        [
            PathBuf::from("RAPID/TASK1/PROGMOD/MainModule.mod"),
            PathBuf::from("RAPID/TASK1/PROGMOD/ScanPath.mod"),
            PathBuf::from("RAPID/TASK2/PROGMOD/1_T_ROB2.mod"),
        ]
    );
    // The same bytes as correcting the task's files by hand, with its
    // tools from its user.sys (robot 1 stands at the world origin; robot
    // 2's placement comes only from the backup's MOC.cfg).
    let by_hand = dir.path().join("by_hand");
    copy_tree(&sample(), &by_hand);
    let out = rapidtherm(
        &[
            "correct",
            "by_hand/RAPID/TASK1/SYSMOD/user.sys",
            "by_hand/RAPID/TASK1/PROGMOD/MainModule.mod",
            "by_hand/RAPID/TASK1/PROGMOD/ScanPath.mod",
            "--at",
            "120",
            "--in-place",
        ],
        dir.path(),
    );
    assert!(out.status.success(), "{}", text(&out));
    for rel in [
        "RAPID/TASK1/PROGMOD/MainModule.mod",
        "RAPID/TASK1/PROGMOD/ScanPath.mod",
    ] {
        assert!(
            std::fs::read(bk.join(rel)).unwrap() == std::fs::read(by_hand.join(rel)).unwrap(),
            "{rel}"
        );
    }
    let again = rapidtherm(&["correct", "bk", "--at", "120", "--in-place"], dir.path());
    assert!(again.status.success(), "{}", text(&again));
    assert!(
        text(&again).contains("already corrected"),
        "{}",
        text(&again)
    );
    let other = rapidtherm(&["correct", "bk", "--at", "60", "--check"], dir.path());
    assert_eq!(other.status.code(), Some(2), "{}", text(&other));
}

#[test]
fn an_arm_without_thermal_defaults_is_refused_unless_said() {
    let dir = tempfile::tempdir().unwrap();
    let bk = dir.path().join("bk");
    copy_tree(&sample(), &bk);
    let moc = bk.join("SYSPAR/MOC.cfg");
    let text_moc = std::fs::read_to_string(&moc).unwrap();
    std::fs::write(
        &moc,
        text_moc.replace("ROB2_140_0.81_6", "ROB2_6660_1.90_205"),
    )
    .unwrap();
    let out = rapidtherm(&["correct", "bk", "--at", "120", "--check"], dir.path());
    assert_eq!(out.status.code(), Some(2), "{}", text(&out));
    assert!(text(&out).contains("ROB2_6660_1.90_205"), "{}", text(&out));
    // Naming the arm of that task, or picking the other task, runs.
    let out = rapidtherm(
        &[
            "correct", "bk", "--at", "120", "--task", "T_ROB1", "--check",
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
    let out = rapidtherm(
        &[
            "correct",
            "bk",
            "--at",
            "120",
            "--robot",
            "T_ROB2=irb140",
            "--check",
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
    // A type the catalogue has: found by family, payload and reach, and
    // refused for want of thermal defaults until the user says which.
    std::fs::write(
        &moc,
        text_moc.replace("ROB2_140_0.81_6", "ROB2_2600_1.65_12"),
    )
    .unwrap();
    let out = rapidtherm(&["correct", "bk", "--at", "120", "--check"], dir.path());
    assert_eq!(out.status.code(), Some(2), "{}", text(&out));
    assert!(
        text(&out).contains("task T_ROB2: IRB 2600-12/1.65 is not an IRB 140"),
        "{}",
        text(&out)
    );
    // Past the thermal refusal with --irb140-thermal: the IRB 140's
    // targets are not an IRB 2600's (their robconf has no solution
    // there), an error of its own.
    let out = rapidtherm(
        &[
            "correct",
            "bk",
            "--at",
            "120",
            "--check",
            "--irb140-thermal",
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2), "{}", text(&out));
    assert!(!text(&out).contains("not an IRB 140"), "{}", text(&out));
    assert!(text(&out).contains("robconf"), "{}", text(&out));
    // A designation that names a payload class (the IRB 2400-10 carries
    // 12 kg) is found by the designation.
    std::fs::write(
        &moc,
        text_moc.replace("ROB2_140_0.81_6", "ROB2_2400_1.55_10"),
    )
    .unwrap();
    let out = rapidtherm(&["correct", "bk", "--at", "120", "--check"], dir.path());
    assert!(
        text(&out).contains("task T_ROB2: IRB 2400-10 is not an IRB 140"),
        "{}",
        text(&out)
    );
}

#[test]
fn each_robot_stands_where_moc_cfg_places_it() {
    let dir = tempfile::tempdir().unwrap();
    let bk = dir.path().join("bk");
    copy_tree(&sample(), &bk);
    let moc = bk.join("SYSPAR/MOC.cfg");
    let placed = std::fs::read_to_string(&moc).unwrap();
    // Robot 2 faces robot 1 from 1.6 m: its fixture's targets are in
    // reach from there and nowhere near the world origin.
    let at_origin = placed.replace(
        "-base_frame_pos_x 1.6 -base_frame_orient_u0 0 -base_frame_orient_u3 1",
        "-base_frame_pos_x 0",
    );
    assert_ne!(at_origin, placed);
    std::fs::write(&moc, &at_origin).unwrap();
    let out = rapidtherm(
        &["correct", "bk", "--task", "T_ROB2", "--at", "120"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2), "{}", text(&out));
    assert!(text(&out).contains("out of reach"), "{}", text(&out));
    // A robot on a track: its base is elsewhere at every target; refused
    // by name rather than corrected as if it stood still.
    let on_track = placed.replace(
        "-base_frame_pos_x 1.6",
        "-base_frame_coordinated \"TRACK_2\" -base_frame_pos_x 1.6",
    );
    std::fs::write(&moc, &on_track).unwrap();
    let out = rapidtherm(
        &["correct", "bk", "--task", "T_ROB2", "--at", "120"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2), "{}", text(&out));
    assert!(text(&out).contains("TRACK_2"), "{}", text(&out));
}

/// A backup whose configuration does not place its robots is refused,
/// with the file it lacks, and nothing is written; the user can accept the
/// default placement (the world origin) explicitly. Before, the robots
/// were silently put at the origin as IRB 140s.
#[test]
fn a_backup_that_does_not_place_its_robots_is_refused_unless_the_default_is_accepted() {
    type Breaks<'a> = &'a dyn Fn(&Path);
    let edit = |bk: &Path, file: &str, from: &str, to: &str| {
        let p = bk.join(file);
        let t = std::fs::read_to_string(&p).unwrap();
        assert!(t.contains(from), "{file} has no {from}");
        std::fs::write(&p, t.replace(from, to)).unwrap();
    };
    // Robot 1's task: without backinfo.txt, it is named by its folder.
    let cases: [(&str, Breaks, &str, &str); 5] = [
        (
            "no backinfo",
            &|bk| std::fs::remove_file(bk.join("BACKINFO/backinfo.txt")).unwrap(),
            "the backup has no BACKINFO/backinfo.txt",
            "TASK1",
        ),
        (
            "no MOC.cfg",
            &|bk| std::fs::remove_file(bk.join("SYSPAR/MOC.cfg")).unwrap(),
            "the backup has no SYSPAR/MOC.cfg",
            "T_ROB1",
        ),
        (
            "garbled SYS.cfg",
            &|bk| std::fs::write(bk.join("SYSPAR/SYS.cfg"), "garbage\n").unwrap(),
            "SYSPAR/SYS.cfg is not a controller configuration file",
            "T_ROB1",
        ),
        (
            "a decimal comma in the base frame",
            &|bk| {
                edit(
                    bk,
                    "SYSPAR/MOC.cfg",
                    "-base_frame_pos_x 1.6",
                    "-base_frame_pos_x 1,6",
                )
            },
            "MOC.cfg's base_frame_pos_x is `1,6`",
            "T_ROB1",
        ),
        (
            "a task the backinfo does not list",
            &|bk| {
                edit(
                    bk,
                    "BACKINFO/backinfo.txt",
                    ">>TASK2: (T_ROB2,,)",
                    ">>TASK9: (T_ROB9,,)",
                )
            },
            "backinfo.txt does not list the task folder TASK2",
            "T_ROB1",
        ),
    ];
    for (what, break_it, says, rob1) in cases {
        let dir = tempfile::tempdir().unwrap();
        let bk = dir.path().join("bk");
        copy_tree(&sample(), &bk);
        break_it(&bk);
        let before = files(&bk);
        for cmd in [
            &["correct", "bk", "--at", "120", "--in-place"][..],
            &[
                "correct", "bk", "--at", "120", "--check", "--robot", "irb140",
            ],
        ] {
            let out = rapidtherm(cmd, dir.path());
            let log = text(&out);
            assert_eq!(out.status.code(), Some(2), "{what}: {cmd:?}: {log}");
            assert!(log.contains(says), "{what}: {log}");
            assert!(log.contains("--accept-default-placement"), "{what}: {log}");
            assert_eq!(files(&bk), before, "{what}: written");
        }
        // Robot 1 stands at the world origin: accepted, it is corrected.
        let out = rapidtherm(
            &[
                "correct",
                "bk",
                "--task",
                rob1,
                "--at",
                "120",
                "--in-place",
                "--accept-default-placement",
            ],
            dir.path(),
        );
        assert!(out.status.success(), "{what}: {}", text(&out));
        assert_ne!(files(&bk), before, "{what}: nothing written");
    }
}

/// A robot type missing from MOC.cfg is made up for by naming the arm;
/// the base frame it gives is still used.
#[test]
fn a_named_arm_makes_up_for_a_missing_robot_type_but_not_for_a_place() {
    let dir = tempfile::tempdir().unwrap();
    let bk = dir.path().join("bk");
    copy_tree(&sample(), &bk);
    let p = bk.join("SYSPAR/MOC.cfg");
    let t = std::fs::read_to_string(&p).unwrap();
    std::fs::write(&p, t.replace("-use_robot_type \"ROB2_140_0.81_6\" ", "")).unwrap();
    let args = [
        "correct", "bk", "--task", "T_ROB2", "--at", "120", "--check",
    ];
    let out = rapidtherm(&args, dir.path());
    assert_eq!(out.status.code(), Some(2), "{}", text(&out));
    assert!(
        text(&out).contains("MOC.cfg's robot ROB_2 has no use_robot_type"),
        "{}",
        text(&out)
    );
    let named = rapidtherm(
        &[&args[..], &["--robot", "T_ROB2=irb140"]].concat(),
        dir.path(),
    );
    // Named, the task is corrected where MOC.cfg places it: robot 2's
    // targets are out of reach at the origin, so a run that reached them
    // used the backup's base frame.
    assert_eq!(named.status.code(), Some(1), "{}", text(&named));
    assert!(
        text(&named).contains("3 target(s) would be corrected"),
        "{}",
        text(&named)
    );
}

/// One file read by two motion tasks (a module hard-linked into both task
/// folders, or a task folder named beside its backup) is refused before
/// anything is read or written, whatever the action: before, the last
/// task's correction was written, and `--check` judged each task alone.
#[test]
fn a_file_read_by_two_tasks_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let bk = dir.path().join("bk");
    copy_tree(&sample(), &bk);
    std::fs::remove_file(bk.join("RAPID/TASK2/SYSMOD/user.sys")).unwrap();
    std::fs::hard_link(
        bk.join("RAPID/TASK1/SYSMOD/user.sys"),
        bk.join("RAPID/TASK2/SYSMOD/user.sys"),
    )
    .unwrap();
    let before = files(&bk);
    for action in [&["--in-place"][..], &["--check"], &["--diff"]] {
        let out = rapidtherm(
            &[&["correct", "bk", "--at", "120"][..], action].concat(),
            dir.path(),
        );
        let log = text(&out);
        assert_eq!(out.status.code(), Some(2), "{action:?}: {log}");
        assert!(
            log.contains("bk/RAPID/TASK1/SYSMOD/user.sys is read by task T_ROB1 and, as bk/RAPID/TASK2/SYSMOD/user.sys, by task T_ROB2"),
            "{log}"
        );
        assert_eq!(files(&bk), before, "{action:?}: written");
    }
    // One task at a time is fine.
    let out = rapidtherm(
        &[
            "correct", "bk", "--task", "T_ROB1", "--at", "120", "--check",
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));

    let out = rapidtherm(
        &["correct", "bk", "bk/RAPID/TASK1", "--at", "120", "--check"],
        dir.path(),
    );
    let log = text(&out);
    assert_eq!(out.status.code(), Some(2), "{log}");
    assert!(
        log.contains("task T_ROB1 is named twice in this run"),
        "{log}"
    );
}

/// `--start` on the backup: the FOR loop over the scan array reads its
/// bounds and so its index at run time; the move to `pScan{i}` visits every
/// element in order, so each of the 20,000 gets a time and the run checks
/// them (before, the walk gave them none and the run was refused).
#[test]
fn a_scan_array_indexed_at_run_time_is_timed_element_by_element() {
    let dir = tempfile::tempdir().unwrap();
    let bk = dir.path().join("bk");
    copy_tree(&sample(), &bk);
    let out = rapidtherm(
        &[
            "correct", "bk", "--task", "T_ROB1", "--start", "0", "--check",
        ],
        dir.path(),
    );
    let log = text(&out);
    assert_eq!(out.status.code(), Some(1), "{log}");
    assert!(
        log.contains("its 20000 elements are visited in order, each timed"),
        "{log}"
    );
    assert!(!log.contains("the schedule has no time"), "{log}");
}

/// Targets the walk gives no time (here the scan array, once the call of
/// its routine is never taken) are one cause, said once with the others
/// counted (before, each was its own error, and finding each one's source
/// line took the run 24 s).
#[test]
fn targets_the_walk_cannot_time_are_one_error_counted() {
    let dir = tempfile::tempdir().unwrap();
    let bk = dir.path().join("bk");
    copy_tree(&sample(), &bk);
    let main = bk.join("RAPID/TASK1/PROGMOD/MainModule.mod");
    let text_of = std::fs::read_to_string(&main).unwrap();
    let cut = text_of.replace("    rScan;", "    IF FALSE rScan;");
    assert_ne!(cut, text_of);
    std::fs::write(&main, cut).unwrap();
    let out = rapidtherm(
        &[
            "correct", "bk", "--task", "T_ROB1", "--start", "0", "--check",
        ],
        dir.path(),
    );
    let log = text(&out);
    assert_eq!(out.status.code(), Some(2), "{log}");
    assert!(
        log.contains("target pScan{1}: the schedule has no time for it"),
        "{log}"
    );
    assert!(log.contains("the same for 19999 more"), "{log}");
}

/// A backup whose SYS.cfg marks no task as a motion task (the
/// `-MotionTask` flags deleted), though T_ROB1 and T_ROB2 hold moves: not
/// "every task left alone, nothing to check", but each target their moves
/// reach reported left cold, so that the check fails naming them; the
/// task that holds no move (T_COM) is still left alone. Written in place,
/// nothing changes.
#[test]
fn tasks_holding_moves_that_sys_cfg_does_not_mark_as_motion_tasks_fail_the_check() {
    let dir = tempfile::tempdir().unwrap();
    let bk = dir.path().join("bk");
    copy_tree(&sample(), &bk);
    let sys = bk.join("SYSPAR/SYS.cfg");
    let text_of_sys = std::fs::read_to_string(&sys).unwrap();
    std::fs::write(&sys, text_of_sys.replace(" -MotionTask", "")).unwrap();
    let before = files(&bk);
    let out = rapidtherm(&["correct", "bk", "--at", "120", "--check"], dir.path());
    let all = text(&out);
    assert_eq!(out.status.code(), Some(1), "{all}");
    let stdout = String::from_utf8_lossy(&out.stdout);
    // T_ROB2's three targets (`1_T_ROB2.mod`: pPick line 4, pPlace line
    // 5, jHome line 6), each with the reason.
    for (id, at) in [
        ("pPick", "1_T_ROB2.mod:4:"),
        ("pPlace", "1_T_ROB2.mod:5:"),
        ("jHome", "1_T_ROB2.mod:6:"),
        ("pHome", "MainModule.mod:4:"),
    ] {
        let row = stdout
            .lines()
            .find(|l| l.starts_with(&format!("{id} ")))
            .unwrap_or_else(|| panic!("no row of {id}: {all}"));
        assert!(
            row.contains(at) && row.contains("left-alone") && row.contains("not-motion-task"),
            "{row}"
        );
    }
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("task T_ROB2 holds 5 move instruction(s), but SYSPAR/SYS.cfg does not mark it as a motion task"), "{stderr}");
    assert!(
        stderr.contains("task T_COM is not a motion task (SYSPAR/SYS.cfg): left alone"),
        "{stderr}"
    );
    let out = rapidtherm(&["correct", "bk", "--at", "120", "--in-place"], dir.path());
    assert!(out.status.success(), "{}", text(&out));
    assert_eq!(files(&bk), before);
}
