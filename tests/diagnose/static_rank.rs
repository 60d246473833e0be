//! The static stage is judged whenever the poses give more numbers than a
//! full kinematic calibration (with the instrument frame) can take up: 3 ×
//! poses (positions) above the identifiable rank of `geometry-offset` with
//! its joint origins and `tracker-frame` at these poses, not at a fixed
//! count of poses. The rank is computed here from the same poses, so that
//! the test follows the rule, not a number.

use super::world::{generate, SetSpec};
use rapidtherm::diagnose::fit::Problem;
use rapidtherm::diagnose::measurements::{Measurements, IRB140_LIMITS_DEG};
use rapidtherm::diagnose::temps::ColdStart;
use rapidtherm::diagnose::{diagnose, prepare, DiagnoseOptions, ScoredIn};
use rapidtherm::model::{EffectKind, Model};

/// Whether the static stage of a set of `poses` poses was judged, and the
/// identifiable rank of a full calibration and the frame at those poses.
fn judged_and_rank(poses: usize) -> (bool, usize) {
    let mut spec = SetSpec::new(vec![], 41_000 + poses as u64);
    spec.poses = poses;
    // Seven sweeps keep the test quick; each pose is measured again and
    // again, so the diagnosis works in its two stages.
    spec.times = (0..=6).map(|i| 30.0 * f64::from(i)).collect();
    let set = generate(&spec);
    let meas = Measurements::parse("rank.csv", set.csv.as_bytes(), &IRB140_LIMITS_DEG).unwrap();
    let prepared = prepare(&meas, &Model::default(), true).unwrap();
    let d = diagnose(
        &prepared,
        &DiagnoseOptions::default().with_cold_start(ColdStart::Irb140),
    )
    .unwrap();
    let stage = d
        .stages
        .iter()
        .find(|s| s.part == ScoredIn::Static)
        .expect("a static stage");
    // The rank against the noise the diagnosis estimated, as it judges it.
    let tuned = Problem {
        noise_mm: d.noise.per_axis_mm,
        origins: true,
        ..prepared.problem.clone()
    }
    .with_zero_jacobians();
    let all: Vec<usize> = (0..tuned.rows.len()).collect();
    let rank = tuned.identifiable_rank(
        &[EffectKind::GeometryOffset, EffectKind::TrackerFrame],
        &all,
    );
    (stage.judged, rank)
}

#[test]
fn static_stage_judged_when_three_times_poses_exceeds_the_rank() {
    let mut seen = [false; 2];
    for poses in [6, 8, 9, 12] {
        let (judged, rank) = judged_and_rank(poses);
        assert_eq!(
            judged,
            3 * poses > rank,
            "{poses} poses, rank {rank}: judged {judged}"
        );
        seen[usize::from(judged)] = true;
    }
    // Both sides of the rule were tried: the rule, not one outcome.
    assert_eq!(seen, [true, true], "judged and not judged both seen");
}
