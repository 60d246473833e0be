//! Parsing speed and peak memory of the RAPID reader: the committed CAM
//! sample (~0.7 MB, 5,251 inline MoveL) and a generated ~100 MB CAM program
//! (written to a temporary directory at bench time, never committed).
//!
//! Besides criterion's timings, prints MB/s and the process's peak resident
//! memory (VmHWM, reset before each case through /proc/self/clear_refs) to
//! stderr.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use std::hint::black_box;
use std::time::Instant;

#[path = "../examples/gen_cam.rs"]
#[allow(dead_code)]
mod gen_cam;

fn peak_rss_kb() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

fn current_rss_kb() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmRSS:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

fn reset_peak() {
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

/// One timed parse outside criterion, for MB/s and memory.
fn report(label: &str, bytes: &[u8]) {
    reset_peak();
    let before = current_rss_kb().unwrap_or(0);
    let t = Instant::now();
    let prog = rapidtherm::rapid::parse(label, bytes).expect("parses");
    let dt = t.elapsed().as_secs_f64();
    let peak = peak_rss_kb().unwrap_or(0);
    eprintln!(
        "{label}: {:.1} MB in {:.3} s = {:.1} MB/s; {} targets; RSS before {:.0} MB (input held), peak {:.0} MB, parse added {:.0} MB",
        bytes.len() as f64 / 1e6,
        dt,
        bytes.len() as f64 / 1e6 / dt,
        prog.targets().len(),
        before as f64 / 1024.0,
        peak as f64 / 1024.0,
        (peak.saturating_sub(before)) as f64 / 1024.0,
    );
}

fn cam_sample(c: &mut Criterion) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/samples/cam_contour.mod");
    let bytes = std::fs::read(path).expect("sample");
    report("cam_contour.mod", &bytes);
    let mut g = c.benchmark_group("parse");
    g.throughput(Throughput::Bytes(bytes.len() as u64));
    g.bench_function("cam_contour.mod", |b| {
        b.iter(|| rapidtherm::rapid::parse("cam", black_box(&bytes)).expect("parses"))
    });
    g.finish();
}

fn cam_100mb(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("cam_100mb.mod");
    // ~125 bytes per move, 5 passes.
    std::fs::write(&path, gen_cam::cam_program(160_000, 5)).expect("write");
    let bytes = std::fs::read(&path).expect("read");
    report("generated 100 MB", &bytes);
    let mut g = c.benchmark_group("parse");
    g.sample_size(10);
    g.throughput(Throughput::Bytes(bytes.len() as u64));
    g.bench_function("cam_100mb", |b| {
        b.iter(|| rapidtherm::rapid::parse("cam", black_box(&bytes)).expect("parses"))
    });
    g.finish();
}

criterion_group!(benches, cam_sample, cam_100mb);
criterion_main!(benches);
