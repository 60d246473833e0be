//! The arm of a backup's robot type (MOC.cfg `use_robot_type`): a build
//! variant of a catalogue arm is taken as that arm and said; a type the
//! catalogue lacks is refused naming the nearest arms. Expectations worked
//! by hand from data/arms/*.toml.

use super::common::copy_tree;
use super::rapidtherm;
use rapidtherm::rapid::task::Task;
use rapidtherm::resolve::arm::{arm_for, ChosenBy};
use std::path::PathBuf;

fn task_of_type(robot_type: &str) -> Task {
    Task {
        name: Some("T_ROB1".into()),
        origin: None,
        modules: Vec::new(),
        motion: Some(true),
        robot_type: Some(robot_type.into()),
        base_frame: None,
        base_moved_by: None,
        notes: Vec::new(),
        gaps: Vec::new(),
        not_a_backup: None,
    }
}

#[test]
fn a_type_b_variant_is_taken_as_its_base_arm_and_says_so() {
    let arm = arm_for(&task_of_type("ROB1_1200_0.9_5_TypeB"), &[]).unwrap();
    assert_eq!(arm.robot.name, "IRB 1200-5/0.9");
    assert_eq!(
        arm.chosen_by,
        ChosenBy::RobotTypeVariant {
            robot_type: "ROB1_1200_0.9_5_TypeB".into(),
            variants: vec!["TypeB".into()],
        }
    );
    // The plain type is the arm itself, with nothing assumed.
    let plain = arm_for(&task_of_type("ROB1_1200_0.9_5"), &[]).unwrap();
    assert_eq!(plain.robot.name, "IRB 1200-5/0.9");
    assert_eq!(
        plain.chosen_by,
        ChosenBy::RobotType("ROB1_1200_0.9_5".into())
    );
}

#[test]
fn a_type_the_catalogue_lacks_names_the_nearest_arms() {
    // LeanID is another arm (its own wrist), not a build variant: refused.
    // By reach and payload (fractions of 2.65 m, 220 kg), the IRB 6700s
    // first: 235/2.65 (0 + 0.068), 200/2.60 (0.019 + 0.091); then of the
    // other families the IRB 6640-235/2.55 (0.038 + 0.068).
    let e = arm_for(&task_of_type("ROB1_6700_LeanID_2.65_220"), &[]).unwrap_err();
    assert!(e.message.contains("no description of"), "{e}");
    assert_eq!(
        e.notes,
        vec![
            "nearest in the catalogue by reach and payload: IRB 6700-235/2.65, IRB 6700-200/2.60, IRB 6640-235/2.55"
                .to_string()
        ]
    );
}

#[test]
fn a_backup_of_a_variant_says_what_it_assumed() {
    let dir = tempfile::tempdir().unwrap();
    let bk = dir.path().join("bk");
    let sample = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("samples/backup_multimove");
    copy_tree(&sample, &bk);
    let p = bk.join("SYSPAR/MOC.cfg");
    let t = std::fs::read_to_string(&p).unwrap();
    std::fs::write(
        &p,
        t.replace("\"ROB1_140_0.81_6\"", "\"ROB1_1200_0.9_5_TypeB\""),
    )
    .unwrap();
    let out = rapidtherm(
        &[
            "correct", "bk", "--task", "T_ROB1", "--at", "120", "--check",
        ],
        dir.path(),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("no description of"), "{err}");
    assert!(
        err.contains("the robot type ROB1_1200_0.9_5_TypeB of SYSPAR/MOC.cfg is taken as the IRB 1200-5/0.9 (TypeB assumed not to change its geometry)"),
        "{err}"
    );
}
