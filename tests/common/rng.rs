//! Deterministic uniform numbers for the kinematics tests (xorshift64*):
//! the same samples on every machine and run, without a seed file. Each
//! test crate uses part of it.
#![allow(dead_code)]

use rapidtherm::robot::{Joints, Robot};
use std::f64::consts::PI;

pub struct Rng(pub u64);

impl Rng {
    /// Uniform in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Joints uniform within the robot's limits.
    pub fn joints_within(&mut self, robot: &Robot) -> Joints {
        std::array::from_fn(|i| {
            let (lo, hi) = robot.limits[i];
            lo + (hi - lo) * self.next()
        })
    }

    /// Joints uniform in (−2π, 2π), whatever the limits.
    pub fn any_joints(&mut self) -> Joints {
        std::array::from_fn(|_| (self.next() * 2.0 - 1.0) * 2.0 * PI)
    }
}
