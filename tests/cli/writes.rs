//! Nothing lost by a write (issue 53, docs/limits.md "Outputs"): every
//! path a run writes is checked before it reads, by the file's identity,
//! against every input and every other output; a file the user did not
//! name (the `--runtime` module, a picture) is replaced only where it is
//! rapidtherm's own, or with `--force`; in place only regular files of one
//! name; a lock refuses a second run on a file; a signal leaves no
//! temporary file. Each case runs the binary as a user would.

use super::gate::copy_tree;
use super::hostile::snapshot;
use super::outputs::{refused, run, stderr};
use proptest::prelude::*;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

fn ok(out: &Output) {
    assert_eq!(out.status.code(), Some(0), "{}", stderr(out));
}

const PROGRAM: &str = "MODULE M\n  CONST robtarget p1:=[[500,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n  PROC main()\n    MoveL p1,v100,fine,tool0;\n  ENDPROC\nENDMODULE\n";

/// A program of `n` targets, each moved to: a correction of it takes a
/// while, long enough to be caught writing.
fn big_program(n: usize) -> String {
    let mut s = String::from("MODULE Big\n");
    for i in 0..n {
        s.push_str(&format!(
            "  CONST robtarget p{i}:=[[{},{},{}],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n",
            480 + i % 40,
            i % 40,
            580 + i % 40
        ));
    }
    s.push_str("  PROC main()\n");
    for i in 0..n {
        s.push_str(&format!("    MoveL p{i},v100,fine,tool0;\n"));
    }
    s.push_str("  ENDPROC\nENDMODULE\n");
    s
}

#[cfg(unix)]
fn symlink(target: impl AsRef<Path>, link: impl AsRef<Path>) {
    std::os::unix::fs::symlink(target, link).unwrap();
}

#[cfg(unix)]
#[test]
fn the_cold_original_is_never_the_output() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("cold.mod"), PROGRAM).unwrap();
    std::fs::create_dir(d.join("sub")).unwrap();
    symlink("cold.mod", d.join("link.mod"));
    symlink(".", d.join("here"));
    let absolute = d.join("cold.mod").display().to_string();
    let before = snapshot(d);
    for out in [
        "cold.mod",
        "./././cold.mod",
        "sub/../cold.mod",
        "here/here/cold.mod",
        "link.mod",
        absolute.as_str(),
    ] {
        let o = run(d, &["correct", "cold.mod", "--at", "120", "-o", out]);
        refused(&o, "that is an input of this run");
        assert_eq!(snapshot(d), before, "-o {out} wrote");
    }
}

#[test]
fn a_plot_never_replaces_an_input() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A program named as a picture would be.
    std::fs::write(d.join("top.svg"), PROGRAM).unwrap();
    let before = snapshot(d);
    let o = run(d, &["correct", "top.svg", "--at", "120", "--plot", "."]);
    refused(&o, "is an input of this run");
    assert_eq!(snapshot(d), before);

    // Measurements named as a diagnosis's picture.
    let sim = run(
        d,
        &[
            "simulate", "--poses", "random:8", "--times", "0,60,120", "--noise", "0.02",
        ],
    );
    ok(&sim);
    std::fs::create_dir(d.join("DIR")).unwrap();
    std::fs::write(d.join("DIR/gap_over_time.svg"), &sim.stdout).unwrap();
    let before = snapshot(d);
    let o = run(d, &["diagnose", "DIR/gap_over_time.svg", "--plot", "DIR"]);
    refused(&o, "is an input of this run");
    assert_eq!(snapshot(d), before);
}

#[test]
fn a_plot_replaces_its_own_pictures_and_nothing_else_unless_forced() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("x.mod"), PROGRAM).unwrap();
    let args = ["correct", "x.mod", "--at", "120", "--plot", "p"];
    ok(&run(d, &args));
    // A second run replaces the first run's pictures.
    ok(&run(d, &args));
    std::fs::write(d.join("p/side.svg"), "my notes\n").unwrap();
    let before = snapshot(d);
    let o = run(d, &args);
    refused(&o, "p/side.svg exists and is not an SVG picture");
    assert!(stderr(&o).contains("--force"), "{}", stderr(&o));
    assert_eq!(snapshot(d), before);
    ok(&run(d, &[&args[..], &["--force"]].concat()));
    assert!(std::fs::read_to_string(d.join("p/side.svg"))
        .unwrap()
        .starts_with("<svg"));
}

