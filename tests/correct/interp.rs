//! The project runs what it writes: the controller module of `correct
//! --runtime`, executed by the project's own RAPID interpreter
//! (`interp`), agrees with the static correction (`correct
//! --at`, `correct --schedule`) on every sample's every target.

use nalgebra::{Isometry3, UnitQuaternion};
use rapidtherm::correct::job::warm_robot;
use rapidtherm::correct::runtime::{module_text, ModuleOptions, RuntimeSpec};
use rapidtherm::correct::{correct, Correction, Options, ScheduleSource, When};
use rapidtherm::interp::{kin, CallArg, Clock, Interp, Kinematics, Precision, Value};
use rapidtherm::model::warm::Moment;
use rapidtherm::model::Model;
use rapidtherm::rapid::{self, Program};
use rapidtherm::robot::Robot;
use rapidtherm::schedule::Schedule;
use std::collections::HashMap;
use std::path::PathBuf;

/// The module `correct --runtime` writes for the embedded IRB 140 and
/// model, its base frame turned by `base` in the world.
pub(super) fn module(base: UnitQuaternion<f64>) -> String {
    let spec = RuntimeSpec::new(&Robot::irb140(), &Model::default(), base).unwrap();
    let opts = ModuleOptions {
        name: "RtWarm".into(),
        version: "test".into(),
        heating_source: "the embedded default".into(),
    };
    module_text(&spec, &opts)
}

/// An interpreter holding the module of a robot standing at `base` in
/// the world, its clock at `start`.
fn interp(base: Isometry3<f64>, start: Clock) -> Interp {
    let text = module(base.rotation);
    let mut kin = Kinematics::new(Robot::irb140());
    kin.base = base;
    let mut i = Interp::load(&[("RtWarm.sys", text.as_bytes())], kin).unwrap();
    i.set_clock(start);
    i
}

/// Late on a Friday: a day of running crosses midnight.
pub(super) fn start() -> Clock {
    Clock::at(2026, 11, 27, 22, 30, 0)
}

pub(super) fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A sample program and where its robot stands in the world.
struct Sample {
    name: String,
    program: Program,
    base: Option<Isometry3<f64>>,
    /// The robtarget literals by lower-case identifier (a CAM program's
    /// thousands looked up once each).
    literals: HashMap<String, Value>,
}

impl Sample {
    fn new(name: String, program: Program, base: Option<Isometry3<f64>>) -> Sample {
        let literals = program
            .targets()
            .iter()
            .filter_map(|t| {
                let v = t.value.as_ref()?;
                let p = kin::robtarget(
                    v.trans_values(),
                    v.rot_values(),
                    v.robconf_values(),
                    v.extax_values(),
                );
                Some((t.id.to_ascii_lowercase(), p))
            })
            .collect();
        Sample {
            name,
            program,
            base,
            literals,
        }
    }
}

/// Every sample program: each file, and each motion task of the backup
/// (its files read together, its robot where MOC.cfg puts it).
fn samples() -> Vec<Sample> {
    let mut out = Vec::new();
    for name in [
        "fixtures.mod",
        "weld_cell_latin1.mod",
        "cam_contour.mod",
        "control_flow.mod",
        "arc_pendant.mod",
        "service_positions.mod",
        "two_modules.mod",
        "deburr_mixed_eol.modx",
        "inspection_bom.prg",
        "process_lib.sys",
    ] {
        let bytes = std::fs::read(root().join("samples").join(name)).unwrap();
        out.push(Sample::new(
            name.to_string(),
            rapid::parse(name, &bytes).unwrap(),
            None,
        ));
    }
    let tasks = rapid::task::discover(&[root().join("samples/backup_multimove")]).unwrap();
    for task in tasks {
        if task.motion == Some(false) {
            continue;
        }
        let files: Vec<(String, Vec<u8>)> = task
            .modules
            .iter()
            .map(|p| (p.display().to_string(), std::fs::read(p).unwrap()))
            .collect();
        let refs: Vec<(&str, &[u8])> = files
            .iter()
            .map(|(n, b)| (n.as_str(), b.as_slice()))
            .collect();
        out.push(Sample::new(
            task.label(),
            rapid::parse_files(&refs).unwrap(),
            rapidtherm::resolve::arm::base_frame(&task).unwrap(),
        ));
    }
    out
}

