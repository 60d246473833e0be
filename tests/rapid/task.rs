//! Tasks as the controller has them: a controller backup, its task
//! folders, program files (.pgf) and folders of modules, read by
//! `rapid::task::discover` into the modules of each task.

use rapidtherm::rapid::task::{discover, Task};
use std::path::{Path, PathBuf};

fn sample() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("samples/backup_multimove")
}

fn file_names(t: &Task) -> Vec<String> {
    t.modules
        .iter()
        .map(|p| {
            let parent = p.parent().and_then(Path::file_name).unwrap();
            format!(
                "{}/{}",
                parent.to_string_lossy(),
                p.file_name().unwrap().to_string_lossy()
            )
        })
        .collect()
}

#[test]
fn a_whole_backup_is_its_tasks_with_names_order_motion_and_robot() {
    let tasks = discover(&[sample()]).unwrap();
    let names: Vec<String> = tasks.iter().map(Task::label).collect();
    assert_eq!(names, ["T_ROB1", "T_ROB2", "T_COM"]);
    // backinfo.txt's load order: the system module first.
    assert_eq!(
        file_names(&tasks[0]),
        [
            "SYSMOD/user.sys",
            "PROGMOD/MainModule.mod",
            "PROGMOD/ScanPath.mod"
        ]
    );
    assert_eq!(tasks[0].motion, Some(true));
    assert_eq!(tasks[0].robot_type.as_deref(), Some("ROB1_140_0.81_6"));
    // Through its mechanical unit group rob2 to ROB_2.
    assert_eq!(tasks[1].robot_type.as_deref(), Some("ROB2_140_0.81_6"));
    // Robot 1 at the world origin; robot 2 1.6 m along x, turned about z
    // (MOC.cfg writes metres).
    assert_eq!(tasks[0].base_frame, None);
    assert_eq!(
        tasks[1].base_frame,
        Some(([1600.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]))
    );
    // No -MotionTask: a background task, whatever group it names.
    assert_eq!(tasks[2].motion, Some(false));
    assert_eq!(tasks[2].robot_type, None);
}

#[test]
fn the_rapid_folder_and_one_task_folder_know_their_backup() {
    let rapid = discover(&[sample().join("RAPID")]).unwrap();
    assert_eq!(rapid.len(), 3);
    assert_eq!(rapid[1].name.as_deref(), Some("T_ROB2"));
    let one = discover(&[sample().join("RAPID/TASK2")]).unwrap();
    assert_eq!(one.len(), 1);
    assert_eq!(one[0].name.as_deref(), Some("T_ROB2"));
    assert_eq!(one[0].motion, Some(true));
    assert_eq!(
        file_names(&one[0]),
        ["SYSMOD/user.sys", "PROGMOD/1_T_ROB2.mod"]
    );
}

#[test]
fn a_task_folder_without_a_backup_reads_system_then_program_modules() {
    let dir = tempfile::tempdir().unwrap();
    let task = dir.path().join("cell");
    for (sub, name) in [
        ("PROGMOD", "b.mod"),
        ("PROGMOD", "A.mod"),
        ("SYSMOD", "user.sys"),
    ] {
        std::fs::create_dir_all(task.join(sub)).unwrap();
        std::fs::write(task.join(sub).join(name), "MODULE x\nENDMODULE\n").unwrap();
    }
    std::fs::write(task.join("PROGMOD/notes.txt"), "not RAPID").unwrap();
    let tasks = discover(&[task]).unwrap();
    assert_eq!(tasks.len(), 1);
    assert_eq!(tasks[0].name.as_deref(), Some("cell"));
    assert_eq!(tasks[0].motion, None);
    assert_eq!(
        file_names(&tasks[0]),
        ["SYSMOD/user.sys", "PROGMOD/A.mod", "PROGMOD/b.mod"]
    );
}

