//! The controller module of `correct --runtime`: its arithmetic (the
//! `mirror`) against the project's own warm arm and heating curves, the
//! first-order correction's error, and the module's RAPID read by the
//! project's own grammar.

use nalgebra::{Isometry3, UnitQuaternion};
use rand::{RngExt, SeedableRng};
use rapidtherm::correct::runtime::mirror::{
    advance, days_since_2000, drift_base, grown, growth, temps, Rises,
};
use rapidtherm::correct::runtime::{module_text, ModuleOptions, RuntimeSpec};
use rapidtherm::model::Model;
use rapidtherm::robot::Robot;

fn spec(robot: &Robot) -> RuntimeSpec {
    RuntimeSpec::new(robot, &Model::default(), UnitQuaternion::identity()).unwrap()
}

fn random_q(robot: &Robot, rng: &mut rand_chacha::ChaCha8Rng) -> [f64; 6] {
    std::array::from_fn(|i| {
        let (lo, hi) = robot.limits[i];
        rng.random_range(lo.max(-3.0)..hi.min(3.0))
    })
}

#[test]
fn the_day_number_is_the_calendars() {
    // Python's date arithmetic gave these.
    for ((y, m, d), n) in [
        ((2000, 1, 1), 0),
        ((2000, 3, 1), 60),
        ((2024, 2, 29), 8825),
        ((2026, 11, 27), 9827),
        ((2100, 3, 1), 36584),
    ] {
        assert_eq!(days_since_2000(y, m, d), n, "{y}-{m}-{d}");
    }
}

#[test]
fn the_series_keeps_the_digits_exp_would_lose() {
    for u in [1e-7f64, 1e-4, 0.005, 0.0099, 0.01, 0.5, 3.0, 40.0] {
        let exact = -(-u).exp_m1();
        assert!(((grown(u) - exact) / exact).abs() < 1e-9, "u = {u}");
    }
}

#[test]
fn running_in_steps_follows_the_heating_curves_and_stopping_cools() {
    let s = spec(&Robot::irb140());
    let mut x: Rises = [[0.0; 2]; 6];
    // A correction every 6 s for three hours.
    let step = 0.1;
    for _ in 0..1800 {
        advance(&s, &mut x, step, true);
    }
    let t = temps(&s, &x);
    for (a, (t, c)) in t.iter().zip(&s.curves).enumerate() {
        let curve = c.eval(180.0);
        assert!((t - curve).abs() < 1e-9, "axis {}: {t} vs {curve}", a + 1);
    }
    // A night's stop: back to the cold start's temperatures.
    advance(&s, &mut x, 16.0 * 60.0, false);
    let cold = temps(&s, &x);
    for (a, (t, c)) in cold.iter().zip(&s.curves).enumerate() {
        assert!((t - c.t0).abs() < 0.01, "axis {}", a + 1);
    }
}

#[test]
fn the_drift_is_the_warm_arms_on_every_closed_form_arm() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(31);
    let mut arms = vec![Robot::irb140()];
    for arm in rapidtherm::robot::abb::catalogue() {
        let r = arm.robot();
        if r.opw.as_ref().is_ok_and(|o| o.coupling == 0.0) {
            arms.push(r);
        }
    }
    assert!(arms.len() > 3, "{} arms", arms.len());
    let model = Model::default();
    let hot: [f64; 6] = [45.0, 52.0, 48.0, 38.0, 41.0, 35.0];
    let scales = model.thermal.scales(&hot);
    for robot in &arms {
        let s = spec(robot);
        let g = growth(&s, &hot);
        for k in 0..4 {
            assert!((g[k] + 1.0 - scales[k]).abs() < 1e-15, "{}", robot.name);
        }
        for _ in 0..200 {
            let q = random_q(robot, &mut rng);
            let want =
                robot.fk_scaled(&q, &scales).translation.vector - robot.fk(&q).translation.vector;
            let got = drift_base(&s, &q.map(f64::to_degrees), &g);
            assert!(
                (got - want).norm() < 1e-9,
                "{} at {q:?}: {got} vs {want}",
                robot.name
            );
        }
    }
}

