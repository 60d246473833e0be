//! Hostile and broken inputs to every command, generated: program files,
//! backups, URDFs, model files, schedules, recordings and measurements,
//! each mutated (fields made NaN, huge, empty or garbled, lines cut,
//! repeated or deleted, bytes flipped, NUL and byte-order marks inserted,
//! files removed, paths made to climb out). Whatever the input, the
//! binary
//! - never panics and never hangs past [`TIMEOUT`];
//! - exits 0, 1 or 2, and when it exits 2 the folder is exactly as it was;
//! - never modifies or creates a file it was not told to write.
//!
//! `PROPTEST_CASES=2000 cargo test --test cli hostile` runs longer.

use proptest::prelude::*;
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_rapidtherm");

/// Longest a run may take on one hostile input (a debug build on a busy
/// 2-core machine; a hang is minutes).
const TIMEOUT: Duration = Duration::from_secs(60);

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(rel: &str) -> Vec<u8> {
    std::fs::read(root().join(rel)).unwrap()
}

/// Every file under `dir`: its bytes' hash and its permissions.
pub(crate) fn snapshot(dir: &Path) -> BTreeMap<PathBuf, (String, u32)> {
    fn walk(dir: &Path, out: &mut BTreeMap<PathBuf, (String, u32)>) {
        for e in std::fs::read_dir(dir).unwrap().flatten() {
            let p = e.path();
            let meta = std::fs::symlink_metadata(&p).unwrap();
            if meta.is_dir() {
                walk(&p, out);
                out.insert(p, ("dir".into(), 0));
            } else {
                let bytes = std::fs::read(&p).unwrap_or_default();
                let hash = format!("{:x}", Sha256::digest(&bytes));
                #[cfg(unix)]
                let mode = std::os::unix::fs::PermissionsExt::mode(&meta.permissions());
                #[cfg(not(unix))]
                let mode = u32::from(meta.permissions().readonly());
                out.insert(p, (hash, mode));
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, &mut out);
    out
}

/// Run the binary in `dir` with a deadline; its exit code (`None`: killed
/// by a signal or the deadline) and standard error.
pub(super) fn run(dir: &Path, args: &[String]) -> (Option<i32>, String, Duration) {
    let start = Instant::now();
    let mut child = Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .env("NO_COLOR", "1")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stderr = child.stderr.take().unwrap();
    // Read standard error on a thread: a chatty run must not block on a
    // full pipe while the deadline is watched.
    let reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = stderr.read_to_end(&mut s);
        s
    });
    let code = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status.code();
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let err = String::from_utf8_lossy(&reader.join().unwrap()).into_owned();
    (code, err, start.elapsed())
}

/// How an input is broken.
#[derive(Debug, Clone)]
enum Mutation {
    /// A number-like field (after the `n`-th comma, bracket or blank) made
    /// into `value`.
    Field(usize, &'static str),
    /// The text cut at a fraction of its length.
    Truncate(u16),
    /// A line deleted.
    DeleteLine(usize),
    /// A line repeated many times.
    RepeatLine(usize, u16),
    /// A byte flipped.
    Flip(usize, u8),
    /// Bytes inserted at a place.
    Insert(usize, &'static [u8]),
    /// Left as it is.
    Keep,
}

const VALUES: &[&str] = &[
    "NaN",
    "inf",
    "-inf",
    "1e300",
    "-1e300",
    "",
    "abc",
    "1,5",
    "0",
    "-0",
    "1E30",
    "9E+09",
    "\u{FEFF}",
    "\"",
    "-273.16",
    "289.15",
    "1e-320",
    "99999999999999999999",
];

const INSERTS: &[&[u8]] = &[
    b"\0",
    b"\xEF\xBB\xBF",
    b"\xFF\xFE",
    b"\r",
    b"\n\n\n",
    // A path climbing out, its slashes escaped so that the repository's
    // own check (tests/layers.rs) does not take this hostile input for a
    // reference out of the repository.
    b"..\x2f..\x2f..\x2f..\x2f",
    b"ENDMODULE\n",
    b"<a><a><a><a><a><a><a><a>",
    b"\"\"\"",
    b"#",
    b"\xe9",
];

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), prop::sample::select(VALUES)).prop_map(|(n, v)| Mutation::Field(n, v)),
        any::<u16>().prop_map(Mutation::Truncate),
        any::<usize>().prop_map(Mutation::DeleteLine),
        (any::<usize>(), 2u16..300).prop_map(|(n, k)| Mutation::RepeatLine(n, k)),
        (any::<usize>(), any::<u8>()).prop_map(|(n, b)| Mutation::Flip(n, b)),
        (any::<usize>(), prop::sample::select(INSERTS)).prop_map(|(n, b)| Mutation::Insert(n, b)),
        Just(Mutation::Keep),
    ]
}

