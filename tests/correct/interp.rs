//! The project runs what it writes: the controller module of `correct
//! --runtime`, executed by the project's own RAPID interpreter
//! (`interp`), agrees with the static correction (`correct
//! --at`, `correct --schedule`) on every sample's every target, by the
//! module's table (the path the rewrite gives every target the program
//! names) and by its slower path (the controller's joints, for targets
//! made at run time).

use nalgebra::{Isometry3, UnitQuaternion};
use rapidtherm::correct::job::warm_robot;
use rapidtherm::correct::runtime::table::{Table, TableRows};
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
/// model, its base frame turned by `base` in the world, with `rows`.
pub(super) fn module(base: UnitQuaternion<f64>, rows: &TableRows) -> String {
    let spec = RuntimeSpec::new(&Robot::irb140(), &Model::default(), base).unwrap();
    let opts = ModuleOptions {
        name: "RtWarm".into(),
        version: "test".into(),
        heating_source: "the embedded default".into(),
        model: "the embedded default".into(),
    };
    module_text(&spec, rows, &opts)
}

/// An interpreter holding `text`, the module of a robot standing at
/// `base` in the world, its clock at `start`.
fn interp_with(text: &str, base: Isometry3<f64>, start: Clock) -> Interp {
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
    /// thousands looked up once each), with their number in the program.
    literals: HashMap<String, (usize, Value)>,
}

impl Sample {
    fn new(name: String, program: Program, base: Option<Isometry3<f64>>) -> Sample {
        let literals = program
            .targets()
            .iter()
            .enumerate()
            .filter_map(|(n, t)| {
                let v = t.value.as_ref()?;
                let p = kin::robtarget(
                    v.trans_values(),
                    v.rot_values(),
                    v.robconf_values(),
                    v.extax_values(),
                );
                Some((t.id.to_ascii_lowercase(), (n, p)))
            })
            .collect();
        Sample {
            name,
            program,
            base,
            literals,
        }
    }