#[test]
fn the_first_order_correction_is_right_to_far_below_a_micrometre() {
    let robot = Robot::irb140();
    let s = spec(&robot);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let model = Model::default();
    let steady: [f64; 6] = std::array::from_fn(|a| s.curves[a].steady());
    let scales = model.thermal.scales(&steady);
    let g = growth(&s, &steady);
    let (mut worst, mut largest) = (0.0f64, 0.0f64);
    let mut n = 0;
    while n < 500 {
        let q = random_q(&robot, &mut rng);
        let target = robot.fk(&q);
        let conf = robot.conf_of(&q);
        // What the module does: the drift at the target's nominal joints,
        // taken off the target.
        let d = drift_base(&s, &q.map(f64::to_degrees), &g);
        let moved = Isometry3::from_parts((target.translation.vector - d).into(), target.rotation);
        let Ok(sols) = robot.ik(&moved) else { continue };
        let Some(sol) = sols.iter().find(|x| x.conf == conf) else {
            continue;
        };
        let reached = robot.fk_scaled(&sol.q, &scales).translation.vector;
        worst = worst.max((reached - target.translation.vector).norm());
        largest = largest.max(d.norm());
        n += 1;
    }
    assert!(largest > 0.05, "the drift at steady state: {largest} mm");
    // The first-order step misses by the drift's change over the joint
    // move it makes: ~1e-5 mm over most of the space, up to 0.3 µm near
    // the wrist's singularity (500 random poses at steady state), within
    // the micrometre the static correction is held to.
    assert!(
        worst < 5e-4,
        "worst miss {worst} mm (drift up to {largest} mm)"
    );
}

#[test]
fn the_module_is_read_by_the_projects_grammar_and_adds_only_its_five_names() {
    let s = spec(&Robot::irb140());
    let opts = ModuleOptions {
        name: "ThWarm".into(),
        version: "test".into(),
        heating_source: "the embedded default".into(),
        model: "the embedded default".into(),
    };
    let text = module_text(&s, &Default::default(), &opts);
    assert!(text.ends_with("ENDMODULE\r\n"));
    assert!(!text.replace("\r\n", "").contains('\n'), "CRLF throughout");
    let program = rapidtherm::rapid::parse("ThWarm.sys", text.as_bytes()).unwrap();
    assert!(program.warnings.is_empty(), "{:?}", program.warnings);
    assert_eq!(program.source(0), text.as_bytes());
    let m = &program.modules[0];
    assert_eq!(&*m.name, "ThWarm");
    assert!(m
        .attributes
        .iter()
        .any(|a| a.eq_ignore_ascii_case("SYSMODULE")));
    // What the rewritten program calls is defined under the chosen name
    // (issue 48: `--runtime-module ThWarm` wrote calls of ThWarm(...)
    // while the functions stayed RtWarm); nothing else is global, so the
    // module cannot clash with a name of the task (ABB RAPID overview:
    // a LOCAL routine or datum is seen in its own module only).
    let mut global: Vec<&str> = m
        .routines
        .iter()
        .filter(|r| !r.local)
        .map(|r| &*r.name)
        .collect();
    global.sort_unstable();
    assert_eq!(
        global,
        ["ThWarm", "ThWarmJ", "ThWarmJT", "ThWarmReset", "ThWarmT"]
    );
    assert!(m
        .data
        .iter()
        .all(|d| d.scope == Some(rapidtherm::rapid::Scope::Local)));
    // The state is PERS, the arm's numbers CONST.
    let pers: Vec<&str> = m
        .data
        .iter()
        .filter(|d| d.storage == rapidtherm::rapid::Storage::Pers)
        .map(|d| d.name.as_str())
        .collect();
    assert_eq!(pers, ["rtX", "rtKnown", "rtDay", "rtMinute"], "{pers:?}");
    // Numbers as the controller keeps them: none longer than a float's
    // shortest form (issue 48: literals of 20 digits).
    for word in text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '.' || c == '-')) {
        let mantissa = word.split('E').next().unwrap_or("");
        let significant = mantissa.trim_start_matches(['-', '0', '.']);
        let digits = significant.chars().filter(char::is_ascii_digit).count();
        if word.starts_with(|c: char| c.is_ascii_digit() || c == '-') {
            assert!(digits <= 9, "{word}");
        }
    }
}

