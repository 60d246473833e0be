//! A program named as a RobotStudio user names it, bare from its own
//! folder (`rapidtherm targets Cell.pgf`), is read as `./Cell.pgf` is
//! (issue 49: it was `error: : No such file or directory`).

use std::path::Path;
use std::process::{Command, Output};

fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("runs")
}

#[test]
fn a_program_file_named_bare_is_read_from_the_current_folder() {
    let dir = tempfile::tempdir().expect("temp dir");
    let sample = concat!(env!("CARGO_MANIFEST_DIR"), "/samples/fixtures.mod");
    std::fs::copy(sample, dir.path().join("Cell.mod")).expect("copied");
    std::fs::write(
        dir.path().join("Cell.pgf"),
        "<?xml version=\"1.0\" encoding=\"ISO-8859-1\" ?>\r\n<Program>\r\n    <Module>Cell.mod</Module>\r\n</Program>\r\n",
    )
    .expect("written");
    for (bare, dotted) in [
        (vec!["targets", "Cell.pgf"], vec!["targets", "./Cell.pgf"]),
        (vec!["schedule", "Cell.pgf"], vec!["schedule", "./Cell.pgf"]),
        (
            vec!["diff", "Cell.pgf", "Cell.pgf"],
            vec!["diff", "./Cell.pgf", "./Cell.pgf"],
        ),
        (
            vec!["correct", "--at", "120", "-o", "bare.mod", "Cell.pgf"],
            vec!["correct", "--at", "120", "-o", "dotted.mod", "./Cell.pgf"],
        ),
    ] {
        let (a, b) = (run(dir.path(), &bare), run(dir.path(), &dotted));
        let said = String::from_utf8_lossy(&a.stderr);
        assert_eq!(a.status.code(), b.status.code(), "{bare:?}: {said}");
        assert!(a.status.code().is_some_and(|c| c < 2), "{bare:?}: {said}");
        assert_eq!(
            String::from_utf8_lossy(&a.stdout),
            String::from_utf8_lossy(&b.stdout),
            "{bare:?}"
        );
    }
    let corrected = |name: &str| std::fs::read(dir.path().join(name)).expect("written");
    assert_eq!(corrected("bare.mod"), corrected("dotted.mod"));
}
