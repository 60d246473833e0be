//! A target moved to with several tools or work objects (the glue cell of
//! `tests/cmd/correct_data/glue_cell.mod`: a gripper and a glue gun both
//! park at `pHome`, `pPick` is the same point in two fixtures). Before, one
//! such target stopped the whole run. Now the first use decides, every
//! other use is reported with where the warm robot lands there, and on
//! request the target is split into copies, each right for its own pair.
//! The residuals are checked against an oracle built from the robot's own
//! kinematics, not the correction's bookkeeping.

use nalgebra::Isometry3;
use rapidtherm::correct::{correct, Options, Outcome, When};
use rapidtherm::model::warm::{Moment, WarmRobot};
use rapidtherm::model::Model;
use rapidtherm::rapid::{self, Program};
use rapidtherm::resolve::{target_pose, usages, uses_by_frames, Frames};
use rapidtherm::robot::Robot;
use rapidtherm::thermal::{default_profile, HeatingProfile};
use std::path::PathBuf;

const MINUTE: f64 = 120.0;

fn glue_cell() -> Vec<u8> {
    std::fs::read(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/cmd/correct_data/glue_cell.mod"),
    )
    .unwrap()
}

fn run(bytes: &[u8], minute: f64, split: bool) -> (Program, Outcome) {
    let program = rapid::parse("glue_cell.mod", bytes).unwrap();
    let warm = WarmRobot::new(Robot::irb140(), &Model::default(), minute).unwrap();
    let options = Options {
        split_shared: split,
        ..Options::new(When::At(Moment::Minute(minute)))
    };
    let outcome = correct(&program, &warm, &options, &mut |_, _| {}).unwrap();
    (program, outcome)
}

/// Where the TCP of the warm robot at `MINUTE` lands, in the work object,
/// when the controller (nominal IK, the target's robconf) is sent target
/// `id` of `program` with this tool and work object.
fn lands(program: &Program, id: &str, tool: &str, wobj: &str) -> Isometry3<f64> {
    let robot = Robot::irb140();
    let temps = default_profile().temps_at(MINUTE).unwrap();
    let scales = Model::default().thermal.scales(&temps);
    let frames = Frames::of_program(program).unwrap();
    let (tool, wobj) = (
        frames.tool(Some(tool)).unwrap(),
        frames.wobj(Some(wobj)).unwrap(),
    );
    let (sent, conf) = target_pose(program, &program.target(id).unwrap())
        .unwrap()
        .unwrap();
    let flange = rapidtherm::robot::frames::flange_of_target(&sent, tool, wobj).unwrap();
    let q = robot.ik_conf(&flange, &conf).unwrap();
    rapidtherm::robot::frames::target_of_flange(&robot.fk_scaled(&q, &scales), tool, wobj).unwrap()
}

fn cold_pose(program: &Program, id: &str) -> Isometry3<f64> {
    target_pose(program, &program.target(id).unwrap())
        .unwrap()
        .unwrap()
        .0
}

fn off(a: &Isometry3<f64>, b: &Isometry3<f64>) -> f64 {
    (a.translation.vector - b.translation.vector).norm()
}