#[test]
fn a_program_file_lists_its_modules_and_loose_files_join_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("Main.mod"), "MODULE Main\nENDMODULE\n").unwrap();
    std::fs::write(d.join("Path.mod"), "MODULE Path\nENDMODULE\n").unwrap();
    std::fs::write(d.join("Old.mod"), "MODULE Old\nENDMODULE\n").unwrap();
    std::fs::write(d.join("user.sys"), "MODULE user(SYSMODULE)\nENDMODULE\n").unwrap();
    std::fs::write(
        d.join("Cell.pgf"),
        "<?xml version=\"1.0\" encoding=\"ISO-8859-1\" ?>\r\n<Program>\r\n    <Module>Main.mod</Module>\r\n    <Module>path.MOD</Module>\r\n</Program>\r\n",
    )
    .unwrap();
    let tasks = discover(&[d.join("Cell.pgf"), d.join("user.sys")]).unwrap();
    assert_eq!(tasks.len(), 1);
    assert_eq!(tasks[0].name.as_deref(), Some("Cell"));
    let names: Vec<String> = tasks[0]
        .modules
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    // Old.mod is beside it but not in the program; the case of a listed
    // name does not matter, as on the controller.
    assert_eq!(names, ["Main.mod", "Path.mod", "user.sys"]);
    // The folder with its one program file is the program.
    let tasks = discover(&[d.to_path_buf()]).unwrap();
    assert_eq!(tasks[0].modules.len(), 2);
    // A listed module that is missing is an error naming it.
    std::fs::remove_file(d.join("Path.mod")).unwrap();
    let e = discover(&[d.join("Cell.pgf")]).unwrap_err().to_string();
    assert!(e.contains("path.MOD") && e.contains("not found"), "{e}");
}

#[test]
fn files_one_by_one_are_one_unnamed_task_as_given() {
    let files = vec![PathBuf::from("b.mod"), PathBuf::from("-")];
    let tasks = discover(&files).unwrap();
    assert_eq!(tasks.len(), 1);
    assert_eq!(tasks[0].name, None);
    assert_eq!(tasks[0].modules, files);
}

#[test]
fn a_folder_with_nothing_of_rapid_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("readme.txt"), "x").unwrap();
    let e = discover(&[dir.path().to_path_buf()])
        .unwrap_err()
        .to_string();
    assert!(e.contains("no RAPID modules"), "{e}");
}

/// A copy of the sample backup in a temporary folder, for breaking.
fn copy_of_sample() -> tempfile::TempDir {
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
    let dir = tempfile::tempdir().unwrap();
    copy(&sample(), &dir.path().join("bk"));
    dir
}

fn gap_texts(t: &Task) -> Vec<String> {
    t.gaps.iter().map(|g| g.kind.to_string()).collect()
}

#[test]
fn a_whole_backup_has_no_gaps() {
    for t in discover(&[sample()]).unwrap() {
        assert!(t.gaps.is_empty(), "{}: {:?}", t.label(), gap_texts(&t));
    }
}

/// Every part of a backup that says where a robot stands, when missing or
/// broken, is a gap of the motion tasks, with its file and, where the
/// file has it, its line: never a silent default.
#[test]
fn a_broken_backup_names_what_it_lacks() {
    use rapidtherm::rapid::task::placement::{BackupPart, GapKind};
    type Breaks<'a> = &'a dyn Fn(&Path);
    let cases: [(&str, Breaks, GapKind); 5] = [
        (
            "no backinfo",
            &|bk: &Path| std::fs::remove_file(bk.join("BACKINFO/backinfo.txt")).unwrap(),
            GapKind::Missing(BackupPart::BackInfo),
        ),
        (
            "no MOC.cfg",
            &|bk: &Path| std::fs::remove_file(bk.join("SYSPAR/MOC.cfg")).unwrap(),
            GapKind::Missing(BackupPart::Moc),
        ),
        (
            "garbled SYS.cfg",
            &|bk: &Path| std::fs::write(bk.join("SYSPAR/SYS.cfg"), "garbage\n").unwrap(),
            GapKind::Unreadable(BackupPart::Sys),
        ),
        (
            "a decimal comma in the base frame",
            &|bk: &Path| {
                let p = bk.join("SYSPAR/MOC.cfg");
                let t = std::fs::read_to_string(&p).unwrap();
                std::fs::write(
                    &p,
                    t.replace("-base_frame_pos_x 1.6", "-base_frame_pos_x 1,6"),
                )
                .unwrap()
            },
            GapKind::BadNumber {
                key: "base_frame_pos_x".into(),
                value: "1,6".into(),
            },
        ),
        (
            "a task the backinfo does not list",
            &|bk: &Path| {
                let p = bk.join("BACKINFO/backinfo.txt");
                let t = std::fs::read_to_string(&p).unwrap();
                std::fs::write(&p, t.replace(">>TASK2: (T_ROB2,,)", ">>TASK9: (T_ROB9,,)")).unwrap()
            },
            GapKind::FolderNotListed {
                folder: "TASK2".into(),
            },
        ),
    ];
    for (what, break_it, expected) in cases {
        let dir = copy_of_sample();
        let bk = dir.path().join("bk");
        break_it(&bk);
        let tasks = discover(std::slice::from_ref(&bk)).unwrap();
        let rob2 = tasks.iter().find(|t| t.label().ends_with("2")).unwrap();
        assert!(
            rob2.gaps.iter().any(|g| g.kind == expected),
            "{what}: {:?}",
            gap_texts(rob2)
        );
    }
    // The bad number is placed at its line and column in MOC.cfg.
    let dir = copy_of_sample();
    let bk = dir.path().join("bk");
    let p = bk.join("SYSPAR/MOC.cfg");
    let t = std::fs::read_to_string(&p).unwrap();
    std::fs::write(
        &p,
        t.replace("-base_frame_pos_x 1.6", "-base_frame_pos_x 1,6"),
    )
    .unwrap();
    let tasks = discover(&[bk]).unwrap();
    let gap = &tasks[1].gaps[0];
    let loc = gap.location.as_ref().unwrap();
    assert_eq!(loc.line, 22);
    assert_eq!(&loc.line_text[loc.col - 1..loc.col + 2], "1,6");
    let e = gap.to_error("T_ROB2").to_string();
    assert!(e.contains("MOC.cfg:22:"), "{e}");
}

