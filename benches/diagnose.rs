//! Diagnosis of 10,000 measurements (100 poses × 100 times, one effect),
//! all candidates scored with cross-validation and forward selection.

use criterion::{criterion_group, criterion_main, Criterion};
use rapidtherm::diagnose::measurements::IRB140_LIMITS_DEG;
use rapidtherm::diagnose::simulate::{random_poses, simulate, SimSpec};
use rapidtherm::diagnose::{diagnose, prepare, DiagnoseOptions};
use rapidtherm::model::Model;
use rapidtherm::model::{Base, Effect, EffectKind};
use rapidtherm::thermal::default_profile;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
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

criterion_group!(benches, bench);
criterion_main!(benches);
