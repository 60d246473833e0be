//! FK and IK per call, rapidtherm beside rs-opw-kinematics (same arm, same
//! poses, same run). `cargo bench --bench kinematics`.

use criterion::{criterion_group, criterion_main, Criterion};
use rapidtherm::robot::{irb140_opw, Joints, Robot};
use rs_opw_kinematics::glam::{DQuat, DVec3};
use rs_opw_kinematics::kinematic_traits::{Kinematics, Pose};
use rs_opw_kinematics::kinematics_impl::OPWKinematics;
use rs_opw_kinematics::parameters::opw_kinematics::Parameters;
use std::hint::black_box;

fn reference() -> OPWKinematics {
    let irb140 = irb140_opw();
    OPWKinematics::new(Parameters {
        a1: irb140.a1,
        a2: irb140.a2,
        b: irb140.b,
        c1: irb140.c1,
        c2: irb140.c2,
        c3: irb140.c3,
        c4: irb140.c4,
        offsets: [0.0, 0.0, -std::f64::consts::FRAC_PI_2, 0.0, 0.0, 0.0],
        sign_corrections: [1; 6],
        dof: 6,
    })
}

fn bench(c: &mut Criterion) {
    let robot = Robot::irb140();
    let arm = robot.opw.clone().expect("the IRB 140 has OPW form");
    let wide = [(-std::f64::consts::PI, std::f64::consts::PI); 6];
    let reference = reference();
    let q: Joints = [30.0f64, 20.0, -40.0, 50.0, 60.0, 70.0].map(f64::to_radians);
    let temps = rapidtherm::thermal::TABLE1_TMAX;
    let pose = robot.fk(&q);
    let t = pose.translation.vector;
    let r = pose.rotation.quaternion();
    let ref_pose = Pose::from_parts(
        DVec3::new(t.x, t.y, t.z),
        DQuat::from_xyzw(r.i, r.j, r.k, r.w),
    );
    let conf = robot.conf_of(&q);

    let mut g = c.benchmark_group("fk");
    g.bench_function("rapidtherm", |b| b.iter(|| robot.fk(black_box(&q))));
    g.bench_function("rapidtherm_warm", |b| {
        // The warm arm as the correction asks for it: the link scales of
        // the motor temperatures, then the scaled arm's FK.
        let thermal = rapidtherm::model::ThermalExpansion::default();
        b.iter(|| robot.fk_scaled(black_box(&q), &thermal.scales(black_box(&temps))))
    });
    g.bench_function("rapidtherm_urdf_chain", |b| {
        b.iter(|| robot.chain.fk(black_box(&q)))
    });
    g.bench_function("rs_opw_kinematics", |b| {
        b.iter(|| reference.forward(black_box(&q)))
    });
    g.finish();

    let mut g = c.benchmark_group("ik");
    g.bench_function("rapidtherm_8_branches", |b| {
        b.iter(|| arm.solve(black_box(&pose), &wide, None))
    });
    g.bench_function("rapidtherm_all_turns_in_limits", |b| {
        b.iter(|| robot.ik(black_box(&pose)))
    });
    g.bench_function("rapidtherm_with_robconf", |b| {
        b.iter(|| robot.ik_conf(black_box(&pose), &conf))
    });
    // The enumerate-and-pick search the direct robconf path replaced (its
    // fallback and test reference), for before and after in one run.
    g.bench_function("rapidtherm_with_robconf_by_enumeration", |b| {
        b.iter(|| arm.solve_conf_by_enumeration(black_box(&pose), &robot.limits, &conf))
    });
    g.bench_function("rs_opw_kinematics", |b| {
        b.iter(|| reference.inverse(black_box(&ref_pose)))
    });
    // The reference's closest call to IK with a robconf: one pose, its
    // solutions sorted by closeness to the previous joints (the first is
    // the one a program would take).
    g.bench_function("rs_opw_kinematics_continuing", |b| {
        b.iter(|| reference.inverse_continuing(black_box(&ref_pose), &q))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