/// A backup that lists a module outside itself is refused: a correction
/// in place would otherwise write there.
#[test]
fn a_backup_cannot_name_files_outside_itself() {
    let dir = copy_of_sample();
    let bk = dir.path().join("bk");
    std::fs::write(dir.path().join("outside.mod"), "MODULE x\nENDMODULE\n").unwrap();
    let p = bk.join("BACKINFO/backinfo.txt");
    let t = std::fs::read_to_string(&p).unwrap();
    // The climbing path is joined here so that the repository's own check
    // (tests/layers.rs) does not take this hostile input for a reference.
    let climbing = ["..", "..", "..", "outside.mod"].join("/");
    for listed in [climbing.as_str(), "/etc/passwd", "C:/outside.mod"] {
        std::fs::write(&p, t.replace("PROGMOD/ScanPath.mod", listed)).unwrap();
        let e = discover(std::slice::from_ref(&bk)).unwrap_err().to_string();
        assert!(e.contains("outside"), "{listed}: {e}");
    }
    #[cfg(unix)]
    {
        std::fs::write(&p, &t).unwrap();
        let scan = bk.join("RAPID/TASK1/PROGMOD/ScanPath.mod");
        std::fs::remove_file(&scan).unwrap();
        std::os::unix::fs::symlink(dir.path().join("outside.mod"), &scan).unwrap();
        let e = discover(std::slice::from_ref(&bk)).unwrap_err().to_string();
        assert!(e.contains("outside"), "a link out: {e}");
    }
}

/// A folder whose name starts with a letter of more than one byte is not a
/// task folder, and does not stop the backup being read.
#[test]
fn a_folder_with_a_non_ascii_name_is_read_past() {
    let dir = copy_of_sample();
    let bk = dir.path().join("bk");
    std::fs::create_dir(bk.join("RAPID/Menü")).unwrap();
    std::fs::create_dir(bk.join("RAPID/TASKü")).unwrap();
    let tasks = discover(&[bk]).unwrap();
    assert_eq!(tasks.len(), 3);
}

/// A folder holding `RAPID/` but neither `BACKINFO/` nor `SYSPAR/` (a
/// repository of programs) is not a backup missing its parts: its task
/// folders have no gaps and say which folder was taken for no backup.
/// With an empty `SYSPAR/` beside, it is a backup, and lacks its files.
#[test]
fn rapid_without_backinfo_or_syspar_is_no_backup() {
    let dir = tempfile::tempdir().unwrap();
    let progmod = dir.path().join("RAPID/TASK1/PROGMOD");
    std::fs::create_dir_all(&progmod).unwrap();
    std::fs::write(progmod.join("m.mod"), "MODULE m\nENDMODULE\n").unwrap();
    for named in [
        dir.path().to_path_buf(),
        dir.path().join("RAPID"),
        dir.path().join("RAPID/TASK1"),
    ] {
        let tasks = discover(std::slice::from_ref(&named)).unwrap();
        assert_eq!(tasks.len(), 1, "{}", named.display());
        assert!(tasks[0].gaps.is_empty(), "{:?}", gap_texts(&tasks[0]));
        assert_eq!(tasks[0].name.as_deref(), Some("TASK1"));
        assert_eq!(tasks[0].not_a_backup.as_deref(), Some(dir.path()));
        assert_eq!(file_names(&tasks[0]), ["PROGMOD/m.mod"]);
    }
    std::fs::create_dir(dir.path().join("SYSPAR")).unwrap();
    let tasks = discover(&[dir.path().join("RAPID/TASK1")]).unwrap();
    assert_eq!(tasks[0].not_a_backup, None);
    assert_eq!(gap_texts(&tasks[0]).len(), 3, "{:?}", gap_texts(&tasks[0]));
}
