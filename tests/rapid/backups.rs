//! A backup that says two things of one thing is refused, naming both
//! places; said twice alike, it is read. Each case breaks a copy of
//! `samples/backup_multimove` the way a hand-edited backup is broken; the
//! places (line:column) are counted by hand in the sample's files.

use proptest::prelude::*;
use rapidtherm::rapid::task::discover;
use std::path::{Path, PathBuf};

fn sample() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("samples/backup_multimove")
}

fn copy(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            copy(&p, &to.join(e.file_name()));
        } else {
            std::fs::copy(&p, to.join(e.file_name())).unwrap();
        }
    }
}

/// A copy of the sample with `file` (a path in the backup) edited by
/// `edit`.
fn broken(file: &str, edit: impl Fn(&str) -> String) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let bk = dir.path().join("bk");
    copy(&sample(), &bk);
    let path = bk.join(file);
    // The sample's files end their lines in CRLF: edited as LF.
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("\r\n", "\n");
    let edited = edit(&text);
    assert_ne!(edited, text, "the edit changed nothing");
    std::fs::write(&path, edited.replace('\n', "\r\n")).unwrap();
    (dir, bk)
}

fn refusal(bk: &Path) -> String {
    discover(&[bk.to_path_buf()]).unwrap_err().to_string()
}

/// The message names `file` at both places, and points at the second.
fn names_both(e: &str, bk: &Path, file: &str, first: (usize, usize), second: (usize, usize)) {
    let f = bk.join(file).display().to_string();
    let (a, b) = (
        format!("{f}:{}:{}", first.0, first.1),
        format!("{f}:{}:{}", second.0, second.1),
    );
    assert!(e.starts_with(&format!("{b}: error: ")), "{e}");
    assert!(e.contains(&format!("(at {a} and at {b})")), "{e}");
}

#[test]
fn the_sample_itself_is_one_truth() {
    assert_eq!(discover(&[sample()]).unwrap().len(), 3);
}

#[test]
fn two_motion_tasks_on_one_mechanical_unit_group_are_refused() {
    let (_d, bk) = broken("SYSPAR/SYS.cfg", |t| {
        t.replace(
            "-UseMechanicalUnitGroup \"rob2\" -MotionTask",
            "-UseMechanicalUnitGroup \"rob1\" -MotionTask",
        )
    });
    let e = refusal(&bk);
    // `"rob1"` at column 61 of lines 5 and 7.
    names_both(&e, &bk, "SYSPAR/SYS.cfg", (5, 61), (7, 61));
    assert!(
        e.contains("the motion tasks T_ROB1 and T_ROB2 both move mechanical unit group rob1"),
        "{e}"
    );
}

#[test]
fn a_task_declared_twice_in_sys_cfg_is_refused() {
    let (_d, bk) = broken("SYSPAR/SYS.cfg", |t| {
        t.replace(
            "      -UseMechanicalUnitGroup \"rob1\"\n#",
            "      -UseMechanicalUnitGroup \"rob1\"\n      -Name \"T_ROB1\" -Type \"STATIC\"\n#",
        )
    });
    let e = refusal(&bk);
    // `"T_ROB1"` at column 13 of line 5, and of the new line 11.
    names_both(&e, &bk, "SYSPAR/SYS.cfg", (5, 13), (11, 13));
    assert!(e.contains("CAB_TASKS T_ROB1 is declared twice"), "{e}");
}

#[test]
fn one_robot_in_two_groups_is_refused() {
    let (_d, bk) = broken("SYSPAR/SYS.cfg", |t| {
        t.replace("-Robot \"ROB_2\"", "-Robot \"ROB_1\"")
    });
    let e = refusal(&bk);
    // `"ROB_1"` at column 27 of lines 14 and 16.
    names_both(&e, &bk, "SYSPAR/SYS.cfg", (14, 27), (16, 27));
    assert!(
        e.contains("robot ROB_1 is in two mechanical unit groups, rob1 and rob2"),
        "{e}"
    );
}

#[test]
fn a_moc_key_given_twice_is_refused() {
    let (_d, bk) = broken("SYSPAR/MOC.cfg", |t| {
        t.replace(
            "-base_frame_orient_u3 1",
            "-base_frame_orient_u3 1 -base_frame_pos_x 0",
        )
    });
    let e = refusal(&bk);
    // `1.6` at column 25 of line 22; the `0` after
    // `-base_frame_orient_u3 1 -base_frame_pos_x ` at column 95.
    let line = "      -base_frame_pos_x 1.6 -base_frame_orient_u0 0 -base_frame_orient_u3 1 -base_frame_pos_x ";
    assert_eq!(line.len() + 1, 95);
    names_both(&e, &bk, "SYSPAR/MOC.cfg", (22, 25), (22, 95));
    assert!(
        e.contains("ROBOT ROB_2 gives -base_frame_pos_x twice"),
        "{e}"
    );
}

