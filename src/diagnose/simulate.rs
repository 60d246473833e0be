//! Simulated "real" data: the base model plus chosen effects at chosen
//! magnitudes, tracker noise, deterministic for a seed (ChaCha8).

use super::arm::{ArmMap, IsoCube};
use super::instrument::instrument;
use super::measurements::{Measurement, Measurements};
use crate::error::{Error, ErrorKind, Result};
use crate::model::{predict, Base, Effect, LinkLags, RowState};
use crate::rapid::{Program, TargetKind};
use crate::resolve::{frames_of, target_pose, usages, Frames};
use crate::robot::frames::flange_of_target;
use crate::robot::{Joints, Robot};
use crate::thermal::HeatingProfile;
use crate::thermal::TempHistory;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// What to simulate.
#[derive(Debug, Clone)]
pub struct SimSpec {
    pub base: Base,
    /// Labelled poses; each is measured at every time.
    pub poses: Vec<(String, Joints)>,
    /// Minutes since the cold start.
    pub times: Vec<f64>,
    pub effects: Vec<Effect>,
    /// Tracker noise, mm per axis (Gaussian).
    pub noise_mm: f64,
    pub orientation: bool,
    /// Write the motor temperatures as columns (else the reader uses the
    /// heating profile, the same one used here).
    pub measured_temps: bool,
    pub seed: u64,
}

/// `N` random poses uniformly within joint limits (degrees), labelled
/// `P1..PN`.
pub fn random_poses(n: usize, limits_deg: &[(f64, f64); 6], seed: u64) -> Vec<(String, Joints)> {
    // A stream separate from the noise's, so that changing the noise does
    // not change the poses.
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x9E37_79B9_7F4A_7C15);
    (0..n)
        .map(|i| {
            let q: Joints = std::array::from_fn(|k| {
                let (lo, hi) = limits_deg[k];
                rng.random_range(lo..hi).to_radians()
            });
            (format!("P{}", i + 1), q)
        })
        .collect()
}

/// The five positions of the ISO 9283 test plane of `cube` (an arm's:
/// [`super::arm::Arm::iso_cube`]): the cube cut by its diagonal plane
/// through C1, C2, C7, C8; P1 at the centre, P2..P5 on the plane's
/// diagonals at 10 % of their length from the corners. The tool (flange)
/// points down, as in most test set-ups; each pose is solved with the
/// natural configuration (arm in front, elbow up, wrist not flipped).
pub fn iso_cube_poses(robot: &Robot, cube: &IsoCube) -> Result<Vec<(String, Joints)>> {
    let h = cube.side / 2.0;
    let c = Vector3::from(cube.centre);
    // Corners of the diagonal plane: bottom front-left to top back-right.
    let corners = [
        Vector3::new(-h, -h, -h),
        Vector3::new(-h, h, -h),
        Vector3::new(h, h, h),
        Vector3::new(h, -h, h),
    ];
    // A point at `inset` of the diagonal from a corner is at 1 − 2·inset of
    // the half-diagonal from the centre.
    let scale = 1.0 - 2.0 * instrument()?.iso_cube.corner_inset;
    let mut points = vec![("P1".to_string(), c)];
    for (k, corner) in corners.iter().enumerate() {
        points.push((format!("P{}", k + 2), c + corner * scale));
    }
    let down = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::PI);
    points
        .into_iter()
        .map(|(name, p)| {
            let pose = Isometry3::from_parts(Translation3::from(p), down);
            let sols = robot.ik(&pose)?;
            let best = sols
                .iter()
                .filter(|s| s.conf.cfx == 0)
                .min_by(|a, b| {
                    let cost = |q: &Joints| q[3].abs() + q[5].abs();
                    cost(&a.q).total_cmp(&cost(&b.q))
                })
                .ok_or_else(|| {
                    Error::new(
                        ErrorKind::Unreachable,
                        format!("ISO cube point {name} at {p:?} has no front, elbow-up solution"),
                    )
                })?;
            Ok((name, best.q))
        })
        .collect()
}

/// The joints at which a RAPID program reaches each of its targets (with
/// the tool, work object and robconf the program gives), labelled by the
/// target identifiers. Derived targets and targets no move reaches are
/// left out.
pub fn program_poses(program: &Program, robot: &Robot) -> Result<Vec<(String, Joints)>> {
    let frames = Frames::of_program(program)?;
    let uses = usages(program);
    let mut out = Vec::new();
    for (index, target) in program.targets().iter().enumerate() {
        if target.kind == TargetKind::Derived
            || (target.kind != TargetKind::Inline && !uses.contains_key(&index))
        {
            continue;
        }
        let Some((pose, conf)) = target_pose(program, &target)? else {
            continue;
        };
        let (tool, wobj, _, _) = frames_of(program, &frames, index, uses.get(&index))?;
        let flange = flange_of_target(&pose, &tool, &wobj)?;
        let q = robot.ik_conf(&flange, &conf).map_err(|e| {
            Error {
                message: format!("target {}: {}", target.id, e.message),
                ..e
            }
            .at(program.location(&target.origin))
        })?;
        out.push((target.id.clone(), q));
    }
    if out.is_empty() {
        return Err(Error::input(
            "the program has no target a move instruction reaches",
        ));
    }
    Ok(out)
}