/// The module's call for a correction's target, as the rewrite writes
/// it: `RtWarm(p, tool \WObj:=wobj)` (no `\WObj` for `wobj0`), or
/// `RtWarmJ(j)`. `None` for a target that is no literal.
fn call_for(sample: &Sample, c: &Correction) -> Option<(&'static str, Vec<CallArg>)> {
    let program = &sample.program;
    let Some(tool) = &c.tool else {
        let j = program
            .jointtargets()
            .iter()
            .find(|j| j.id.eq_ignore_ascii_case(&c.id))?;
        let v = kin::jointtarget(
            j.robax.each_ref().map(|n| n.value),
            j.extax.each_ref().map(|n| n.value),
        );
        return Some(("RtWarmJ", vec![CallArg::Value(v)]));
    };
    let p = sample.literals.get(&c.id.to_ascii_lowercase())?.clone();
    let tool = match program
        .tools()
        .iter()
        .find(|t| t.name.eq_ignore_ascii_case(tool))
    {
        Some(t) => kin::declared_tool(t),
        None if tool.eq_ignore_ascii_case("tool0") => {
            kin::tool_value(&rapidtherm::robot::ToolFrame::tool0())
        }
        None => panic!("{}: tool {tool} not declared", c.id),
    };
    let mut args = vec![CallArg::Value(p), CallArg::Value(tool)];
    match c.wobj.as_deref() {
        None => {}
        Some(w) if w.eq_ignore_ascii_case("wobj0") => {}
        Some(w) => {
            let w = program
                .wobjs()
                .iter()
                .find(|x| x.name.eq_ignore_ascii_case(w))
                .unwrap_or_else(|| panic!("{}: wobj {w} not declared", c.id));
            args.push(CallArg::Named("WObj".into(), kin::declared_wobj(w)));
        }
    }
    Some(("RtWarm", args))
}

/// How far the interpreter's answer is from the static correction: (mm,
/// degrees) for a robtarget (position, rotation), (0, largest joint
/// difference) for a jointtarget.
fn miss(got: &Value, c: &Correction) -> (f64, f64) {
    let n = got.numbers();
    if c.tool.is_none() {
        let worst = (0..6)
            .map(|i| (n[i] - c.corrected[i]).abs())
            .fold(0.0, f64::max);
        return (0.0, worst);
    }
    let (pose, _, _) = kin::robtarget_parts(got).unwrap();
    let exact = c.exact.unwrap();
    let d = (pose.translation.vector - exact.translation.vector).norm();
    let a = pose.rotation.angle_to(&exact.rotation).to_degrees();
    (d, a)
}

/// What the static path corrects at `when` (a moment, or a schedule
/// until minute `horizon`) on a sample.
fn corrected(sample: &Sample, when: When, horizon: f64) -> Vec<Correction> {
    let warm = warm_robot(Robot::irb140(), &Model::default(), &when, horizon).unwrap();
    let mut options = Options::new(when);
    options.base_frame = sample.base;
    correct(&sample.program, &warm, &options, &mut |_, _| {})
        .unwrap()
        .corrections
}

fn at(m: Moment) -> (When, f64) {
    let horizon = match m {
        Moment::Minute(t) => t.max(1.0),
        Moment::Steady => 1.0,
    };
    (When::At(m), horizon)
}

/// Runs the module for `minutes` of continuous running: a correction
/// every `step` minutes (any target: each brings the state to now).
fn run_for(i: &mut Interp, minutes: f64, step: f64) {
    let end = i.clock().plus(minutes);
    while i.clock().plus(step).minutes() <= end.minutes() + 1e-9 {
        i.advance(step);
        i.call_proc("RtWarmUpdate", &[]).unwrap();
    }
    i.set_clock(end);
    i.call_proc("RtWarmUpdate", &[]).unwrap();
}

/// The worst of several misses.
#[derive(Debug, Default, Clone, Copy)]
struct Worst {
    mm: f64,
    deg: f64,
    targets: usize,
}

impl Worst {
    fn add(&mut self, other: Worst) {
        self.mm = self.mm.max(other.mm);
        self.deg = self.deg.max(other.deg);
        self.targets += other.targets;
    }
}

