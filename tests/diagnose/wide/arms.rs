//! The arms of the widened evaluation and the poses a measurement program
//! would visit on each.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use rapidtherm::diagnose::arm::Arm as DiagArm;
use rapidtherm::robot::{Joints, Robot};
use std::path::PathBuf;

/// An arm of the evaluation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum WideArm {
    Irb140,
    Ur5,
    /// Stäubli TX60: a lateral offset of 20 mm between shoulder and forearm.
    Tx60,
    /// KUKA KR 210 R2700 extra: 2.7 m of reach.
    Kr210,
}

impl WideArm {
    pub const ALL: [WideArm; 4] = [WideArm::Irb140, WideArm::Ur5, WideArm::Tx60, WideArm::Kr210];

    pub fn name(self) -> &'static str {
        match self {
            WideArm::Irb140 => "irb140",
            WideArm::Ur5 => "ur5",
            WideArm::Tx60 => "tx60",
            WideArm::Kr210 => "kr210",
        }
    }

    /// The URDF of the arm (none for the IRB 140: the library's own).
    pub fn urdf(self) -> Option<PathBuf> {
        let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data");
        match self {
            WideArm::Irb140 => None,
            WideArm::Ur5 => Some(dir.join("ur5/ur5.urdf")),
            WideArm::Tx60 => Some(dir.join("tx60/tx60.urdf")),
            WideArm::Kr210 => Some(dir.join("kr210/kr210.urdf")),
        }
    }

    /// The robot, as a user's `--robot` would give it.
    pub fn robot(self) -> Robot {
        match self.urdf() {
            None => Robot::irb140(),
            Some(path) => Robot::from_urdf_file(&path)
                .unwrap_or_else(|e| panic!("{}: {}", path.display(), e.message)),
        }
    }

    /// The arm the diagnosis works on.
    pub fn diag_arm(self, robot: &Robot) -> DiagArm {
        let source = self
            .urdf()
            .map_or_else(|| "irb140".to_string(), |p| p.display().to_string());
        DiagArm::of_robot(robot, &source)
            .unwrap_or_else(|e| panic!("{}: {}", self.name(), e.message))
    }

    /// How far the tracker stands from the base, mm: a few metres, more
    /// for the large arm.
    pub fn tracker_range_mm(self) -> (f64, f64) {
        match self {
            WideArm::Kr210 => (4000.0, 6000.0),
            _ => (2000.0, 3500.0),
        }
    }
}

/// A pose of a measurement program: every joint within its limits (and
/// within ±170°, as programs keep clear of the stops), the wrist clear of
/// its singularity (|sin q5| > 0.3 on the axis's own zero).
pub fn random_pose(rng: &mut ChaCha8Rng, limits: &[(f64, f64); 6]) -> Joints {
    let bound = 170f64.to_radians();
    let mut draw = |i: usize| {
        let (lo, hi) = limits[i];
        let (lo, hi) = (lo.max(-bound), hi.min(bound));
        rng.random_range(lo..hi)
    };
    let mut q: Joints = [0.0; 6];
    for (i, v) in q.iter_mut().enumerate().take(4) {
        *v = draw(i);
    }
    q[4] = loop {
        let v = draw(4);
        if v.sin().abs() > 0.3 {
            break v;
        }
    };
    q[5] = draw(5);
    q
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    /// The new arms' tool0, worked by hand from the data sheets' lengths
    /// (the READMEs beside the URDFs): the TX60 straight up at zero, and
    /// with axis 2 turned 90° its arm along +x (R_y(90°) takes z to x); the
    /// KR 210 at zero with its lower arm and forearm horizontal forward.
    #[test]
    fn the_new_arms_are_their_data_sheets() {
        let deg = |q: [f64; 6]| q.map(f64::to_radians);
        for (arm, q, p) in [
            (WideArm::Tx60, [0.0; 6], [0.0, 20.0, 1045.0]),
            (
                WideArm::Tx60,
                [0.0, 90.0, 0.0, 0.0, 0.0, 0.0],
                [670.0, 20.0, 375.0],
            ),
            // 350 + 1150 + 1200 + 215 forward; 675 − 41 up.
            (WideArm::Kr210, [0.0; 6], [2915.0, 0.0, 634.0]),
            // Axis 2 at −90° (the lower arm straight up), axis 3 at +90°
            // (the forearm forward again): 350 + 1415 forward, 675 + 1150
            // − 41 up.
            (
                WideArm::Kr210,
                [0.0, -90.0, 90.0, 0.0, 0.0, 0.0],
                [1765.0, 0.0, 1784.0],
            ),
        ] {
            let got = arm.robot().fk(&deg(q)).translation.vector;
            assert!(
                (got - Vector3::from(p)).norm() < 1e-6,
                "{} at {q:?}: {got:?} against {p:?}",
                arm.name()
            );
        }
    }
}
