//! Speed and memory of the diagnosis.
//!
//! - criterion: the diagnosis of 10,000 measurements in memory (100 poses
//!   × 100 times, one effect), all candidates scored with cross-validation
//!   and forward selection;
//! - end to end: `rapidtherm diagnose` beside `rapidtherm gap` of the
//!   same file, in turn in the same rounds (so that both see the same
//!   load), on sets generated with `rapidtherm simulate` (50 poses visited
//!   again and again as the arm warms, arm bending; 2,000 and 10,000 rows
//!   by default, written to a temporary folder, never committed): medians
//!   of the times and of the rounds' ratios, each command's median peak
//!   resident memory against the CSV's size. Set
//!   `RAPIDTHERM_BENCH_ROWS` (`2000,10000,100000`),
//!   `RAPIDTHERM_BENCH_RUNS` (3 rounds by default) and
//!   `RAPIDTHERM_BENCH_TEMPS=measured` (the motor temperatures written as
//!   columns instead of left to the heating profile) to change them,
//!   `RAPIDTHERM_BENCH_ROBOT` (a robot name or a URDF file, given as
//!   `--robot` to `simulate`, `gap` and `diagnose`; the IRB 140 by
//!   default) for another arm, and `RAPIDTHERM_BENCH_CRITERION=0` to skip
//!   the in-memory part.

use criterion::Criterion;
use rapidtherm::diagnose::measurements::IRB140_LIMITS_DEG;
use rapidtherm::diagnose::simulate::{random_poses, simulate, SimSpec};
use rapidtherm::diagnose::{diagnose, prepare, DiagnoseOptions};
use rapidtherm::model::Model;
use rapidtherm::model::{Base, Effect, EffectKind};
use rapidtherm::thermal::default_profile;
use std::ffi::OsStr;
use std::hint::black_box;
use std::process::Command;
use std::time::{Duration, Instant};

fn bench_in_memory(c: &mut Criterion) {
    let spec = SimSpec {
        base: Base::default(),
        poses: random_poses(100, &IRB140_LIMITS_DEG, 1),
        times: (0..100).map(|i| i as f64 * 1.8).collect(),
        effects: vec![Effect::with_defaults(EffectKind::ArmBending)],
        noise_mm: 0.01,
        orientation: false,
        measured_temps: false,
        seed: 1,
    };
    let meas = simulate(&spec, &default_profile()).expect("simulate");
    let prepared = prepare(&meas, &Model::default(), false).expect("prepare");
    let mut group = c.benchmark_group("diagnose");
    group.sample_size(10);
    group.bench_function("10000 rows, 8 candidates, 4-fold CV", |b| {
        b.iter(|| diagnose(black_box(&prepared), &DiagnoseOptions::default()).expect("diagnose"))
    });
    group.finish();
}

/// One run's wall time, CPU time (user and system) and peak resident
/// memory (kB), the child's own (waited for with `wait4`).
struct Ran {
    wall: Duration,
    cpu: Duration,
    peak_kb: i64,
}

/// Run `program args`, its standard output to `/dev/null`, and measure it.
// The child is reaped by `wait4` (for its own resource use), which
// clippy does not see.
#[allow(clippy::zombie_processes)]
fn run(program: &str, args: &[&OsStr]) -> Ran {
    let t = Instant::now();
    let child = Command::new(program)
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("spawn");
    let pid = child.id() as libc::pid_t;
    // The child's messages are read before it is waited for (a full pipe
    // would stop it).
    let mut stderr = String::new();
    if let Some(mut e) = child.stderr {
        let _ = std::io::Read::read_to_string(&mut e, &mut stderr);
    }
    let mut status = 0;
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: waits for our own child and writes into structs we own.
    let got = unsafe { libc::wait4(pid, &mut status, 0, &mut usage) };
    let wall = t.elapsed();
    assert_eq!(got, pid, "wait4");
    assert!(
        libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0,
        "{program} {args:?}: {stderr}"
    );
    let tv = |v: libc::timeval| Duration::new(v.tv_sec as u64, v.tv_usec as u32 * 1000);
    Ran {
        wall,
        cpu: tv(usage.ru_utime) + tv(usage.ru_stime),
        peak_kb: usage.ru_maxrss,
    }
}