fn root() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The lines of `after` that are not in `before`, and the reverse.
fn changed_lines(before: &str, after: &str) -> (Vec<String>, Vec<String>) {
    let b: Vec<&str> = before.lines().collect();
    let a: Vec<&str> = after.lines().collect();
    let gone = b
        .iter()
        .filter(|l| !a.contains(l))
        .map(|l| l.to_string())
        .collect();
    let new = a
        .iter()
        .filter(|l| !b.contains(l))
        .map(|l| l.to_string())
        .collect();
    (gone, new)
}

#[test]
fn runtime_rewrites_only_the_moves_and_writes_the_module_beside() {
    let dir = tempfile::tempdir().unwrap();
    let cold = std::fs::read(root().join("samples/fixtures.mod")).unwrap();
    std::fs::write(dir.path().join("fixtures.mod"), &cold).unwrap();
    std::fs::create_dir(dir.path().join("warm")).unwrap();
    let out = super::rapidtherm(
        &[
            "correct",
            "fixtures.mod",
            "--runtime",
            "-o",
            "warm/fixtures.mod",
        ],
        dir.path(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let written = std::fs::read(dir.path().join("warm/fixtures.mod")).unwrap();
    let module = std::fs::read(dir.path().join("warm/RtWarm.sys")).unwrap();
    // Both read by the project's own grammar, byte for byte.
    for (name, bytes) in [("fixtures.mod", &written), ("RtWarm.sys", &module)] {
        let p = rapidtherm::rapid::parse(name, bytes).unwrap();
        assert_eq!(p.source(0), bytes.as_slice());
    }
    let (before, after) = (
        String::from_utf8_lossy(&cold),
        String::from_utf8_lossy(&written),
    );
    let (gone, new) = changed_lines(&before, &after);
    // Every line that changed is a move now calling the module, plus the
    // marker's two lines; the declarations keep their cold numbers.
    let program = rapidtherm::rapid::parse("fixtures.mod", &cold).unwrap();
    let moves = {
        let mut n = 0;
        rapidtherm::resolve::each_move_instruction(&program, &mut |_| n += 1);
        n
    };
    assert!(moves > 5, "{moves} moves");
    assert_eq!(gone.len(), new.len() - 2, "{gone:?}\n{new:?}");
    assert!(new.iter().any(|l| l.contains("basis=runtime RtWarm")));
    assert!(new.iter().any(|l| l.contains("rapidtherm numbers v2")));
    let calls = new.iter().filter(|l| l.contains("RtWarm")).count();
    assert_eq!(calls, gone.len() + 1, "{new:?}");
    for l in &gone {
        assert!(
            rapidtherm::rapid::motion_signature(l.split_whitespace().next().unwrap()).is_some(),
            "only moves change: {l}"
        );
    }
    // A second run changes nothing; a static correction of the result
    // is refused (it would correct twice).
    let again = super::rapidtherm(
        &["correct", "warm/fixtures.mod", "--runtime", "--diff"],
        dir.path(),
    );
    super::assert_exit(&again, 0);
    assert!(again.stdout.is_empty());
    let twice = super::rapidtherm(
        &["correct", "warm/fixtures.mod", "--at", "60", "--diff"],
        dir.path(),
    );
    assert_eq!(twice.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&twice.stderr).contains("second correction"));
}

#[test]
fn runtime_on_a_backup_changes_only_moves_and_adds_the_module_to_each_motion_task() {
    let dir = tempfile::tempdir().unwrap();
    let backup = dir.path().join("backup");
    super::common::copy_tree(&root().join("samples/backup_multimove"), &backup);
    let out = super::rapidtherm(
        &["correct", "backup", "--runtime", "--in-place"],
        dir.path(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut modules = 0;
    for task in ["TASK1", "TASK2", "TASK3"] {
        let sysmod = backup.join("RAPID").join(task).join("SYSMOD/RtWarm.sys");
        if sysmod.exists() {
            modules += 1;
            let text = std::fs::read(&sysmod).unwrap();
            rapidtherm::rapid::parse("RtWarm.sys", &text).unwrap();
        }
        for f in ["PROGMOD", "SYSMOD"] {
            let src_dir = root()
                .join("samples/backup_multimove/RAPID")
                .join(task)
                .join(f);
            for e in std::fs::read_dir(&src_dir).unwrap() {
                let e = e.unwrap();
                let before = std::fs::read_to_string(e.path()).unwrap();
                let after = std::fs::read_to_string(
                    backup.join("RAPID").join(task).join(f).join(e.file_name()),
                )
                .unwrap();
                let (gone, _) = changed_lines(&before, &after);
                for l in &gone {
                    assert!(
                        rapidtherm::rapid::motion_signature(l.split_whitespace().next().unwrap())
                            .is_some(),
                        "{task}/{f}: only moves change: {l}"
                    );
                }
            }
        }
    }
    // The backup's two robots' tasks (the third moves none).
    assert_eq!(modules, 2);
    let again = super::rapidtherm(&["correct", "backup", "--runtime", "--diff"], dir.path());
    super::assert_exit(&again, 0);
    assert!(
        again.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&again.stdout)
    );
}

#[test]
fn runtime_refuses_what_the_module_cannot_carry_with_the_reason() {
    // A recording has no state to carry through a stop.
    let dir = tempfile::tempdir().unwrap();
    let out = super::rapidtherm(
        &[
            "correct".as_ref(),
            root().join("tests/cmd/correct_data/cell.mod").as_os_str(),
            "--runtime".as_ref(),
            "--diff".as_ref(),
            "--model".as_ref(),
            root()
                .join("tests/cmd/correct_data/recorded.toml")
                .as_os_str(),
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("heating fit --model two-tau"), "{err}");
    // A parallel-arm robot, typed.
    let parallel = rapidtherm::robot::abb::catalogue()
        .iter()
        .map(|a| a.robot())
        .find(|r| r.opw.as_ref().is_ok_and(|o| o.coupling != 0.0))
        .expect("the catalogue has a parallel-arm robot");
    let e = RuntimeSpec::new(&parallel, &Model::default(), UnitQuaternion::identity()).unwrap_err();
    assert!(e.message.contains("parallel-arm"), "{}", e.message);
    // A bad module name is a usage error before anything is read.
    let bad = super::rapidtherm(
        &["correct", "x.mod", "--runtime", "--runtime-module", "9x"],
        dir.path(),
    );
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("a RAPID name"));
}

#[test]
fn at_minute_zero_the_module_moves_no_target() {
    // A cold state (what a freshly written module and RtWarmReset hold):
    // the motors at the curves' T0, which the embedded model taught its
    // targets at, so every link's growth and every drift is zero.
    let robot = Robot::irb140();
    let s = spec(&robot);
    let x: Rises = [[0.0; 2]; 6];
    let g = growth(&s, &temps(&s, &x));
    assert_eq!(g, [0.0; 4]);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0);
    for _ in 0..100 {
        let q = random_q(&robot, &mut rng);
        assert_eq!(drift_base(&s, &q.map(f64::to_degrees), &g).norm(), 0.0);
    }
    // And it warms from there: after an hour running, a drift.
    let mut warm = x;
    advance(&s, &mut warm, 60.0, true);
    let q = random_q(&robot, &mut rng).map(f64::to_degrees);
    assert!(drift_base(&s, &q, &growth(&s, &temps(&s, &warm))).norm() > 0.01);
}
