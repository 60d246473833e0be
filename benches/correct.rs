//! Speed and memory of the main job.
//!
//! - criterion: correcting the CAM sample (5,252 targets) in memory, and
//!   one target through the warm robot;
//! - end to end: `rapidtherm correct --at`, `correct --start`,
//!   `correct --runtime` and `rapidtherm targets` on generated programs of 1,000,000 targets in
//!   each of the three shapes large programs come in (CAM inline moves,
//!   RobotStudio's declared targets, one array walked by a FOR loop;
//!   written to a temporary folder, never committed), side by side with
//!   `cp` of the same file (the floor), three rounds, medians, the load
//!   average and each run's peak resident memory on stderr. Set
//!   `RAPIDTHERM_BENCH_TARGETS`, `RAPIDTHERM_BENCH_RUNS` and
//!   `RAPIDTHERM_BENCH_SHAPES` (`cam,declared,array`) to change them.
//!   Set `RAPIDTHERM_BENCH_REFERENCE` to another build of rapidtherm (an
//!   earlier commit's `target/release/rapidtherm`) to run its `correct
//!   --at 120` and `targets` in the same rounds, beside this build's, and
//!   print this build's time over the reference's (the median of the
//!   rounds' ratios): a change is judged against the code before it under
//!   the same load, not against a number from another day.

use criterion::{Criterion, Throughput};
use rapidtherm::correct::{correct, Options, When};
use rapidtherm::model::warm::{Moment, WarmRobot};
use rapidtherm::model::Model;
use rapidtherm::rapid;
use rapidtherm::robot::Robot;
use std::hint::black_box;
use std::io::Write;
use std::process::Command;
use std::time::{Duration, Instant};

#[path = "../examples/gen_shapes.rs"]
#[allow(dead_code)]
mod gen_shapes;
use gen_shapes::Shape;

fn options() -> Options {
    Options::new(When::At(Moment::Minute(120.0)))
}

fn bench_sample(c: &mut Criterion) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/samples/cam_contour.mod");
    let bytes = std::fs::read(path).expect("CAM sample");
    let program = rapid::parse("cam_contour.mod", &bytes).expect("parses");
    let warm = WarmRobot::new(Robot::irb140(), &Model::default(), 120.0).expect("model");
    let mut group = c.benchmark_group("correct");
    group.throughput(Throughput::Elements(program.targets().len() as u64));
    group.bench_function("cam_sample_5252_targets", |b| {
        b.iter(|| correct(&program, &warm, &options(), &mut |_, _| {}).expect("corrects"))
    });
    group.finish();
}

/// The children's resource use of one run: wall time, CPU time (user
/// and system) and peak resident memory (kB), each child's own (waited
/// for with `wait4`, so that one large run does not hide the others'
/// peaks, as `RUSAGE_CHILDREN` would).
struct Ran {
    wall: Duration,
    cpu: Duration,
    peak_kb: i64,
}

