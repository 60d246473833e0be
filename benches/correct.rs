//! Speed and memory of the main job.
//!
//! - criterion: correcting the CAM sample (5,252 targets) in memory, and
//!   one target through the warm robot;
//! - end to end: `rapidtherm correct` and `rapidtherm targets` on a
//!   generated program of 1,000,000 inline targets (117 MB, written to a
//!   temporary folder, never committed), side by side with `cp` of the
//!   same file (the floor), three runs each, medians, the load average and
//!   the children's peak resident memory on stderr.
//!   Set `RAPIDTHERM_BENCH_TARGETS` to change the count.

use criterion::{Criterion, Throughput};
use rapidtherm::correct::{correct, Options, When};
use rapidtherm::model::warm::{Moment, WarmRobot};
use rapidtherm::model::Model;
use rapidtherm::rapid;
use rapidtherm::robot::Robot;
use std::hint::black_box;
use std::io::Write;
use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

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

/// A CAM-style program as the issue describes it: `n` inline MoveL
/// targets with a spindle tool and a work object, CRLF line ends, all
/// reachable, robconf consistent with the pose (117 MB for a million).
fn write_program(path: &Path, n: usize) {
    let file = std::fs::File::create(path).expect("temp file");
    let mut w = std::io::BufWriter::new(file);
    let _ = write!(w, "MODULE Big\r\n");
    let _ = write!(
        w,
        "  PERS tooldata tSpindle:=[TRUE,[[0,0,150],[1,0,0,0]],[2,[0,0,60],[1,0,0,0],0,0,0]];\r\n"
    );
    let _ = write!(
        w,
        "  PERS wobjdata wPlate:=[FALSE,TRUE,\"\",[[0,0,0],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];\r\n"
    );
    let _ = write!(w, "  PROC main()\r\n");
    // A deterministic zigzag over a 300 x 300 mm field.
    for i in 0..n {
        let u = (i % 1000) as f64 / 1000.0;
        let v = (i / 1000 % 1000) as f64 / 1000.0;
        let (x, y, z) = (
            420.0 + 80.0 * u,
            -150.0 + 300.0 * v,
            250.0 + 20.0 * (u * 7.0).sin(),
        );
        let cf = if y >= 0.0 { 0 } else { -1 };
        let _ = write!(
            w,
            "    MoveL [[{x:.3},{y:.3},{z:.3}],[0,0,1,0],[{cf},0,{cf},0],[9E9,9E9,9E9,9E9,9E9,9E9]],v200,z1,tSpindle\\WObj:=wPlate;\r\n"
        );
    }
    let _ = write!(w, "  ENDPROC\r\nENDMODULE\r\n");
}

/// Peak resident memory (kB) of the largest waited-for child so far.
fn children_peak_kb() -> i64 {
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: getrusage writes into the struct we own.
    unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage) };
    usage.ru_maxrss
}

/// CPU time (user and system) of all waited-for children so far: on a
/// machine other work shares, what a run costs apart from the wait.
fn children_cpu() -> Duration {
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: getrusage writes into the struct we own.
    unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage) };
    let t = |v: libc::timeval| Duration::new(v.tv_sec as u64, v.tv_usec as u32 * 1000);
    t(usage.ru_utime) + t(usage.ru_stime)
}

fn median(mut v: Vec<Duration>) -> Duration {
    v.sort();
    v[v.len() / 2]
}

fn end_to_end() {
    let n: usize = std::env::var("RAPIDTHERM_BENCH_TARGETS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000);
    let dir = tempfile::tempdir().expect("temp dir");
    let input = dir.path().join("big.mod");
    write_program(&input, n);
    let size_mb = std::fs::metadata(&input).map(|m| m.len()).unwrap_or(0) as f64 / 1e6;
    let out = dir.path().join("out.mod");
    let copy = dir.path().join("copy.mod");
    let mut cp_times = Vec::new();
    for _ in 0..3 {
        let t = Instant::now();
        let status = Command::new("cp")
            .arg(&input)
            .arg(&copy)
            .status()
            .expect("cp");
        assert!(status.success());
        cp_times.push(t.elapsed());
    }
    let cp_peak = children_peak_kb();
    let mut times = Vec::new();
    let mut cpu = Vec::new();
    for _ in 0..3 {
        let t = Instant::now();
        let c = children_cpu();
        let result = Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
            .args(["correct", "--at", "120", "-o"])
            .arg(&out)
            .arg(&input)
            .output()
            .expect("rapidtherm");
        assert!(
            result.status.success(),
            "{}",
            String::from_utf8_lossy(&result.stderr)
        );
        times.push(t.elapsed());
        cpu.push(children_cpu() - c);
    }
    let peak = children_peak_kb();
    // `targets` after `correct`: the peak memory read next is the larger
    // of the two runs'.
    let mut listing = Vec::new();
    let mut listing_cpu = Vec::new();
    for _ in 0..3 {
        let t = Instant::now();
        let c = children_cpu();
        let status = Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
            .arg("targets")
            .arg(&input)
            .stdout(std::process::Stdio::null())
            .status()
            .expect("rapidtherm");
        assert!(status.success());
        listing.push(t.elapsed());
        listing_cpu.push(children_cpu() - c);
    }
    let listing_peak = children_peak_kb();
    let (cp, rt, ls) = (median(cp_times), median(times), median(listing));
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    eprintln!(
        "end to end, {n} inline targets ({size_mb:.1} MB), medians of 3, load average {}:\n  cp {:.3} s (peak {} MB)\n  rapidtherm correct --at 120 -o OUT {:.2} s = {:.1} x cp, {:.1} MB/s, {:.2} µs/target, CPU {:.2} s (peak {} MB = {:.2} x the file)\n  rapidtherm targets {:.2} s = {:.1} MB/s, CPU {:.2} s (peak of both runs {} MB)",
        load.split_whitespace().take(3).collect::<Vec<_>>().join(" "),
        cp.as_secs_f64(),
        cp_peak / 1024,
        rt.as_secs_f64(),
        rt.as_secs_f64() / cp.as_secs_f64(),
        size_mb / rt.as_secs_f64(),
        rt.as_secs_f64() * 1e6 / n as f64,
        median(cpu).as_secs_f64(),
        peak / 1024,
        peak as f64 * 1024.0 / 1e6 / size_mb,
        ls.as_secs_f64(),
        size_mb / ls.as_secs_f64(),
        median(listing_cpu).as_secs_f64(),
        listing_peak / 1024
    );
    black_box(out);
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    bench_sample(&mut c);
    c.final_summary();
    end_to_end();
}
