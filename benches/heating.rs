//! Speed of the heating fits on the reference sample (2017 rows) and of the
//! default profile's evaluation (called once per target when correcting).

use criterion::{criterion_group, criterion_main, Criterion};
use rapidtherm::thermal::fit::{fit_curve, ModelKind};
use rapidtherm::thermal::{default_profile, HeatingProfile, HeatingRecord};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/samples/heating_irb140_60pct.csv"
    );
    let bytes = std::fs::read(path).expect("sample");
    c.bench_function("parse sample", |b| {
        b.iter(|| HeatingRecord::parse("s", black_box(&bytes)).expect("parse"))
    });
    let rec = HeatingRecord::parse("s", &bytes).expect("parse");
    let (t, y) = (&rec.times, &rec.temps[5]);
    for kind in [
        ModelKind::Poly(3),
        ModelKind::Poly(10),
        ModelKind::FirstOrder,
        ModelKind::TwoTau,
    ] {
        c.bench_function(&format!("fit {kind} axis 6"), |b| {
            b.iter(|| fit_curve(black_box(t), black_box(y), kind, None).expect("fit"))
        });
    }
    let p = default_profile();
    c.bench_function("default profile temps_at", |b| {
        b.iter(|| p.temps_at(black_box(97.5)).expect("temps"))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