/// Run `program args`, its standard output to `/dev/null`, and measure it.
// The child is reaped by `wait4` (for its own resource use), which
// clippy does not see.
#[allow(clippy::zombie_processes)]
fn run(program: &str, args: &[&std::ffi::OsStr]) -> Ran {
    // The outputs of the runs before are written to disk first: a run
    // otherwise pays for the write-back of the last one's hundred
    // megabytes (`cp` of a cached file took 0.03 to 0.36 s by that alone).
    // SAFETY: sync takes no arguments and cannot fail.
    unsafe { libc::sync() };
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

fn median<T: PartialOrd + Copy>(mut v: Vec<T>) -> T {
    v.sort_by(|a, b| a.partial_cmp(b).expect("no NaN"));
    v[v.len() / 2]
}

/// The three shapes of a million targets (`examples/gen_shapes.rs`), each
/// beside `cp` of the same file: `correct --at 120 -o OUT`, `correct
/// --start 0 -o OUT`, `correct --runtime -o OUT` (the controller module
/// written beside OUT) and `targets` (to `/dev/null`), the five run in turn
/// (`RAPIDTHERM_BENCH_RUNS` rounds, 3 by default) so that all see the same
/// load; medians of the times and of the per-round ratios, each command's
/// median peak memory, the load average.
fn end_to_end() {
    let n: usize = std::env::var("RAPIDTHERM_BENCH_TARGETS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let rounds: usize = std::env::var("RAPIDTHERM_BENCH_RUNS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3);
    let shapes: Vec<Shape> = match std::env::var("RAPIDTHERM_BENCH_SHAPES") {
        Ok(list) => list.split(',').filter_map(Shape::named).collect(),
        Err(_) => Shape::ALL.to_vec(),
    };
    let bin = env!("CARGO_BIN_EXE_rapidtherm");
    let reference = std::env::var("RAPIDTHERM_BENCH_REFERENCE").ok();
    for shape in shapes {
        let dir = tempfile::tempdir().expect("temp dir");
        let input = dir.path().join(format!("{}.mod", shape.name()));
        {
            let file = std::fs::File::create(&input).expect("temp file");
            let mut w = std::io::BufWriter::new(file);
            shape.write(&mut w, n).expect("written");
            w.flush().expect("written");
        }
        let size_mb = std::fs::metadata(&input).map(|m| m.len()).unwrap_or(0) as f64 / 1e6;
        let out = dir.path().join("out.mod");
        let copy = dir.path().join("copy.mod");
        let os = |s: &'static str| std::ffi::OsStr::new(s);
        let (inp, outp, cpp) = (input.as_os_str(), out.as_os_str(), copy.as_os_str());
        let mut all: [Vec<Ran>; 5] = Default::default();
        let (mut at_cp, mut start_at, mut rt_cp) = (Vec::new(), Vec::new(), Vec::new());
        let mut against = AgainstReference::default();
        for _ in 0..rounds {
            let cp = run("cp", &[inp, cpp]);
            let at = run(
                bin,
                &[os("correct"), os("--at"), os("120"), os("-o"), outp, inp],
            );
            let start = run(
                bin,
                &[os("correct"), os("--start"), os("0"), os("-o"), outp, inp],
            );
            let runtime = run(bin, &[os("correct"), os("--runtime"), os("-o"), outp, inp]);
            let list = run(bin, &[os("targets"), inp]);
            if let Some(old) = reference.as_deref() {
                let old_at = run(
                    old,
                    &[os("correct"), os("--at"), os("120"), os("-o"), outp, inp],
                );
                let old_list = run(old, &[os("targets"), inp]);
                against.push(&at, &old_at, &list, &old_list);
            }
            at_cp.push(at.wall.as_secs_f64() / cp.wall.as_secs_f64());
            start_at.push(start.wall.as_secs_f64() / at.wall.as_secs_f64());
            rt_cp.push(runtime.wall.as_secs_f64() / cp.wall.as_secs_f64());
            for (k, r) in [cp, at, start, runtime, list].into_iter().enumerate() {
                all[k].push(r);
            }
        }
        let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
        let [cp, at, start, runtime, list] = all.map(|runs| {
            (
                median(runs.iter().map(|r| r.wall).collect()).as_secs_f64(),
                median(runs.iter().map(|r| r.cpu).collect()).as_secs_f64(),
                median(runs.iter().map(|r| r.peak_kb).collect()) as f64 * 1024.0 / 1e6,
            )
        });
        eprintln!(
            "{} shape, {n} targets ({size_mb:.1} MB, CRLF), medians of {rounds}, load average {}:\n  cp {:.3} s (peak {:.0} MB)\n  correct --at 120 -o OUT {:.2} s = {:.1} x cp (median of the rounds' ratios), CPU {:.2} s, peak {:.0} MB = {:.2} x the file\n  correct --start 0 -o OUT {:.2} s = {:.2} x --at (median of the rounds' ratios), CPU {:.2} s, peak {:.0} MB = {:.2} x the file\n  correct --runtime -o OUT {:.2} s = {:.1} x cp (median of the rounds' ratios), CPU {:.2} s, peak {:.0} MB = {:.2} x the file\n  targets {:.2} s = {:.1} MB/s, CPU {:.2} s, peak {:.0} MB",
            shape.name(),
            load.split_whitespace().take(3).collect::<Vec<_>>().join(" "),
            cp.0,
            cp.2,
            at.0,
            median(at_cp),
            at.1,
            at.2,
            at.2 / size_mb,
            start.0,
            median(start_at),
            start.1,
            start.2,
            start.2 / size_mb,
            runtime.0,
            median(rt_cp),
            runtime.1,
            runtime.2,
            runtime.2 / size_mb,
            list.0,
            size_mb / list.0,
            list.1,
            list.2,
        );
        if let Some(old) = reference.as_deref() {
            against.print(shape.name(), old);
        }
        black_box(&out);
    }
}

/// This build's `correct --at 120` and `targets` over the reference
/// build's, round by round (each ratio taken within one round, where both
/// saw the same load).
#[derive(Default)]
struct AgainstReference {
    at_wall: Vec<f64>,
    at_cpu: Vec<f64>,
    targets_wall: Vec<f64>,
    targets_cpu: Vec<f64>,
}

impl AgainstReference {
    fn push(&mut self, at: &Ran, old_at: &Ran, list: &Ran, old_list: &Ran) {
        let ratio = |a: Duration, b: Duration| a.as_secs_f64() / b.as_secs_f64();
        self.at_wall.push(ratio(at.wall, old_at.wall));
        self.at_cpu.push(ratio(at.cpu, old_at.cpu));
        self.targets_wall.push(ratio(list.wall, old_list.wall));
        self.targets_cpu.push(ratio(list.cpu, old_list.cpu));
    }

    fn print(self, shape: &str, old: &str) {
        eprintln!(
            "{shape} shape, this build over the reference ({old}), medians of the rounds' ratios:\n  correct --at 120 -o OUT: wall {:.3}, CPU {:.3}\n  targets: wall {:.3}, CPU {:.3}",
            median(self.at_wall),
            median(self.at_cpu),
            median(self.targets_wall),
            median(self.targets_cpu),
        );
    }
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    bench_sample(&mut c);
    c.final_summary();
    end_to_end();
}