#[cfg(unix)]
#[test]
fn the_runtime_module_replaces_only_its_own() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("cell.mod"), PROGRAM).unwrap();
    std::fs::create_dir_all(d.join("warm")).unwrap();
    let args = ["correct", "cell.mod", "--runtime", "-o", "warm/cell.mod"];
    // A module of the user's under the module's name.
    let theirs = "MODULE RtWarm(SYSMODULE)\n  ! the cell's own\nENDMODULE\n";
    std::fs::write(d.join("warm/RtWarm.sys"), theirs).unwrap();
    let before = snapshot(d);
    let o = run(d, &args);
    refused(
        &o,
        "warm/RtWarm.sys exists and is not a module rapidtherm wrote",
    );
    assert_eq!(snapshot(d), before);
    ok(&run(d, &[&args[..], &["--force"]].concat()));
    assert_ne!(
        std::fs::read_to_string(d.join("warm/RtWarm.sys")).unwrap(),
        theirs
    );
    // The module a former run wrote is the run's to replace.
    std::fs::remove_file(d.join("warm/cell.mod")).unwrap();
    ok(&run(d, &args));

    // A link of the module's name out of the folder is not followed, even
    // with --force.
    std::fs::create_dir_all(d.join("elsewhere")).unwrap();
    std::fs::write(d.join("elsewhere/keep.sys"), theirs).unwrap();
    std::fs::create_dir_all(d.join("linked")).unwrap();
    symlink("../elsewhere/keep.sys", d.join("linked/RtWarm.sys"));
    let before = snapshot(d);
    for force in [&[][..], &["--force"]] {
        let o = run(
            d,
            &[
                &["correct", "cell.mod", "--runtime", "-o", "linked/cell.mod"][..],
                force,
            ]
            .concat(),
        );
        refused(&o, "linked/RtWarm.sys is a symbolic link");
        assert_eq!(snapshot(d), before);
    }

    // The program written where its module goes.
    std::fs::create_dir_all(d.join("out")).unwrap();
    let o = run(
        d,
        &["correct", "cell.mod", "--runtime", "-o", "out/RtWarm.sys"],
    );
    refused(&o, "are one file");
    assert!(!d.join("out/RtWarm.sys").exists());
}

#[test]
fn a_module_named_as_a_cells_system_module_leaves_it() {
    let dir = tempfile::tempdir().unwrap();
    let bk = dir.path().join("bk");
    copy_tree(
        &PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("samples/backup_multimove"),
        &bk,
    );
    let before = snapshot(&bk);
    let o = run(
        dir.path(),
        &[
            "correct",
            "bk",
            "--runtime",
            "--in-place",
            "--runtime-module",
            "user",
        ],
    );
    refused(
        &o,
        "SYSMOD/user.sys exists and is not a module rapidtherm wrote",
    );
    assert_eq!(snapshot(&bk), before);
}

/// The run's exit within `limit`, else killed (`None`).
fn wait_for(mut child: Child, limit: Duration) -> Option<Output> {
    let start = Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            return Some(child.wait_with_output().unwrap());
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn spawn(dir: &Path, args: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
        .current_dir(dir)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

#[cfg(unix)]
#[test]
fn in_place_on_a_fifo_is_refused_before_reading() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("x.mod");
    let c = std::ffi::CString::new(fifo.as_os_str().as_encoded_bytes()).unwrap();
    // SAFETY: a path of this test's own folder, NUL-terminated.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
    let child = spawn(
        dir.path(),
        &["correct", "x.mod", "--at", "120", "--in-place"],
    );
    let out = wait_for(child, Duration::from_secs(20)).expect("the run blocked on the FIFO");
    refused(&out, "x.mod: is not a regular file (a FIFO)");
}

#[cfg(unix)]
#[test]
fn in_place_on_a_hard_linked_file_is_refused_and_both_names_kept() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("a.mod"), PROGRAM).unwrap();
    std::fs::hard_link(d.join("a.mod"), d.join("b.mod")).unwrap();
    let before = snapshot(d);
    let o = run(d, &["correct", "a.mod", "--at", "120", "--in-place"]);
    refused(&o, "a.mod: has 2 names (hard links)");
    assert_eq!(snapshot(d), before);
    use std::os::unix::fs::MetadataExt;
    assert_eq!(std::fs::metadata(d.join("b.mod")).unwrap().nlink(), 2);
}

/// Temporary files rapidtherm is writing in `dir`.
fn temporaries(dir: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with(".rapidtherm-"))
        })
        .collect()
}

/// Wait until `child` is writing a temporary file in `dir`; false if it
/// ended first.
fn until_writing(child: &mut Child, dir: &Path) -> bool {
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(120) {
        if !temporaries(dir).is_empty() {
            return true;
        }
        if child.try_wait().unwrap().is_some() {
            return false;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    false
}

#[cfg(unix)]
#[test]
fn a_signal_leaves_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("big.mod"), big_program(150_000)).unwrap();
    for signal in [libc::SIGTERM, libc::SIGINT] {
        let mut child = spawn(d, &["correct", "big.mod", "--at", "120", "-o", "out.mod"]);
        assert!(
            until_writing(&mut child, d),
            "the run ended before it wrote"
        );
        // SAFETY: a process this test started and has not waited for.
        unsafe { libc::kill(child.id() as i32, signal) };
        let out = wait_for(child, Duration::from_secs(60)).expect("the run did not end");
        use std::os::unix::process::ExitStatusExt;
        assert_eq!(out.status.signal(), Some(signal), "{}", stderr(&out));
        assert_eq!(temporaries(d), Vec::<PathBuf>::new());
        assert!(!d.join("out.mod").exists());
    }
}