/// Make the measurements: rows ordered by time, then pose.
pub fn simulate(spec: &SimSpec, profile: &dyn HeatingProfile) -> Result<Measurements> {
    simulate_arm(spec, &ArmMap::default(), profile)
}

/// A simulated instrument's noise, mm per axis: finite, not negative, and
/// at most `data/instrument.toml`'s largest (a usage error otherwise,
/// before anything is read).
pub fn check_noise(noise_mm: f64) -> Result<()> {
    if !(noise_mm.is_finite() && noise_mm >= 0.0) {
        return Err(Error::usage(
            "the simulated tracker noise must be a finite number of mm >= 0",
        ));
    }
    let largest = instrument()?.position.max_noise_mm;
    if noise_mm > largest {
        let shown = if noise_mm >= 1e6 {
            format!("{noise_mm:e}")
        } else {
            noise_mm.to_string()
        };
        return Err(Error::usage(format!(
            "a tracker noise of {shown} mm is no instrument's: rapidtherm takes at most {largest} mm per axis (data/instrument.toml), and the effects it simulates are hundredths to tenths of a mm"
        )));
    }
    Ok(())
}

/// [`simulate`] for any OPW-shaped arm: `spec.poses` are the robot's
/// joints, mapped by `map` to the chain's; orientations are the robot's
/// tool0.
pub fn simulate_arm(
    spec: &SimSpec,
    map: &ArmMap,
    profile: &dyn HeatingProfile,
) -> Result<Measurements> {
    check_noise(spec.noise_mm)?;
    if spec.times.len().saturating_mul(spec.poses.len()) > 5_000_000 {
        return Err(Error::usage("simulate: more than 5,000,000 rows asked for"));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(spec.seed);
    let pos_noise = Normal::new(0.0, spec.noise_mm).map_err(|e| Error::usage(e.to_string()))?;
    // Probe orientation noise scales with the position noise asked for.
    let noise = instrument()?;
    let ori_noise = Normal::new(
        0.0,
        noise.orientation.noise_mrad * 1e-3 * (spec.noise_mm / noise.position.noise_mm),
    )
    .map_err(|e| Error::usage(e.to_string()))?;
    let t_end = spec.times.iter().copied().fold(0.0, f64::max);
    let history = TempHistory::from_profile(profile, t_end)?;
    let lag = LinkLags::new(&history, &spec.effects);
    let mut rows = Vec::with_capacity(spec.times.len() * spec.poses.len());
    for &t in &spec.times {
        let temps = profile.temps_at(t)?;
        let lagged = lag.as_ref().map(|l| l.at(t));
        for (label, q) in &spec.poses {
            let pose = map.tool0(&predict(
                &spec.base,
                &spec.effects,
                &RowState {
                    q: map.to_chain(q),
                    temps,
                    lagged,
                },
            ));
            let noise = Vector3::new(
                pos_noise.sample(&mut rng),
                pos_noise.sample(&mut rng),
                pos_noise.sample(&mut rng),
            );
            let orientation = if spec.orientation {
                let w = Vector3::new(
                    ori_noise.sample(&mut rng),
                    ori_noise.sample(&mut rng),
                    ori_noise.sample(&mut rng),
                );
                Some(pose.rotation * UnitQuaternion::from_scaled_axis(w))
            } else {
                None
            };
            rows.push(Measurement {
                line: 0,
                time_min: t,
                joints: *q,
                position: pose.translation.vector + noise,
                orientation,
                temps: spec.measured_temps.then_some(temps),
                ambient: None,
                pose: Some(label.clone()),
            });
        }
    }
    Ok(Measurements {
        file: "<simulated>".to_string(),
        rows,
        warnings: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnose::measurements::IRB140_LIMITS_DEG;

    #[test]
    fn same_seed_same_data() {
        let spec = SimSpec {
            base: Base::default(),
            poses: random_poses(3, &IRB140_LIMITS_DEG, 7),
            times: vec![0.0, 60.0],
            effects: vec![Effect::with_defaults(crate::model::EffectKind::ThermalLag)],
            noise_mm: 0.01,
            orientation: true,
            measured_temps: true,
            seed: 7,
        };
        let p = crate::thermal::default_profile();
        let a = simulate(&spec, &p).unwrap().to_csv();
        let b = simulate(&spec, &p).unwrap().to_csv();
        assert_eq!(a, b);
        let c = simulate(&SimSpec { seed: 8, ..spec }, &p).unwrap().to_csv();
        assert_ne!(a, c);
    }
}