/// Before: "target pHome is used with tool tGripper / wobj wobj0 ... and
/// with tool tGlueGun ...: one robtarget cannot be corrected for both",
/// and nothing of the program was corrected.
#[test]
fn the_first_use_decides_and_every_other_use_is_reported() {
    let bytes = glue_cell();
    let (program, outcome) = run(&bytes, MINUTE, false);
    // pHome is corrected exactly as if the gripper were its only tool.
    let gripper_only = String::from_utf8(bytes.clone()).unwrap().replace(
        "MoveJ pHome, v1000, z50, tGlueGun;",
        "MoveJ pHome, v1000, z50, tGripper;",
    );
    let (_, alone) = run(gripper_only.as_bytes(), MINUTE, false);
    let exact = |o: &Outcome| {
        o.corrections
            .iter()
            .find(|c| c.id == "pHome")
            .unwrap()
            .exact
            .unwrap()
    };
    assert_eq!(exact(&outcome), exact(&alone));
    assert!(alone.shared.iter().all(|u| u.id != "pHome"));

    // Every use with another pair than its target's first has its line.
    let uses = usages(&program);
    let mut expected = 0;
    for (&i, list) in &uses {
        for group in uses_by_frames(list).iter().skip(1) {
            for u in group {
                expected += 1;
                let id = &program.targets().at(i).id;
                assert!(
                    outcome
                        .shared
                        .iter()
                        .any(|s| &s.id == id && s.other.line == u.line),
                    "{id} at line {} not reported",
                    u.line
                );
            }
        }
    }
    assert_eq!(outcome.shared.len(), expected);
    assert_eq!(expected, 8);

    // The residual is where the warm robot really lands: the corrected
    // program, driven by the controller with the other use's tool.
    let corrected = rapid::parse("warm.mod", &outcome.outputs[0]).unwrap();
    let home = outcome.shared.iter().find(|s| s.id == "pHome").unwrap();
    assert_eq!(
        (home.other.tool.as_str(), home.other.line),
        ("tGlueGun", 26)
    );
    assert_eq!(
        (home.corrected_for.tool.as_str(), home.corrected_for.line),
        ("tGripper", 19)
    );
    let glue = off(
        &lands(&corrected, "pHome", "tGlueGun", "wobj0"),
        &cold_pose(&program, "pHome"),
    );
    let r = home.residual_mm.unwrap();
    // The written numbers hold 0.001 mm; the reported residual is of the
    // exact correction.
    assert!((r - glue).abs() < 0.001, "reported {r}, lands {glue}");
    assert!(r > 0.005, "a tool 65 mm longer lands {r} mm off");
    // ... while the gripper, its first use, lands where it should.
    let grip = off(
        &lands(&corrected, "pHome", "tGripper", "wobj0"),
        &cold_pose(&program, "pHome"),
    );
    assert!(grip < 0.001, "first use lands {grip} mm off");

    // One target in two work objects.
    let pick = outcome.shared.iter().find(|s| s.id == "pPick").unwrap();
    let b = off(
        &lands(&corrected, "pPick", "tGripper", "wFixtureB"),
        &cold_pose(&program, "pPick"),
    );
    assert!((pick.residual_mm.unwrap() - b).abs() < 0.001);
    assert!(b > 0.01);

    // Through a variable: only the run knows, and it says so.
    let wipe = outcome
        .shared
        .iter()
        .find(|s| s.id == "pService" && s.other.line == 45)
        .unwrap();
    assert_eq!(wipe.residual_mm, None);
    assert!(wipe.unknown.as_deref().unwrap().contains("variable"));
    // Through Offs with the other tool: the derived line and the use's
    // line give the same residual (both in the glue gun's frames).
    let approach = outcome.shared.iter().find(|s| s.id == "pApproach").unwrap();
    let derived = outcome.derived.iter().find(|d| d.id == "main@1").unwrap();
    assert_eq!(
        approach.other.through.as_deref(),
        Some("Offs(pApproach,0,0,50)")
    );
    assert!((approach.residual_mm.unwrap() - derived.residual_mm.unwrap()).abs() < 1e-9);
}