/// The arguments as the `&OsStr`s [`run`] takes.
fn refs(args: &[std::ffi::OsString]) -> Vec<&OsStr> {
    args.iter().map(|a| a.as_os_str()).collect()
}

fn median<T: PartialOrd + Copy>(mut v: Vec<T>) -> T {
    v.sort_by(|a, b| a.partial_cmp(b).expect("no NaN"));
    v[v.len() / 2]
}

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

/// `diagnose` beside `gap` of each generated set, in turn, medians.
fn end_to_end() {
    let sizes: Vec<usize> = std::env::var("RAPIDTHERM_BENCH_ROWS")
        .unwrap_or_else(|_| "2000,10000".into())
        .split(',')
        .filter_map(|s| s.trim().parse().ok())
        .collect();
    let rounds: usize = env_or("RAPIDTHERM_BENCH_RUNS", 3);
    let temps = std::env::var("RAPIDTHERM_BENCH_TEMPS").unwrap_or_else(|_| "profile".into());
    let robot = std::env::var("RAPIDTHERM_BENCH_ROBOT").ok();
    // `--robot R` for each command where an arm is asked for.
    let robot_args: Vec<&OsStr> = match &robot {
        Some(r) => vec![OsStr::new("--robot"), OsStr::new(r.as_str())],
        None => Vec::new(),
    };
    let with_robot = |args: &[&'static OsStr], rest: &[&OsStr]| -> Vec<std::ffi::OsString> {
        args.iter()
            .chain(robot_args.iter())
            .chain(rest.iter())
            .map(|a| a.to_os_string())
            .collect()
    };
    let bin = env!("CARGO_BIN_EXE_rapidtherm");
    let os = OsStr::new;
    for rows in sizes {
        // 50 poses at every minute of the session: the rows' count over
        // the poses is the number of visits.
        let visits = (rows / 50).max(2);
        let dir = tempfile::tempdir().expect("temp dir");
        let data = dir.path().join(format!("sim_{rows}.csv"));
        let times = format!("0:{}:1", visits - 1);
        let sim = with_robot(
            &[os("simulate")],
            &[
                os("--poses"),
                os("random:50"),
                os("--times"),
                os(&times),
                os("--effect"),
                os("arm-bending"),
                os("--temps"),
                os(&temps),
                os("-o"),
                data.as_os_str(),
            ],
        );
        let made = run(bin, &refs(&sim));
        black_box(made.wall);
        let size_mb = std::fs::metadata(&data).map(|m| m.len()).unwrap_or(0) as f64 / 1e6;
        let (mut gaps, mut diags, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..rounds {
            let g = run(
                bin,
                &refs(&with_robot(&[os("gap")], &[os("-q"), data.as_os_str()])),
            );
            let d = run(
                bin,
                &refs(&with_robot(
                    &[os("diagnose")],
                    &[os("-q"), data.as_os_str()],
                )),
            );
            ratios.push(d.wall.as_secs_f64() / g.wall.as_secs_f64());
            gaps.push(g);
            diags.push(d);
        }
        let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
        let summary = |runs: &[Ran]| {
            (
                median(runs.iter().map(|r| r.wall).collect()).as_secs_f64(),
                median(runs.iter().map(|r| r.cpu).collect()).as_secs_f64(),
                median(runs.iter().map(|r| r.peak_kb).collect()) as f64 * 1024.0 / 1e6,
            )
        };
        let (g, d) = (summary(&gaps), summary(&diags));
        eprintln!(
            "{} arm, {visits} visits of 50 poses ({} rows, {size_mb:.2} MB, temperatures {temps}), medians of {rounds}, load average {}:\n  gap {:.3} s, CPU {:.3} s, peak {:.0} MB\n  diagnose {:.2} s = {:.0} x gap (median of the rounds' ratios), CPU {:.2} s, peak {:.0} MB = {:.1} x the file",
            robot.as_deref().unwrap_or("IRB 140"),
            visits * 50,
            load.split_whitespace().take(3).collect::<Vec<_>>().join(" "),
            g.0,
            g.1,
            g.2,
            d.0,
            median(ratios),
            d.1,
            d.2,
            d.2 / size_mb.max(1e-9),
        );
    }
}

fn main() {
    if env_or("RAPIDTHERM_BENCH_CRITERION", 1) != 0 {
        let mut c = Criterion::default().configure_from_args();
        bench_in_memory(&mut c);
        c.final_summary();
    }
    end_to_end();
}