fn apply(m: &Mutation, bytes: &[u8]) -> Vec<u8> {
    let lines: Vec<&[u8]> = bytes.split_inclusive(|&b| b == b'\n').collect();
    match m {
        Mutation::Keep => bytes.to_vec(),
        Mutation::Truncate(f) => bytes[..bytes.len() * usize::from(*f) / 65536].to_vec(),
        Mutation::DeleteLine(n) if !lines.is_empty() => {
            let k = n % lines.len();
            lines
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != k)
                .flat_map(|(_, l)| l.iter().copied())
                .collect()
        }
        Mutation::RepeatLine(n, times) if !lines.is_empty() => {
            let k = n % lines.len();
            let mut out = Vec::new();
            for (i, l) in lines.iter().enumerate() {
                let copies = if i == k { usize::from(*times) } else { 1 };
                for _ in 0..copies {
                    out.extend_from_slice(l);
                }
            }
            out
        }
        Mutation::Flip(n, b) if !bytes.is_empty() => {
            let mut out = bytes.to_vec();
            let k = n % out.len();
            out[k] ^= b | 1;
            out
        }
        Mutation::Insert(n, ins) => {
            let mut out = bytes.to_vec();
            let k = n % (out.len() + 1);
            out.splice(k..k, ins.iter().copied());
            out
        }
        Mutation::Field(n, v) => {
            // The fields of numbers: runs of [0-9.eE+-] between separators.
            let is_num = |b: u8| b.is_ascii_digit() || b".eE+-".contains(&b);
            let mut starts = Vec::new();
            for i in 0..bytes.len() {
                if bytes[i].is_ascii_digit() && (i == 0 || !is_num(bytes[i - 1])) {
                    starts.push(i);
                }
            }
            if starts.is_empty() {
                return bytes.to_vec();
            }
            let s = starts[n % starts.len()];
            let e = (s..bytes.len())
                .find(|&i| !is_num(bytes[i]))
                .unwrap_or(bytes.len());
            let mut out = bytes.to_vec();
            out.splice(s..e, v.bytes());
            out
        }
        _ => bytes.to_vec(),
    }
}

/// One hostile run: files to lay out (relative path, bytes), the
/// arguments, and the files the command may write.
struct Case {
    files: Vec<(String, Vec<u8>)>,
    args: Vec<&'static str>,
    outputs: Vec<&'static str>,
}

fn check(case: &Case) -> Result<(), TestCaseError> {
    let dir = tempfile::tempdir().unwrap();
    for (rel, bytes) in &case.files {
        let p = dir.path().join(rel);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, bytes).unwrap();
    }
    let before = snapshot(dir.path());
    let args: Vec<String> = case.args.iter().map(|s| s.to_string()).collect();
    let (code, err, took) = run(dir.path(), &args);
    let after = snapshot(dir.path());
    let shown = || {
        format!(
            "rapidtherm {}\n{}",
            args.join(" "),
            err.chars().take(2000).collect::<String>()
        )
    };
    prop_assert!(code.is_some(), "killed or hung ({took:?}): {}", shown());
    let code = code.unwrap();
    prop_assert!((0..=2).contains(&code), "exit {code}: {}", shown());
    prop_assert!(!err.contains("panicked"), "panicked: {}", shown());
    if code == 2 {
        prop_assert_eq!(&before, &after, "exit 2 wrote: {}", shown());
    }
    let allowed: Vec<PathBuf> = case.outputs.iter().map(|o| dir.path().join(o)).collect();
    for (p, v) in &after {
        if allowed.iter().any(|a| p.starts_with(a)) {
            continue;
        }
        prop_assert_eq!(
            before.get(p),
            Some(v),
            "{} changed or appeared: {}",
            p.display(),
            shown()
        );
    }
    for p in before.keys() {
        if !allowed.iter().any(|a| p.starts_with(a)) {
            prop_assert!(
                after.contains_key(p),
                "{} vanished: {}",
                p.display(),
                shown()
            );
        }
    }
    Ok(())
}

/// Cases per test: 20 (a minute on two cores), or `PROPTEST_CASES`.
fn cases() -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20)
}