/// The split program: copies right for their own pair, nothing else
/// changed beyond their declarations and the names the moves use.
#[test]
fn a_split_corrects_each_copy_for_its_own_pair() {
    let bytes = glue_cell();
    let (program, outcome) = run(&bytes, MINUTE, true);
    let split = rapid::parse("split.mod", &outcome.outputs[0]).unwrap();
    let text = String::from_utf8(outcome.outputs[0].clone()).unwrap();

    let copies: Vec<(&str, &str)> = outcome
        .splits
        .iter()
        .map(|s| (s.id.as_str(), s.copy.as_str()))
        .collect();
    assert_eq!(
        copies,
        [("pHome", "pHome_tGlueGun"), ("pPick", "pPick_wFixtureB")]
    );
    // Declared on the line after the original, in its storage and layout.
    let lines: Vec<&str> = text.lines().collect();
    let at = lines
        .iter()
        .position(|l| l.contains("robtarget pHome:="))
        .unwrap();
    assert!(lines[at + 1].starts_with("    CONST robtarget pHome_tGlueGun:=[["));
    assert!(lines[at + 1].ends_with("[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];"));

    // Each of the four, driven with the tool and work object of its (now
    // only) pair, lands on the cold pHome / pPick within the written
    // digits.
    for (id, cold, tool, wobj) in [
        ("pHome", "pHome", "tGripper", "wobj0"),
        ("pHome_tGlueGun", "pHome", "tGlueGun", "wobj0"),
        ("pPick", "pPick", "tGripper", "wFixtureA"),
        ("pPick_wFixtureB", "pPick", "tGripper", "wFixtureB"),
    ] {
        let miss = off(&lands(&split, id, tool, wobj), &cold_pose(&program, cold));
        assert!(miss < 0.001, "{id} with {tool}/{wobj} lands {miss} mm off");
    }

    // Round trip: in the split program, every target still used with
    // several pairs is one the run said it could not split.
    let uses = usages(&split);
    for (&i, list) in &uses {
        let id = &split.targets().at(i).id;
        if uses_by_frames(list).len() > 1 {
            assert!(
                outcome
                    .shared
                    .iter()
                    .any(|s| &s.id == id && s.not_split.is_some()),
                "{id} still shared and not reported"
            );
        }
    }
    for id in ["pHome", "pHome_tGlueGun", "pPick", "pPick_wFixtureB"] {
        let i = split.targets().iter().position(|t| t.id == id).unwrap();
        assert_eq!(uses_by_frames(&uses[&i]).len(), 1, "{id}");
    }
    assert!(outcome
        .shared
        .iter()
        .all(|s| s.id != "pHome" && s.id != "pPick"));
    let why = |id: &str| {
        outcome
            .shared
            .iter()
            .find(|s| s.id == id)
            .and_then(|s| s.not_split.clone())
            .unwrap()
    };
    assert!(why("pBead{1}").contains("array"));
    assert!(why("pApproach").contains("Offs(pApproach,0,0,50)"));
    assert!(why("pService").contains("global PERS"));
    // pPurge is passed to Purge, whose one call settles its parameter:
    // the move there reaches pPurge through Offs(pAt, ...).
    assert!(why("pPurge").contains("also reached through Offs(pAt,0,0,20)"));

    // Nothing else changed: without the copies' lines and with their
    // names taken back, the split program is the first-use correction
    // (marker aside).
    let (_, first_use) = run(&bytes, MINUTE, false);
    let strip = |t: &str| -> String {
        t.lines()
            .filter(|l| {
                !l.contains("! rapidtherm ")
                    && !l.contains("_tGlueGun:=")
                    && !l.contains("_wFixtureB:=")
            })
            .map(|l| {
                l.replace("pHome_tGlueGun", "pHome")
                    .replace("pPick_wFixtureB", "pPick")
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    let first_text = String::from_utf8(first_use.outputs[0].clone()).unwrap();
    assert_eq!(strip(&text), strip(&first_text));
}

/// The marker: a second run on the same basis recognises the split
/// program; a split asked of a program corrected without one says why
/// nothing happens.
#[test]
fn a_second_run_recognises_the_corrected_program() {
    let bytes = glue_cell();
    let (_, split) = run(&bytes, MINUTE, true);
    assert!(String::from_utf8_lossy(&split.outputs[0]).contains("; shared=split\n"));
    for asked in [true, false] {
        let (_, again) = run(&split.outputs[0], MINUTE, asked);
        assert!(again.already_corrected.is_some());
        assert_eq!(again.outputs[0], split.outputs[0]);
        assert!(again.notes.is_empty());
    }
    let (_, first_use) = run(&bytes, MINUTE, false);
    let (_, asked) = run(&first_use.outputs[0], MINUTE, true);
    assert!(asked.already_corrected.is_some());
    assert_eq!(asked.outputs[0], first_use.outputs[0]);
    assert!(
        asked.notes[0].contains("without splitting") && asked.notes[0].contains("pHome"),
        "{:?}",
        asked.notes
    );
}

/// Minute 0: nothing drifts, so no use is off and no copy would differ:
/// not a byte changes, split asked or not.
#[test]
fn at_minute_zero_nothing_is_split() {
    let bytes = glue_cell();
    for split in [false, true] {
        let (_, outcome) = run(&bytes, 0.0, split);
        assert_eq!(outcome.outputs[0], bytes);
        assert!(outcome.splits.is_empty());
        assert_eq!(outcome.shared.len(), 8);
        assert!(outcome
            .shared
            .iter()
            .all(|s| s.residual_mm.is_none_or(|r| r < 1e-9)));
    }
}

/// A copy's name is new to the program (here `pHome_tGlue` is taken by a
/// comment's word already), and a CRLF file gets a CRLF line.
#[test]
fn a_copy_takes_a_free_name_and_the_files_line_ends() {
    let src = "MODULE M\r\n\
        \x20 ! pHome_tGlue was the old name of the glue gun's park position\r\n\
        \x20 PERS tooldata tGrip:=[TRUE,[[0,0,145],[1,0,0,0]],[1.8,[0,0,60],[1,0,0,0],0,0,0]];\r\n\
        \x20 PERS tooldata tGlue:=[TRUE,[[0,0,210],[1,0,0,0]],[2.4,[0,0,90],[1,0,0,0],0,0,0]];\r\n\
        \x20 TASK PERS robtarget pHome:=[[515,0,712],[0.5,0,0.866025,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]]; ! park\r\n\
        \x20 PROC main()\r\n\
        \x20   MoveJ pHome,v1000,z50,tGrip;\r\n\
        \x20   MoveJ pHome,v1000,z50,tGlue;\r\n\
        \x20   MoveJ pHome,v1000,z50,tGrip;\r\n\
        \x20 ENDPROC\r\n\
        ENDMODULE\r\n";
    let (_, outcome) = run(src.as_bytes(), MINUTE, true);
    let text = String::from_utf8(outcome.outputs[0].clone()).unwrap();
    assert_eq!(outcome.splits[0].copy, "pHome_2");
    assert!(
        text.contains("! park\r\n  TASK PERS robtarget pHome_2:=[["),
        "{text}"
    );
    assert!(text.contains("MoveJ pHome_2,v1000,z50,tGlue;\r\n"));
    assert_eq!(text.matches("MoveJ pHome,v1000,z50,tGrip;").count(), 2);
    assert!(!text.replace("\r\n", "").contains('\n'));
    rapid::parse("m.mod", text.as_bytes()).unwrap();
}