#[cfg(unix)]
#[test]
fn a_second_run_on_a_file_being_rewritten_is_refused_not_lost() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Another run's lock, held here.
    std::fs::write(d.join("x.mod"), PROGRAM).unwrap();
    let held = std::fs::File::open(d.join("x.mod")).unwrap();
    assert!(fs4::fs_std::FileExt::try_lock_exclusive(&held).unwrap());
    let before = snapshot(d);
    let o = run(d, &["correct", "x.mod", "--at", "60", "--in-place"]);
    refused(&o, "x.mod: another run is writing this file");
    assert_eq!(snapshot(d), before);
    drop(held);
    ok(&run(d, &["correct", "x.mod", "--at", "60", "--in-place"]));

    // Two runs: minute 120, and minute 60 while the first writes.
    let big = big_program(150_000);
    std::fs::write(d.join("big.mod"), &big).unwrap();
    std::fs::write(d.join("same.mod"), &big).unwrap();
    ok(&run(
        d,
        &["correct", "same.mod", "--at", "120", "-o", "expected.mod"],
    ));
    let mut first = spawn(d, &["correct", "big.mod", "--at", "120", "--in-place"]);
    assert!(
        until_writing(&mut first, d),
        "the first run ended before it wrote"
    );
    let second = run(d, &["correct", "big.mod", "--at", "60", "--in-place"]);
    refused(&second, "big.mod: another run is writing this file");
    let first = wait_for(first, Duration::from_secs(120)).expect("the first run did not end");
    ok(&first);
    assert!(
        std::fs::read(d.join("big.mod")).unwrap() == std::fs::read(d.join("expected.mod")).unwrap(),
        "the first run's correction is the file's"
    );
}

/// A spelling of `name` in the test's folder: `.` and `sub/..` parts, a
/// link to the folder, the file itself or a link to it, relative or
/// absolute.
#[cfg(unix)]
fn spelling() -> impl Strategy<Value = (Vec<u8>, bool, bool)> {
    (
        prop::collection::vec(0u8..3, 0..5),
        any::<bool>(),
        any::<bool>(),
    )
}

#[cfg(unix)]
fn spelt(
    dir: &Path,
    name: &str,
    (parts, through_link, absolute): &(Vec<u8>, bool, bool),
) -> String {
    let mut s = if *absolute {
        format!("{}/", dir.display())
    } else {
        String::new()
    };
    for p in parts {
        s.push_str(match p {
            0 => "./",
            1 => "sub/../",
            _ => "here/",
        });
    }
    if *through_link && name == "cold.mod" {
        s.push_str("link.mod");
    } else {
        s.push_str(name);
    }
    s
}

/// Cases per test: 20, or `PROPTEST_CASES`.
fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20)
}

#[cfg(unix)]
proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    /// However the input is spelt as the output (or the plot folder
    /// holding it, or beside the runtime module), the run is refused and
    /// writes nothing; spelt as a new file, it is written there and the
    /// input kept.
    #[test]
    fn no_spelling_of_an_input_is_written(s in spelling(), how in 0usize..3) {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        std::fs::write(d.join("cold.mod"), PROGRAM).unwrap();
        std::fs::create_dir(d.join("sub")).unwrap();
        symlink("cold.mod", d.join("link.mod"));
        symlink(".", d.join("here"));
        let before = snapshot(d);
        let o = match how {
            0 => run(d, &["correct", "cold.mod", "--at", "120", "-o", &spelt(d, "cold.mod", &s)]),
            1 => {
                // The program named as a picture, the folder spelt.
                std::fs::rename(d.join("cold.mod"), d.join("drift.svg")).unwrap();
                let folder = spelt(d, ".", &s);
                let o = run(d, &["correct", "drift.svg", "--at", "120", "--plot", &folder]);
                std::fs::rename(d.join("drift.svg"), d.join("cold.mod")).unwrap();
                o
            }
            _ => run(d, &["correct", "cold.mod", "--at", "120", "--runtime", "-o", &spelt(d, "RtWarm.sys", &s)]),
        };
        prop_assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        prop_assert_eq!(snapshot(d), before.clone(), "{}", stderr(&o));

        let out = spelt(d, "new.mod", &s);
        let o = run(d, &["correct", "cold.mod", "--at", "120", "-o", &out]);
        prop_assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        prop_assert_eq!(std::fs::read(d.join("cold.mod")).unwrap(), PROGRAM.as_bytes());
        prop_assert!(d.join("new.mod").is_file());
    }
}

/// `-o` into a folder that does not exist: refused naming the folder,
/// and no temporary file's name (`nodir/.rapidtherm-FePMJu`) said, since
/// it is no file of the user's (issue 49).
#[test]
fn an_output_in_a_missing_folder_names_the_folder_not_a_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("p.mod"), PROGRAM).unwrap();
    let out = run(
        dir.path(),
        &["correct", "--at", "120", "-o", "nodir/x.mod", "p.mod"],
    );
    refused(&out, "nodir");
    assert!(!stderr(&out).contains(".rapidtherm-"), "{}", stderr(&out));
    assert!(!dir.path().join("nodir").exists());
}