/// The interpreter's corrections of every corrected target of `sample`
/// at the state it holds, against the static path's `want`, each within
/// `limit` (mm and degrees).
/// At minute 0 (`cold`: the precision the interpreter keeps), each
/// robtarget comes back as it went in (as that precision holds it), bit
/// for bit, and each jointtarget to 1e-9° (single precision: `limit`).
fn against(
    i: &mut Interp,
    sample: &Sample,
    want: &[Correction],
    limit: f64,
    cold: Option<Precision>,
) -> Worst {
    let mut w = Worst::default();
    for c in want {
        if c.exact.is_none() && c.tool.is_some() {
            continue;
        }
        let Some((func, args)) = call_for(sample, c) else {
            continue;
        };
        let (got, _) = i
            .call_func(func, &args)
            .unwrap_or_else(|e| panic!("{} {}: {e:?}", sample.name, c.id));
        if let Some(precision) = cold {
            let CallArg::Value(given) = &args[0] else {
                unreachable!()
            };
            let mut given = given.clone();
            if precision == Precision::Single {
                given.to_single();
            }
            let (g, n) = (given.numbers(), got.numbers());
            if func == "RtWarm" {
                assert_eq!(n, g, "{} {}: minute 0 moves it", sample.name, c.id);
            } else {
                // A jointtarget goes through its flange position and back:
                // in single precision a coordinate holds ~1e-4 mm, its
                // joints ~1e-5°.
                let tol = match precision {
                    Precision::Double => 1e-9,
                    Precision::Single => limit,
                };
                for k in 0..6 {
                    let d = (n[k] - g[k]).abs();
                    assert!(d < tol, "{} {}: {d}°", sample.name, c.id);
                }
            }
        }
        let (d, a) = miss(&got, c);
        assert!(
            d <= limit && a <= limit,
            "{} {} ({:?}): {d} mm, {a} deg",
            sample.name,
            c.id,
            c.time_min
        );
        w.add(Worst {
            mm: d,
            deg: a,
            targets: 1,
        });
    }
    w
}

const MINUTES: [f64; 6] = [0.0, 10.0, 30.0, 60.0, 120.0, 240.0];

/// Continuous running from a cold start, on every sample, in `precision`:
/// the worst miss at each of [`MINUTES`] and at the steady state.
fn continuous(precision: Precision, limit: f64) -> Vec<(Moment, Worst)> {
    let mut worst: Vec<(Moment, Worst)> = MINUTES
        .iter()
        .map(|&m| Moment::Minute(m))
        .chain([Moment::Steady])
        .map(|m| (m, Worst::default()))
        .collect();
    for sample in samples() {
        let mut i = interp(sample.base.unwrap_or_else(Isometry3::identity), start());
        i.set_precision(precision).unwrap();
        // The day's first correction: a cold arm.
        i.call_proc("RtWarmUpdate", &[]).unwrap();
        let mut now = 0.0;
        for (m, w) in &mut worst {
            match *m {
                Moment::Minute(t) => {
                    // A correction every 3 s for the first ten minutes
                    // (the update's series branch), every minute after.
                    run_for(&mut i, t - now, if t <= 10.0 { 0.05 } else { 1.0 });
                    now = t;
                }
                // Two days more: the steady state.
                Moment::Steady => run_for(&mut i, 2880.0, 4.0),
            }
            let (when, horizon) = at(*m);
            let want = corrected(&sample, when, horizon);
            let cold = (*m == Moment::Minute(0.0)).then_some(precision);
            w.add(against(&mut i, &sample, &want, limit, cold));
        }
    }
    worst
}

#[test]
fn the_interpreter_runs_the_module_as_correct_at_corrects_every_sample() {
    let t0 = std::time::Instant::now();
    let worst = continuous(Precision::Double, 1e-3);
    for (m, w) in &worst {
        eprintln!(
            "{m}: {:.2e} mm, {:.2e} deg, {} targets",
            w.mm, w.deg, w.targets
        );
        assert!(w.targets > 100, "{m}: {} targets compared", w.targets);
    }
    eprintln!("{:?}", t0.elapsed());
}

const IDLE_SCHEDULE: &str = "target,time_min,kind,end_min\n,120,idle,180\n";

/// 120 min running, 60 stopped (the program restarted: PP to Main, the
/// clock running on, no correction made), 30 running; on every sample,
/// against `correct --schedule` with that stop as an idle span.
fn with_a_stop(precision: Precision, limit: f64) -> Worst {
    let mut worst = Worst::default();
    for sample in samples() {
        let mut i = interp(sample.base.unwrap_or_else(Isometry3::identity), start());
        i.set_precision(precision).unwrap();
        i.call_proc("RtWarmUpdate", &[]).unwrap();
        run_for(&mut i, 120.0, 1.0);
        let warm = i.global("rtX").unwrap().clone();
        i.restart().unwrap();
        assert_eq!(i.global("rtX"), Some(&warm), "PERS data outlive a restart");
        i.advance(60.0);
        // The first correction after the stop, at minute 180: a gap longer
        // than the module's stop gap, so the arm cooled.
        i.call_proc("RtWarmUpdate", &[]).unwrap();
        run_for(&mut i, 30.0, 1.0);
        let when = When::Schedule {
            schedule: Schedule::read("idle.csv", IDLE_SCHEDULE.as_bytes()).unwrap(),
            joints: None,
            default: Some(Moment::Minute(210.0)),
            source: ScheduleSource::File,
        };
        let want = corrected(&sample, when, 210.0);
        worst.add(against(&mut i, &sample, &want, limit, None));
    }
    worst
}