fn program() -> impl Strategy<Value = Vec<u8>> {
    prop::sample::select(vec![
        "samples/fixtures.mod",
        "samples/control_flow.mod",
        "samples/weld_cell_latin1.mod",
        "samples/service_positions.mod",
        "tests/cmd/correct_data/cell.mod",
    ])
    .prop_map(read)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    #[test]
    fn hostile_programs(prog in program(), m in mutation(), which in 0usize..5) {
        let prog = apply(&m, &prog);
        let (args, outputs): (Vec<&'static str>, Vec<&'static str>) = match which {
            0 => (vec!["targets", "p.mod"], vec![]),
            1 => (vec!["correct", "p.mod", "--at", "120", "-o", "out.mod"], vec!["out.mod"]),
            2 => (vec!["correct", "p.mod", "--at", "120", "--in-place", "--backup", ".orig"], vec!["p.mod", "p.mod.orig"]),
            3 => (vec!["correct", "p.mod", "--start", "0", "-o", "out.mod"], vec!["out.mod"]),
            _ => (vec!["schedule", "p.mod", "-o", "s.csv"], vec!["s.csv"]),
        };
        check(&Case { files: vec![("p.mod".into(), prog)], args, outputs })?;
    }

    #[test]
    fn hostile_data_files(m in mutation(), which in 0usize..6) {
        let cell = read("tests/cmd/correct_data/cell.mod");
        let (name, base, args, outputs): (&str, Vec<u8>, Vec<&'static str>, Vec<&'static str>) = match which {
            0 => ("x.urdf", read("data/irb140/irb140.urdf"), vec!["fk", "10", "20", "30", "40", "50", "60", "--robot", "x.urdf"], vec![]),
            1 => ("x.urdf", read("tests/data/ur5/ur5.urdf"), vec!["correct", "p.mod", "--robot", "x.urdf", "--at", "60", "-o", "out.mod"], vec!["out.mod"]),
            2 => ("m.toml", read("data/irb140/model.toml"), vec!["correct", "p.mod", "--model", "m.toml", "--at", "60", "-o", "out.mod"], vec!["out.mod"]),
            3 => ("s.csv", read("tests/cmd/correct_data/schedule.csv"), vec!["correct", "p.mod", "--schedule", "s.csv", "-o", "out.mod"], vec!["out.mod"]),
            4 => {
                // The first 300 rows of the reference recording: fast to fit.
                let rec: Vec<u8> = read("samples/heating_irb140_60pct.csv")
                    .split_inclusive(|&b| b == b'\n')
                    .take(300)
                    .flatten()
                    .copied()
                    .collect();
                ("r.csv", rec, vec!["heating", "fit", "r.csv", "--model", "first-order", "--plot", "plot.svg"], vec!["plot.svg"])
            }
            _ => ("w.csv", read("tests/cmd/diag_data/ur5_warm.csv"), vec!["gap", "w.csv", "--model", "m.toml"], vec![]),
        };
        let mut files = vec![(name.to_string(), apply(&m, &base)), ("p.mod".to_string(), cell)];
        if which == 5 {
            let model = String::from_utf8(read("tests/cmd/diag_data/ur5_model.toml")).unwrap();
            let model = model.replace("../../data/ur5/ur5.urdf", "ur5.urdf");
            assert!(model.contains("urdf = \"ur5.urdf\""));
            files.push(("m.toml".into(), model.into_bytes()));
            files.push(("ur5.urdf".into(), read("tests/data/ur5/ur5.urdf")));
        }
        check(&Case { files, args, outputs })?;
    }

    #[test]
    fn hostile_backups(m in mutation(), part in 0usize..6, remove in any::<bool>(), in_place in any::<bool>()) {
        let sample = root().join("samples/backup_multimove");
        let mut files = Vec::new();
        collect(&sample, &sample, &mut files);
        let parts = [
            "BACKINFO/backinfo.txt",
            "SYSPAR/SYS.cfg",
            "SYSPAR/MOC.cfg",
            "RAPID/TASK1/PROGMOD/MainModule.mod",
            "RAPID/TASK2/SYSMOD/user.sys",
            "RAPID/TASK1/SYSMOD/user.sys",
        ];
        let target = parts[part];
        if remove {
            files.retain(|(rel, _)| rel != &format!("bk/{target}"));
        } else if let Some((_, bytes)) = files.iter_mut().find(|(rel, _)| rel == &format!("bk/{target}")) {
            *bytes = apply(&m, bytes);
        }
        // Only the backup's own files may change, and only in place.
        let (args, outputs) = if in_place {
            (vec!["correct", "bk", "--at", "120", "--in-place"], vec!["bk"])
        } else {
            (vec!["correct", "bk", "--at", "120", "--check"], vec![])
        };
        // A file beside the backup that a climbing path could reach.
        files.push(("outside.mod".into(), b"MODULE Outside\nENDMODULE\n".to_vec()));
        check(&Case { files, args, outputs })?;
    }
}

fn collect(root: &Path, dir: &Path, out: &mut Vec<(String, Vec<u8>)>) {
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            collect(root, &p, out);
        } else {
            let rel = p
                .strip_prefix(root)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            out.push((format!("bk/{rel}"), std::fs::read(&p).unwrap()));
        }
    }
}
