//! A step in time (a knock, a loosened foot, a bumped fixture: no effect
//! of the library) in what the thermal effects leave over time, and its
//! test: each pose's own offset plus one shift from a measurement pause
//! on, its three components tested by F at the level shared among the
//! splits tried.

use super::drift;
use super::fit::Problem;
use super::forward::Forward;
use super::knock;
use super::locate;
use super::square;
use super::stats::Test;
use super::test_noise::TestNoise;

/// A knock as a step between the measurement times around it.
pub(super) fn step_of(problem: &Problem, k: &knock::Knock) -> locate::Step {
    let before = problem
        .rows
        .iter()
        .map(|r| r.time_min)
        .filter(|&t| t < k.after_min - 1e-9)
        .fold(f64::NEG_INFINITY, f64::max);
    let size = k.shift_mm.norm();
    let dir = if size > 0.0 {
        k.shift_mm / size
    } else {
        k.shift_mm
    };
    locate::Step {
        before_min: before,
        after_min: k.after_min,
        size_mm: size,
        direction: [dir.x, dir.y, dir.z],
    }
}

/// A step in time in what `thermal` leaves over time (each pose's own
/// offset taken out), when it is significant: an F test of its three
/// components against the noise, at the level shared among the splits
/// tried. Where a growth with the square of the temperatures adds
/// significantly beyond `thermal` (at `level`), the step must also be
/// significant beyond both (`square::left_beyond`): the growth is a
/// candidate too, and the part of it the effects leave is no step. The
/// step itself is the one the effects alone leave: fitted beyond the
/// square, a real knock lost the part the square took up, and the data
/// corrected by the rest still held a step that a scaled expansion or a
/// lag then followed (10 of 33 step sets, seeds 28006-28030).
///
/// Where no temperatures drive anything (`temps_drive` false), the step
/// is the alternative of a smooth drift in time, and must show beyond it
/// (line and square per axis, [`drift::detrended`]): the best split of a
/// straight drift takes up most of it as a step.
pub(super) fn significant_step(
    centred: &Problem,
    thermal: &Forward,
    noise: &TestNoise,
    level: f64,
    temps_drive: bool,
) -> Option<knock::Knock> {
    let all: Vec<usize> = (0..centred.rows.len()).collect();
    let effects = thermal.effects();
    let mut gaps = centred.position_gaps(&effects, &all);
    if !temps_drive {
        let times: Vec<f64> = centred.rows.iter().map(|r| r.time_min).collect();
        let poses: Vec<usize> = centred.rows.iter().map(|r| r.pose).collect();
        gaps = drift::detrended(&times, &poses, &gaps, true);
    }
    let (k, rss0, rss1, tried) = knock::best(centred, &all, &gaps)?;
    let beyond_square = if temps_drive {
        square::left_beyond(centred, &effects, noise, level)
    } else {
        None
    };
    let (rss0, rss1, tried) = match beyond_square {
        Some(left) => {
            let (_, rss0, rss1, tried) = knock::best(centred, &all, &left)?;
            (rss0, rss1, tried)
        }
        None => (rss0, rss1, tried),
    };
    let t = Test::nested(
        rss0,
        rss1,
        3,
        noise.sigma2,
        noise.dof,
        level / tried.max(1) as f64,
    );
    t.significant().then_some(k)
}
