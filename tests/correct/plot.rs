//! `correct --plot`: the pictures of a correction. On a small program whose
//! targets stand at known places (in two work objects): the SVG is
//! well-formed, one dot per corrected target at the right place in one
//! frame with both axes scaled alike, the largest correction hottest, the
//! time axis the schedule's; and on the command line, nothing written to
//! the folder when the run fails.

use super::rapidtherm;
use quick_xml::events::Event;
use rapidtherm::correct::plot::{pictures, scale_colour, Picture, FILES};
use rapidtherm::correct::{correct, Options, Outcome, ScheduleSource, When};
use rapidtherm::model::{Model, Moment, WarmRobot};
use rapidtherm::rapid;
use rapidtherm::robot::Robot;
use rapidtherm::schedule::Schedule;
use std::path::PathBuf;

/// p1, p2 in wobj0 and p3 in a work object 100 mm along x: in the world
/// p1 (400, 0), p2 (500, 0), p3 (400, 100), all at z 500. pE is written
/// with a constant: left alone, placed at (500, 100, 400).
const PROGRAM: &str = "MODULE m
  CONST num nX := 500;
  PERS wobjdata wShift := [FALSE, TRUE, \"\", [[100, 0, 0], [1, 0, 0, 0]], [[0, 0, 0], [1, 0, 0, 0]]];
  CONST robtarget p1 := [[400, 0, 500], [0, 0, 1, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget p2 := [[500, 0, 500], [0, 0, 1, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget p3 := [[300, 100, 500], [0, 0, 1, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pE := [[nX, 100, 400], [0, 0, 1, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]];
  PROC main()
    MoveL p1, v100, fine, tool0;
    MoveL p2, v100, fine, tool0;
    MoveL p3, v100, fine, tool0\\WObj:=wShift;
    MoveL pE, v100, fine, tool0;
  ENDPROC
ENDMODULE
";

fn outcome(when: When) -> Outcome {
    let program = rapid::parse("m.mod", PROGRAM.as_bytes()).unwrap();
    let warm = WarmRobot::new(Robot::irb140(), &Model::default(), 120.0).unwrap();
    correct(&program, &warm, &Options::new(when), &mut |_, _| {}).unwrap()
}

fn at_120() -> Outcome {
    outcome(When::At(Moment::Minute(120.0)))
}

fn picture<'a>(all: &'a [Picture], name: &str) -> &'a str {
    &all.iter().find(|p| p.name == name).unwrap().svg
}

/// Every element's attributes, by element name, after checking that the
/// whole text is well-formed XML (every element closed).
fn elements(svg: &str) -> Vec<(String, Vec<(String, String)>)> {
    let mut reader = quick_xml::Reader::from_str(svg);
    reader.config_mut().check_end_names = true;
    let mut out = Vec::new();
    let mut depth = 0i32;
    loop {
        let event = reader.read_event().expect("well-formed XML");
        let e = match event {
            Event::Eof => break,
            Event::End(_) => {
                depth -= 1;
                continue;
            }
            Event::Start(e) => {
                depth += 1;
                e
            }
            Event::Empty(e) => e,
            _ => continue,
        };
        let attrs = e
            .attributes()
            .map(|a| {
                let a = a.expect("well-formed attribute");
                (
                    String::from_utf8(a.key.as_ref().to_vec()).unwrap(),
                    a.unescape_value().unwrap().into_owned(),
                )
            })
            .collect();
        out.push((
            String::from_utf8(e.name().as_ref().to_vec()).unwrap(),
            attrs,
        ));
    }
    assert_eq!(depth, 0, "every element closed");
    out
}

/// The dots: (cx, cy, fill) of every circle.
fn dots(svg: &str) -> Vec<(f64, f64, String)> {
    elements(svg)
        .into_iter()
        .filter(|(name, _)| name == "circle")
        .map(|(_, attrs)| {
            let get = |k: &str| attrs.iter().find(|(a, _)| a == k).unwrap().1.clone();
            (
                get("cx").parse().unwrap(),
                get("cy").parse().unwrap(),
                get("fill"),
            )
        })
        .collect()
}

/// Where on the scale (0 coldest, 1 hottest) a dot's colour is.
fn scale_place(fill: &str) -> f64 {
    let hex = fill.trim_start_matches('#');
    let c = |i: usize| i32::from_str_radix(&hex[i..i + 2], 16).unwrap();
    let (r, g, b) = (c(0), c(2), c(4));
    (0..=1000)
        .map(|i| i as f64 / 1000.0)
        .min_by_key(|&f| {
            let s = scale_colour(f);
            (s.0 as i32 - r).pow(2) + (s.1 as i32 - g).pow(2) + (s.2 as i32 - b).pow(2)
        })
        .unwrap()
}

#[test]
fn the_targets_are_placed_in_one_frame_with_equal_scales() {
    let out = at_120();
    assert_eq!(out.corrections.len(), 3);
    assert_eq!(out.left_alone.len(), 1);
    let world = |id: &str| {
        out.corrections
            .iter()
            .find(|c| c.id == id)
            .unwrap()
            .world_mm
            .unwrap()
    };
    assert_eq!(world("p3"), [400.0, 100.0, 500.0], "wShift placed");
    assert_eq!(out.left_alone[0].world_mm, Some([500.0, 100.0, 400.0]));

    let all = pictures(&out, "m.mod").unwrap();
    assert_eq!(
        all.iter().map(|p| p.name).collect::<Vec<_>>(),
        FILES.to_vec()
    );
    let top = dots(picture(&all, "top.svg"));
    assert_eq!(top.len(), 3, "one dot per corrected target");
    // p2 is the one right of the others, p3 the one above (SVG y down).
    let p2 = top.iter().max_by(|a, b| a.0.total_cmp(&b.0)).unwrap();
    let p3 = top.iter().min_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
    let p1 = top
        .iter()
        .find(|d| !std::ptr::eq(*d, p2) && !std::ptr::eq(*d, p3))
        .unwrap();
    // 100 mm along x and 100 mm along y are as many pixels.
    assert!((p1.1 - p2.1).abs() <= 1.0 && (p1.0 - p3.0).abs() <= 1.0);
    let (dx, dy) = (p2.0 - p1.0, p1.1 - p3.1);
    assert!(dx > 50.0 && (dx - dy).abs() <= 1.0, "dx {dx} dy {dy}");

    // The side view: x across (the targets spread as much along x as along
    // y, so x), z up; p1 and p3 are one above the other in it.
    let side = picture(&all, "side.svg");
    assert!(side.contains("x-z"), "the side view says which");
    assert_eq!(dots(side).len(), 3);

    // Every dot lies inside the picture, left of the colour scale and
    // above the legend.
    for svg in [picture(&all, "top.svg"), side] {
        for (x, y, _) in dots(svg) {
            assert!(x > 80.0 && x < 1100.0 - 150.0, "x {x}");
            assert!(y > 30.0 && y < 820.0 - 58.0 - 40.0, "y {y}");
        }
    }
}

#[test]
fn the_largest_correction_is_the_hottest() {
    let out = at_120();
    let all = pictures(&out, "m.mod").unwrap();
    let mut sizes: Vec<f64> = out
        .corrections
        .iter()
        .map(|c| c.correction_norm_mm)
        .collect();
    sizes.sort_by(f64::total_cmp);
    assert!(sizes[2] - sizes[0] > 1e-3, "the targets differ: {sizes:?}");
    for name in ["top.svg", "side.svg", "drift.svg"] {
        let mut places: Vec<f64> = dots(picture(&all, name))
            .iter()
            .map(|d| scale_place(&d.2))
            .collect();
        places.sort_by(f64::total_cmp);
        assert!(places[0] < 0.01, "{name}: the smallest is coldest");
        assert!(places[2] > 0.99, "{name}: the largest is hottest");
        let expected = (sizes[1] - sizes[0]) / (sizes[2] - sizes[0]);
        assert!((places[1] - expected).abs() < 0.02, "{name}: {places:?}");
    }
    // The drift picture in program order, at one minute: p1, p2, p3 from
    // left to right with their own sizes.
    let drift = picture(&all, "drift.svg");
    assert!(drift.contains("target in program order"));
    let d = dots(drift);
    let size = |id: &str| {
        out.corrections
            .iter()
            .find(|c| c.id == id)
            .unwrap()
            .correction_norm_mm
    };
    let hottest = d
        .iter()
        .max_by(|a, b| scale_place(&a.2).total_cmp(&scale_place(&b.2)))
        .unwrap();
    let order = ["p1", "p2", "p3"];
    let mut by_x = d.clone();
    by_x.sort_by(|a, b| a.0.total_cmp(&b.0));
    let biggest = order
        .iter()
        .max_by(|a, b| size(a).total_cmp(&size(b)))
        .unwrap();
    let at = order.iter().position(|id| id == biggest).unwrap();
    assert_eq!(by_x[at].0, hottest.0, "the hottest dot is {biggest}'s");
    // And higher on the picture (SVG y down) the larger.
    let mut by_height = d.clone();
    by_height.sort_by(|a, b| b.1.total_cmp(&a.1));
    let mut by_size = order.to_vec();
    by_size.sort_by(|a, b| size(a).total_cmp(&size(b)));
    for (dot, id) in by_height.iter().zip(&by_size) {
        let x = by_x.iter().position(|b| b.0 == dot.0).unwrap();
        assert_eq!(order[x], *id);
    }
}

#[test]
fn the_drift_runs_along_the_schedules_minutes() {
    let csv = "target,time_min\np1,10\np2,40\np3,25\npE,5\n";
    let schedule = Schedule::read("s.csv", csv.as_bytes()).unwrap();
    let out = outcome(When::Schedule {
        schedule,
        joints: None,
        default: None,
        source: ScheduleSource::File,
    });
    let all = pictures(&out, "m.mod").unwrap();
    let drift = picture(&all, "drift.svg");
    assert!(drift.contains("minute the target is reached"));
    assert!(drift.contains("reached at minutes 10–40"));
    let d = dots(drift);
    assert_eq!(d.len(), 3);
    // p1 (minute 10), p3 (25), p2 (40) from left to right, spaced as the
    // minutes are.
    let mut xs: Vec<f64> = d.iter().map(|p| p.0).collect();
    xs.sort_by(f64::total_cmp);
    let ratio = (xs[1] - xs[0]) / (xs[2] - xs[0]);
    assert!((ratio - 0.5).abs() < 0.01, "{xs:?}");
    // The path joins the targets in the order they are reached.
    assert!(picture(&all, "top.svg").contains("in the order they are reached"));
}

#[test]
fn an_outcome_without_targets_still_draws() {
    let program = rapid::parse(
        "e.mod",
        b"MODULE e\n  PROC main()\n    WaitTime 1;\n  ENDPROC\nENDMODULE\n",
    )
    .unwrap();
    let warm = WarmRobot::new(Robot::irb140(), &Model::default(), 60.0).unwrap();
    let out = correct(
        &program,
        &warm,
        &Options::new(When::At(Moment::Steady)),
        &mut |_, _| {},
    )
    .unwrap();
    for p in pictures(&out, "e.mod").unwrap() {
        assert!(dots(&p.svg).is_empty());
        assert!(p.svg.contains("no target corrected"), "{}", p.name);
    }
}

fn sample(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("samples")
        .join(name)
}

#[test]
fn the_folder_is_made_and_each_task_named() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("m.mod"), PROGRAM).unwrap();
    let out = rapidtherm(
        &["correct", "m.mod", "--at", "120", "--plot", "a/b"],
        dir.path(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut names: Vec<String> = std::fs::read_dir(dir.path().join("a/b"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["drift.svg", "side.svg", "top.svg"]);
    // The report is printed as without --plot.
    assert!(String::from_utf8_lossy(&out.stdout).contains("p1"));

    let backup = sample("backup_multimove");
    let out = rapidtherm(
        &[
            "correct",
            backup.to_str().unwrap(),
            "--task",
            "T_ROB2",
            "--at",
            "120",
            "--check",
            "--plot",
            "pics",
        ],
        dir.path(),
    );
    assert_eq!(
        out.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut names: Vec<String> = std::fs::read_dir(dir.path().join("pics"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["T_ROB2-drift.svg", "T_ROB2-side.svg", "T_ROB2-top.svg"]
    );
    // T_ROB2 stands at x = 1600 mm, turned about z: its targets are drawn
    // where the cell has them, not in its base frame.
    let top = std::fs::read_to_string(dir.path().join("pics/T_ROB2-top.svg")).unwrap();
    assert!(
        top.contains("\n1100\n") && !top.contains("\n400\n"),
        "world x"
    );
}

/// A CAM program written with `-o` at one minute is what the streaming
/// path takes; with `--plot` the pictures are still drawn, never skipped.
#[test]
fn writing_a_cam_program_with_plots_draws_them() {
    let dir = tempfile::tempdir().unwrap();
    let cam = sample("cam_contour.mod");
    let out = rapidtherm(
        &[
            "correct",
            cam.to_str().unwrap(),
            "--at",
            "120",
            "-o",
            "warm.mod",
            "--plot",
            "pics",
        ],
        dir.path(),
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let top = std::fs::read_to_string(dir.path().join("pics/top.svg")).unwrap();
    assert_eq!(dots(&top).len(), 5252);
    let streamed = rapidtherm(
        &[
            "correct",
            cam.to_str().unwrap(),
            "--at",
            "120",
            "-o",
            "plain.mod",
        ],
        dir.path(),
    );
    assert!(streamed.status.success());
    assert_eq!(
        std::fs::read(dir.path().join("warm.mod")).unwrap(),
        std::fs::read(dir.path().join("plain.mod")).unwrap()
    );
}

#[test]
fn a_failed_run_writes_nothing_into_the_folder() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("m.mod"), PROGRAM).unwrap();
    std::fs::write(
        dir.path().join("bad.mod"),
        PROGRAM.replace("tool0\\WObj:=wShift", "tNone\\WObj:=wShift"),
    )
    .unwrap();
    // An input error (an unknown tool).
    let out = rapidtherm(
        &["correct", "bad.mod", "--at", "120", "--plot", "pics"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(!dir.path().join("pics").exists());
    // A write that fails after the correction (-o into no folder).
    let out = rapidtherm(
        &[
            "correct",
            "m.mod",
            "--at",
            "120",
            "-o",
            "no/such/out.mod",
            "--plot",
            "pics",
        ],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(!dir.path().join("pics").exists());
    // A folder that is a file.
    let out = rapidtherm(
        &["correct", "m.mod", "--at", "120", "--plot", "m.mod"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("not a folder"));
    assert_eq!(
        std::fs::read_to_string(dir.path().join("m.mod")).unwrap(),
        PROGRAM
    );
}
