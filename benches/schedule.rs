//! Schedule estimation speed (the walk only: the program is parsed once,
//! outside the timing): the committed CAM sample (5,251 inline MoveL) and a
//! generated CAM program of 1,000,000 inline targets (`gen_cam`, 5 passes;
//! set `SCHEDULE_BENCH_TARGETS` to change the count). Prints the parse
//! time, walk time and peak resident memory once per case on stderr.
//!
//! Then end to end, the binary on one generated CAM program of 80,000
//! targets (`gen_cam`; `SCHEDULE_BENCH_CORRECT_TARGETS` changes the count):
//! `correct --start 0` (the schedule estimated from the program) beside
//! `correct --at 120` (one moment for all), each streamed to a file and
//! on the whole-program path (to standard output), runs alternated so
//! that all see the same load, medians and the medians of the per-run
//! ratios on stderr.

use criterion::{criterion_group, Criterion, Throughput};
use rapidtherm::rapid;
use rapidtherm::robot::Robot;
use rapidtherm::schedule::{estimate, EstimateOptions};
use std::hint::black_box;
use std::process::Command;
use std::time::{Duration, Instant};

#[path = "../examples/gen_cam.rs"]
#[allow(dead_code)]
mod gen_cam;

fn peak_rss_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            let line = s.lines().find(|l| l.starts_with("VmHWM:"))?.to_string();
            line.split_whitespace().nth(1)?.parse::<f64>().ok()
        })
        .unwrap_or(0.0)
        / 1024.0
}

fn case(c: &mut Criterion, label: &str, bytes: &[u8], samples: usize) {
    let t = Instant::now();
    let program = rapid::parse(label, bytes).expect("parses");
    let parse_s = t.elapsed().as_secs_f64();
    let robot = Robot::irb140();
    let opts = EstimateOptions::default();
    let t = Instant::now();
    let est = estimate(&program, &robot, &opts).expect("schedules");
    let walk_s = t.elapsed().as_secs_f64();
    eprintln!(
        "{label}: {} targets, parse {parse_s:.2} s, schedule {walk_s:.3} s, program duration {:.1} min, peak RSS {:.0} MB",
        program.targets().len(),
        est.duration_min,
        peak_rss_mb()
    );
    let mut g = c.benchmark_group("schedule");
    g.sample_size(samples);
    g.throughput(Throughput::Elements(program.targets().len() as u64));
    g.bench_function(label, |b| {
        b.iter(|| estimate(black_box(&program), &robot, &opts).expect("schedules"))
    });
    g.finish();
}

fn cam_sample(c: &mut Criterion) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/samples/cam_contour.mod");
    let bytes = std::fs::read(path).expect("sample");
    case(c, "cam_contour.mod", &bytes, 20);
}

fn generated(c: &mut Criterion) {
    let n: usize = std::env::var("SCHEDULE_BENCH_TARGETS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1_000_000);
    let text = gen_cam::cam_program(n / 5, 5);
    case(c, "generated", text.as_bytes(), 10);
}

/// One run of `rapidtherm correct` with `when` (its arguments) on `input`,
/// written to `out` (`-`: standard output, thrown away).
fn time_correct(
    when: &[&str],
    input: &std::path::Path,
    out: impl AsRef<std::ffi::OsStr>,
) -> Duration {
    let t = Instant::now();
    let result = Command::new(env!("CARGO_BIN_EXE_rapidtherm"))
        .arg("correct")
        .args(when)
        .arg("-o")
        .arg(out)
        .arg(input)
        .stdout(std::process::Stdio::null())
        .output()
        .expect("rapidtherm");
    let elapsed = t.elapsed();
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    elapsed
}

fn median<T: PartialOrd + Copy>(mut v: Vec<T>) -> T {
    v.sort_by(|a, b| a.partial_cmp(b).expect("no NaN"));
    v[v.len() / 2]
}

fn start_beside_at() {
    let n: usize = std::env::var("SCHEDULE_BENCH_CORRECT_TARGETS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(80_000);
    let dir = tempfile::tempdir().expect("temp dir");
    let input = dir.path().join("cam.mod");
    std::fs::write(&input, gen_cam::cam_program(n / 5, 5)).expect("temp file");
    let out = dir.path().join("out.mod");
    // To a file and to standard output the correction is the same pass
    // (docs/streaming.md): written into its sink as it goes, one task
    // writing its files; the two are timed side by side.
    let (mut at, mut start, mut at_whole, mut start_whole, mut ratios) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for _ in 0..3 {
        let a = time_correct(&["--at", "120"], &input, &out);
        let s = time_correct(&["--start", "0"], &input, &out);
        let aw = time_correct(&["--at", "120"], &input, "-");
        let sw = time_correct(&["--start", "0"], &input, "-");
        ratios.push((
            s.as_secs_f64() / a.as_secs_f64(),
            sw.as_secs_f64() / s.as_secs_f64(),
        ));
        at.push(a);
        start.push(s);
        at_whole.push(aw);
        start_whole.push(sw);
    }
    let secs = |v: Vec<Duration>| median(v).as_secs_f64();
    let over_at = median(ratios.iter().map(|r| r.0).collect());
    let speedup = median(ratios.iter().map(|r| r.1).collect());
    eprintln!(
        "correct on {n} CAM targets, 3 runs each, medians: streamed (-o OUT) --at 120 {:.3} s, --start 0 {:.3} s; whole-program path (-o -) --at 120 {:.2} s, --start 0 {:.2} s; streamed --start over streamed --at {over_at:.2} x, whole-path --start over streamed --start {speedup:.1} x (medians of the runs' ratios)",
        secs(at),
        secs(start),
        secs(at_whole),
        secs(start_whole),
    );
}

criterion_group!(benches, cam_sample, generated);

fn main() {
    benches();
    Criterion::default().configure_from_args().final_summary();
    start_beside_at();
}