#[test]
fn a_day_with_a_stop_agrees_with_correct_schedule() {
    let w = with_a_stop(Precision::Double, 1e-3);
    eprintln!(
        "profile: {:.2e} mm, {:.2e} deg, {} targets",
        w.mm, w.deg, w.targets
    );
    assert!(w.targets > 100, "{} targets", w.targets);
}

#[test]
fn in_the_controllers_single_precision_the_module_stays_within_a_micrometre() {
    // Every num the module stores and every operation's result rounded to
    // IEEE single precision, as the controller keeps num: the targets'
    // own numbers too (a coordinate of 1000 mm holds 6e-5 mm).
    let worst = continuous(Precision::Single, 1e-3);
    for (m, w) in &worst {
        eprintln!(
            "single {m}: {:.2e} mm, {:.2e} deg, {} targets",
            w.mm, w.deg, w.targets
        );
    }
    let w = with_a_stop(Precision::Single, 1e-3);
    eprintln!("single profile: {:.2e} mm, {:.2e} deg", w.mm, w.deg);
}

/// Operations per call (expression nodes, statements, built-in calls):
/// the module's cost on the controller, as docs/runtime.md states it.
#[test]
fn the_operations_per_call_are_counted() {
    let sample = &samples()[0];
    let want = corrected(sample, When::At(Moment::Minute(60.0)), 60.0);
    let mut i = interp(Isometry3::identity(), start());
    i.call_proc("RtWarmUpdate", &[]).unwrap();
    run_for(&mut i, 60.0, 1.0);
    let mut seen = std::collections::BTreeMap::new();
    for c in &want {
        let Some((func, args)) = call_for(sample, c) else {
            continue;
        };
        // A correction 3 s after the last: the state is carried forward.
        i.advance(0.05);
        let (_, ops) = i.call_func(func, &args).unwrap();
        let kind = match (func, args.len()) {
            ("RtWarm", 3) => "RtWarm \\WObj",
            ("RtWarm", _) => "RtWarm",
            _ => "RtWarmJ",
        };
        seen.insert(kind, ops);
    }
    for (k, ops) in &seen {
        eprintln!(
            "{k}: {} operations ({} expressions, {} statements, {} built-in calls)",
            ops.total(),
            ops.expressions,
            ops.statements,
            ops.builtins
        );
    }
    assert_eq!(seen.len(), 3, "{seen:?}");
    // Bringing the state to now, alone.
    i.advance(0.05);
    let update = i.call_proc("RtWarmUpdate", &[]).unwrap();
    eprintln!("RtWarmUpdate: {} operations", update.total());
    assert!(update.total() < seen["RtWarmJ"].total());
    // A call in the same second as the last advances nothing: cheaper.
    let c = want.iter().find(|c| c.tool.is_some()).unwrap();
    let (func, args) = call_for(sample, c).unwrap();
    let (_, again) = i.call_func(func, &args).unwrap();
    assert!(again.total() < seen["RtWarm"].total().min(seen["RtWarm \\WObj"].total()));
}

/// The interpreter reads a program as the reader reads it, the fast lane
/// on: inline moves one after another, robtarget declarations and an
/// array of robtarget literals, which the reader holds compactly, run as
/// the grammar reads them (the literals' x written by hand, in the order
/// the moves reach them).
#[test]
fn the_interpreter_runs_what_the_fast_lane_holds() {
    let lit = |x: u32| format!("[[{x},0,500],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]]");
    let src = format!(
        "MODULE m\n  CONST robtarget pA := {};\n  CONST robtarget pB := {};\n  CONST robtarget pScan{{2}} := [\n    {},\n    {}];\n  PROC main()\n    MoveL {}, v100, fine, tool0;\n    MoveL {}, v100, fine, tool0;\n    MoveL pA, v100, fine, tool0;\n    MoveL pB, v100, fine, tool0;\n    FOR i FROM 1 TO 2 DO\n      MoveL pScan{{i}}, v100, fine, tool0;\n    ENDFOR\n  ENDPROC\nENDMODULE\n",
        lit(1),
        lit(2),
        lit(3),
        lit(4),
        lit(5),
        lit(6)
    );
    // The reader holds the six literals in its runs.
    let read = rapid::parse("m.mod", src.as_bytes()).unwrap();
    assert_eq!(read.targets().in_runs(), 6);
    let mut i = Interp::load(
        &[("m.mod", src.as_bytes())],
        Kinematics::new(Robot::irb140()),
    )
    .unwrap();
    i.call_proc("main", &[]).unwrap();
    let xs: Vec<f64> = (i.moves().iter())
        .map(|m| m.targets.last().unwrap().numbers()[0])
        .collect();
    assert_eq!(xs, [5.0, 6.0, 1.0, 2.0, 3.0, 4.0]);
}