#[test]
fn a_robot_defined_twice_with_two_types_is_refused() {
    let (_d, bk) = broken("SYSPAR/MOC.cfg", |t| {
        t.replace(
            "-base_frame_orient_u3 1\n",
            "-base_frame_orient_u3 1\n\n      -name \"ROB_1\" -use_robot_type \"ROB1_6700_2.65_200\"\n",
        )
    });
    let e = refusal(&bk);
    // `"ROB_1"` at column 13 of line 13 and of the new line 24.
    names_both(&e, &bk, "SYSPAR/MOC.cfg", (13, 13), (24, 13));
    assert!(e.contains("ROBOT ROB_1 is declared twice"), "{e}");
}

#[test]
fn two_task_folders_of_one_name_are_refused() {
    // backinfo.txt gives TASK3 the name of TASK1.
    let (_d, bk) = broken("BACKINFO/backinfo.txt", |t| {
        t.replace(">>TASK3: (T_COM,,)", ">>TASK3: (T_ROB1,,)")
    });
    let e = refusal(&bk);
    assert!(e.contains("two task folders are task T_ROB1"), "{e}");
    let info = bk.join("BACKINFO/backinfo.txt").display().to_string();
    for (folder, line) in [("TASK1", 28), ("TASK3", 37)] {
        let f = bk.join("RAPID").join(folder).display().to_string();
        assert!(
            e.contains(&format!("{f} (listed at {info}:{line}:1)")),
            "{e}"
        );
    }
    // Two folders whose names differ only in case (a backup unpacked on a
    // file system that tells them apart).
    let (_d, bk) = broken("BACKINFO/backinfo.txt", |t| t.replace("@ \n", "@\n"));
    copy(&bk.join("RAPID/TASK1"), &bk.join("RAPID/task1"));
    let e = refusal(&bk);
    assert!(e.contains("two task folders are task T_ROB1"), "{e}");
    // One folder listed twice, differently.
    let (_d, bk) = broken("BACKINFO/backinfo.txt", |t| {
        t.replace(
            ">>EOF:",
            ">>TASK1: (T_OTHER,,)\nPROGMOD/MainModule.mod @\n\n>>EOF:",
        )
    });
    let e = refusal(&bk);
    let info = bk.join("BACKINFO/backinfo.txt").display().to_string();
    assert!(
        e.contains("the task folder TASK1 is listed twice, differently (at "),
        "{e}"
    );
    assert!(
        e.contains(&format!("{info}:28:1 and at {info}:42:1")),
        "{e}"
    );
}

fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20)
}

/// What a generated backup says twice.
#[derive(Debug, Clone)]
enum Twice {
    /// A task's entry repeated, with another `-Type`.
    Task,
    /// A group's entry repeated, with another robot.
    Group,
    /// A robot's entry repeated, with another type.
    Robot,
    /// One attribute given twice in a robot's entry.
    Key,
    /// The second motion task moved to the first's group.
    SharedGroup,
}

fn twice() -> impl Strategy<Value = Twice> {
    prop_oneof![
        Just(Twice::Task),
        Just(Twice::Group),
        Just(Twice::Robot),
        Just(Twice::Key),
        Just(Twice::SharedGroup),
    ]
}