    fn base(&self) -> Isometry3<f64> {
        self.base.unwrap_or_else(Isometry3::identity)
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
        "stationary_glue.mod",
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

/// A sample's module loaded, with the table's row of each corrected
/// target (by identifier, tool and work object; jointtargets by
/// identifier), as the rewrite numbers them.
struct Loaded {
    interp: Interp,
    rows: HashMap<(String, Option<String>, Option<String>), usize>,
}

/// The module for `sample` (its table holding every target `want`
/// names), loaded, its clock at `start`.
fn load(sample: &Sample, want: &[Correction], start: Clock) -> Loaded {
    let robot = Robot::irb140();
    let base = sample.base();
    let spec = RuntimeSpec::new(&robot, &Model::default(), base.rotation).unwrap();
    let mut table = Table::new(&sample.program, &robot, &spec, &base);
    let mut rows = HashMap::new();
    for c in want {
        let id = c.id.to_ascii_lowercase();
        let row = match &c.tool {
            Some(tool) => {
                let Some((n, _)) = sample.literals.get(&id) else {
                    continue;
                };
                table.robtarget_row(*n, Some(tool), c.wobj.as_deref())
            }
            None => {
                let Some(j) = sample
                    .program
                    .jointtargets()
                    .iter()
                    .position(|j| j.id.eq_ignore_ascii_case(&c.id))
                else {
                    continue;
                };
                table.jointtarget_row(j)
            }
        };
        if let Some(r) = row {
            rows.insert((id, c.tool.clone(), c.wobj.clone()), r);
        }
    }
    let text = module(base.rotation, &table.rows);
    Loaded {
        interp: interp_with(&text, base, start),
        rows,
    }
}

/// The module's calls for a correction's target, as the rewrite writes
/// them: `RtWarmT(p, row, tool \WObj:=wobj)` (no `\WObj` for `wobj0`) and
/// `RtWarm(p, tool \WObj:=wobj)`; `RtWarmJT(j, row)` for a jointtarget
/// (its slower path, `RtWarmJ`, is the controller's configuration's,
/// held to its own rule in tests/correct/interp_controller.rs). Empty
/// for a target that is no literal.
fn calls_for(
    sample: &Sample,
    loaded: &Loaded,
    c: &Correction,
) -> Vec<(&'static str, Vec<CallArg>)> {
    let program = &sample.program;
    let id = c.id.to_ascii_lowercase();
    let row = loaded
        .rows
        .get(&(id.clone(), c.tool.clone(), c.wobj.clone()));
    let Some(tool) = &c.tool else {
        let Some(j) = program
            .jointtargets()
            .iter()
            .find(|j| j.id.eq_ignore_ascii_case(&c.id))
        else {
            return Vec::new();
        };
        let v = kin::jointtarget(
            j.robax.each_ref().map(|n| n.value),
            j.extax.each_ref().map(|n| n.value),
        );
        let row = *row.expect("every jointtarget has a row");
        return vec![(
            "RtWarmJT",
            vec![CallArg::Value(v), CallArg::Value(Value::Num(row as f64))],
        )];
    };
    let Some((_, p)) = sample.literals.get(&id) else {
        return Vec::new();
    };
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
    let wobj = match c.wobj.as_deref() {
        None => None,
        Some(w) if w.eq_ignore_ascii_case("wobj0") => None,
        Some(w) => {
            let w = program
                .wobjs()
                .iter()
                .find(|x| x.name.eq_ignore_ascii_case(w))
                .unwrap_or_else(|| panic!("{}: wobj {w} not declared", c.id));
            Some(CallArg::Named("WObj".into(), kin::declared_wobj(w)))
        }
    };
    let mut out = Vec::new();
    if let Some(&r) = row {
        let mut args = vec![
            CallArg::Value(p.clone()),
            CallArg::Value(Value::Num(r as f64)),
            CallArg::Value(tool.clone()),
        ];
        args.extend(wobj.clone());
        out.push(("RtWarmT", args));
    }
    let mut args = vec![CallArg::Value(p.clone()), CallArg::Value(tool)];
    args.extend(wobj);
    out.push(("RtWarm", args));
    out
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

/// A call of the module that corrects nothing of interest: it brings
/// the state to now where the last update is older than the module's
/// update period (10 s), as every move's call does.
pub(super) fn touch(i: &mut Interp) {
    let j = kin::jointtarget([0.0, 0.0, 0.0, 0.0, 30.0, 0.0], [9e9; 6]);
    i.call_func(
        "RtWarmJT",
        &[CallArg::Value(j), CallArg::Value(Value::Num(1.0))],
    )
    .unwrap();
}

/// Runs the module for `minutes` of continuous running: a move every
/// `step` minutes (at least the update period, so that each brings the
/// state to now), the last at the end.
fn run_for(i: &mut Interp, minutes: f64, step: f64) {
    let steps = (minutes / step).round() as usize;
    for _ in 0..steps {
        i.advance(step);
        touch(i);
    }
}

/// The worst of several misses.
#[derive(Debug, Default, Clone, Copy)]
struct Worst {
    mm: f64,
    deg: f64,
    targets: usize,
    /// Of those, by the table.
    by_table: usize,
}

impl Worst {
    fn add(&mut self, other: Worst) {
        self.mm = self.mm.max(other.mm);
        self.deg = self.deg.max(other.deg);
        self.targets += other.targets;
        self.by_table += other.by_table;
    }
}

/// The interpreter's corrections of every corrected target of `sample`
/// at the state it holds, by each of the module's paths, against the
/// static path's `want`, each within `limit` (mm and degrees).
/// At minute 0 (`cold`: the precision the interpreter keeps), each
/// robtarget comes back as it went in (as that precision holds it), bit
/// for bit, and each jointtarget too.
fn against(
    loaded: &mut Loaded,
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
        for (func, args) in calls_for(sample, loaded, c) {
            let (got, _) = loaded
                .interp
                .call_func(func, &args)
                .unwrap_or_else(|e| panic!("{} {} {func}: {e:?}", sample.name, c.id));
            if let Some(precision) = cold {
                let CallArg::Value(given) = &args[0] else {
                    unreachable!()
                };
                let mut given = given.clone();
                if precision == Precision::Single {
                    given.to_single();
                }
                assert_eq!(
                    got.numbers(),
                    given.numbers(),
                    "{} {} {func}: minute 0 moves it",
                    sample.name,
                    c.id
                );
            }
            let (d, a) = miss(&got, c);
            assert!(
                d <= limit && a <= limit,
                "{} {} {func} ({:?}): {d} mm, {a} deg",
                sample.name,
                c.id,
                c.time_min
            );
            w.add(Worst {
                mm: d,
                deg: a,
                targets: 1,
                by_table: usize::from(func.ends_with('T')),
            });
        }
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
        let (when, horizon) = at(Moment::Minute(60.0));
        let mut loaded = load(&sample, &corrected(&sample, when, horizon), start());
        loaded.interp.set_precision(precision).unwrap();
        // The day's first correction: a cold arm.
        touch(&mut loaded.interp);
        let mut now = 0.0;
        for (m, w) in &mut worst {
            match *m {
                Moment::Minute(t) => {
                    // A move every 12 s for the first ten minutes (the
                    // update's series branch), every minute after.
                    run_for(
                        &mut loaded.interp,
                        t - now,
                        if t <= 10.0 { 0.2 } else { 1.0 },
                    );
                    now = t;
                }
                // Two days more: the steady state.
                Moment::Steady => run_for(&mut loaded.interp, 2880.0, 4.0),
            }
            let (when, horizon) = at(*m);
            let want = corrected(&sample, when, horizon);
            let cold = (*m == Moment::Minute(0.0)).then_some(precision);
            w.add(against(&mut loaded, &sample, &want, limit, cold));
        }
    }
    worst
}

#[test]
fn the_interpreter_runs_the_module_as_correct_at_corrects_every_sample() {
    let worst = continuous(Precision::Double, 1e-3);
    for (m, w) in &worst {
        eprintln!(
            "{m}: {:.2e} mm, {:.2e} deg, {} calls ({} by the table)",
            w.mm, w.deg, w.targets, w.by_table
        );
        assert!(w.targets > 100, "{m}: {} targets compared", w.targets);
        assert!(w.by_table > 100, "{m}: {} by the table", w.by_table);
    }
}

const IDLE_SCHEDULE: &str = "target,time_min,kind,end_min\n,120,idle,180\n";

/// 120 min running, 60 stopped (the program restarted: PP to Main, the
/// clock running on, no correction made), 30 running; on every sample,
/// against `correct --schedule` with that stop as an idle span.
fn with_a_stop(precision: Precision, limit: f64) -> Worst {
    let mut worst = Worst::default();
    for sample in samples() {
        let (when, horizon) = at(Moment::Minute(60.0));
        let mut loaded = load(&sample, &corrected(&sample, when, horizon), start());
        let i = &mut loaded.interp;
        i.set_precision(precision).unwrap();
        touch(i);
        run_for(i, 120.0, 1.0);
        i.restart().unwrap();
        i.advance(60.0);
        // The first correction after the stop, at minute 180: a gap longer
        // than the module's stop gap, so the arm cooled.
        touch(i);
        run_for(i, 30.0, 1.0);
        let when = When::Schedule {
            schedule: Schedule::read("idle.csv", IDLE_SCHEDULE.as_bytes()).unwrap(),
            joints: None,
            default: Some(Moment::Minute(210.0)),
            source: ScheduleSource::File,
        };
        let want = corrected(&sample, when, 210.0);
        worst.add(against(&mut loaded, &sample, &want, limit, None));
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

/// The most operations a move's call by the table may cost (expression
/// nodes, statements, built-in calls, as the interpreter counts them):
/// the budget of issue 48, with no CalcJointT.
const TABLE_BUDGET: u64 = 100;

/// Operations per call: the module's cost on the controller, as
/// docs/runtime.md states it.
#[test]
fn the_operations_per_call_are_counted() {
    let sample = samples()
        .into_iter()
        .find(|s| s.name == "fixtures.mod")
        .unwrap();
    let want = corrected(&sample, When::At(Moment::Minute(60.0)), 60.0);
    let mut loaded = load(&sample, &want, start());
    touch(&mut loaded.interp);
    run_for(&mut loaded.interp, 60.0, 1.0);
    let mut seen = std::collections::BTreeMap::new();
    for c in &want {
        for (func, args) in calls_for(&sample, &loaded, c) {
            // A move 1 s after the last: within the update period, the
            // state as it is.
            loaded.interp.advance(1.0 / 60.0);
            let (_, ops) = loaded.interp.call_func(func, &args).unwrap();
            let wobj = if args.len() > 3 || (func == "RtWarm" && args.len() > 2) {
                " \\WObj"
            } else {
                ""
            };
            seen.insert(format!("{func}{wobj}"), ops);
        }
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
    for k in ["RtWarmT", "RtWarmT \\WObj", "RtWarmJT"] {
        let ops = seen
            .get(k)
            .unwrap_or_else(|| panic!("{k} not called: {seen:?}"));
        assert!(ops.total() <= TABLE_BUDGET, "{k}: {ops:?}");
    }
    // The call that brings the state to now (once per update period).
    loaded.interp.advance(0.2);
    let j = kin::jointtarget([0.0, 0.0, 0.0, 0.0, 30.0, 0.0], [9e9; 6]);
    let (_, update) = loaded
        .interp
        .call_func(
            "RtWarmJT",
            &[CallArg::Value(j), CallArg::Value(Value::Num(1.0))],
        )
        .unwrap();
    eprintln!("RtWarmJT with the update: {} operations", update.total());
    assert!(update.total() > seen["RtWarmJT"].total());
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