/// A SYS.cfg and MOC.cfg of `n` motion tasks, each on its own group and
/// robot; with `twice` said twice (the second time `alike` or not), the
/// place of each saying (file, line, column), the files' lines ending in
/// `eol`, names in `upper` case or not.
fn configuration(
    n: usize,
    twice: &Twice,
    alike: bool,
    (eol, upper): (&str, bool),
) -> (String, String, [(&'static str, usize, usize); 2]) {
    let case = |s: String| if upper { s.to_uppercase() } else { s };
    let mut sys = vec![
        "SYS:CFG_1.0:6:0::".to_string(),
        "#".to_string(),
        "CAB_TASKS:".to_string(),
    ];
    let mut moc = vec![
        "MOC:CFG_1.0:6:0::".to_string(),
        "#".to_string(),
        "ROBOT:".to_string(),
    ];
    let task = |k: usize, group: usize, ty: &str| {
        format!(
            " -Name \"{}\" -Type \"{ty}\" -UseMechanicalUnitGroup \"{}\" -MotionTask",
            case(format!("T_ROB{k}")),
            case(format!("rob{group}"))
        )
    };
    // ` -Name "` is 8 characters: a value's quote stands at column 8; the
    // group's after ` -Name "T_ROBk" -Type "NORMAL" -UseMechanicalUnitGroup `.
    let group_col = |k: usize, ty: &str| {
        format!(" -Name \"T_ROB{k}\" -Type \"{ty}\" -UseMechanicalUnitGroup ").len() + 1
    };
    let robot = |k: usize, ty: &str| {
        format!(
            " -name \"{}\" -use_robot_type \"{ty}\" -base_frame_pos_x {k}",
            case(format!("ROB_{k}"))
        )
    };
    let mut places = [("", 0, 0); 2];
    for k in 1..=n {
        sys.push(task(k, k, "NORMAL"));
        moc.push(robot(k, "ROB1_140_0.81_6"));
    }
    match twice {
        Twice::Task => {
            places = [("SYS.cfg", 4, 8), ("SYS.cfg", 4 + n, 8)];
            sys.push(task(1, 1, if alike { "NORMAL" } else { "STATIC" }));
        }
        Twice::SharedGroup if alike => {
            // Task 1 named again, alike, on its own group: one truth.
            sys.push(task(1, 1, "NORMAL"));
        }
        Twice::SharedGroup => {
            // Task 2 moved to task 1's group.
            places = [
                ("SYS.cfg", 4, group_col(1, "NORMAL")),
                ("SYS.cfg", 5, group_col(2, "NORMAL")),
            ];
            sys[4] = task(2, 1, "NORMAL");
        }
        Twice::Robot => {
            places = [("MOC.cfg", 4, 8), ("MOC.cfg", 4 + n, 8)];
            moc.push(robot(
                1,
                if alike {
                    "ROB1_140_0.81_6"
                } else {
                    "ROB1_6700_2.65_200"
                },
            ));
        }
        Twice::Key => {
            let first = robot(1, "ROB1_140_0.81_6");
            let value = if alike { "1" } else { "0" };
            places = [
                ("MOC.cfg", 4, first.len()),
                ("MOC.cfg", 4, first.len() + " -base_frame_pos_x ".len() + 1),
            ];
            moc[3] = format!("{first} -base_frame_pos_x {value}");
        }
        Twice::Group => {}
    }
    sys.push("#".to_string());
    sys.push("MECHANICAL_UNIT_GROUP:".to_string());
    let g0 = sys.len() + 1;
    for k in 1..=n {
        sys.push(format!(
            " -Name \"{}\" -Robot \"{}\"",
            case(format!("rob{k}")),
            case(format!("ROB_{k}"))
        ));
    }
    if let Twice::Group = twice {
        places = [("SYS.cfg", g0, 8), ("SYS.cfg", g0 + n, 8)];
        let robot = if alike { 1 } else { 2 };
        sys.push(format!(
            " -Name \"{}\" -Robot \"{}\"",
            case("rob1".to_string()),
            case(format!("ROB_{robot}"))
        ));
    }
    sys.push("#".to_string());
    moc.push("#".to_string());
    let join = |v: Vec<String>| v.join(eol) + eol;
    (join(sys), join(moc), places)
}

/// A backup of `n` tasks (each a folder with one move) with these files.
fn backup(n: usize, sys: &str, moc: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let bk = dir.path();
    std::fs::create_dir_all(bk.join("SYSPAR")).unwrap();
    std::fs::create_dir_all(bk.join("BACKINFO")).unwrap();
    std::fs::write(bk.join("SYSPAR/SYS.cfg"), sys).unwrap();
    std::fs::write(bk.join("SYSPAR/MOC.cfg"), moc).unwrap();
    let mut info = String::new();
    for k in 1..=n {
        let task = bk.join(format!("RAPID/TASK{k}/PROGMOD"));
        std::fs::create_dir_all(&task).unwrap();
        std::fs::write(
            task.join("m.mod"),
            format!("MODULE M{k}\nPROC main()\nMoveL [[{k},0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;\nENDPROC\nENDMODULE\n"),
        )
        .unwrap();
        info.push_str(&format!(
            ">>TASK{k}: (T_ROB{k},,)\nPROGMOD/m.mod @ m.mod\n\n"
        ));
    }
    std::fs::write(bk.join("BACKINFO/backinfo.txt"), info).unwrap();
    dir
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

    /// Said twice differently: refused at the second place, naming the
    /// first; said twice alike: read, every task with its robot.
    #[test]
    fn a_generated_contradiction_is_refused_at_both_places(
        n in 2usize..5,
        what in twice(),
        alike in any::<bool>(),
        eol in prop::sample::select(vec!["\n", "\r\n", "\r"]),
        upper in any::<bool>(),
    ) {
        let (sys, moc, places) = configuration(n, &what, alike, (eol, upper));
        let dir = backup(n, &sys, &moc);
        let found = discover(&[dir.path().to_path_buf()]);
        if alike {
            let tasks = found.unwrap();
            prop_assert_eq!(tasks.len(), n);
            for t in &tasks {
                prop_assert_eq!(t.motion, Some(true));
                prop_assert!(t.robot_type.is_some(), "{:?}", t);
                prop_assert!(t.gaps.is_empty(), "{:?}", t.gaps);
            }
        } else {
            let e = found.unwrap_err().to_string();
            let at = |(file, line, col): (&str, usize, usize)| {
                format!("{}:{line}:{col}", dir.path().join("SYSPAR").join(file).display())
            };
            prop_assert!(e.starts_with(&format!("{}: error: ", at(places[1]))), "{}", e);
            prop_assert!(
                e.contains(&format!("(at {} and at {})", at(places[0]), at(places[1]))),
                "{}",
                e
            );
        }
    }
}
