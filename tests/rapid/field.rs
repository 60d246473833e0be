//! Valid RAPID that real controllers load and the reader once refused:
//! conditional arguments (`\ID?ID`, also inside function calls), a keyword
//! written against a number (`1THEN`, `3DO`), a module named `1_T_ROB2`.
//! Each is read, its targets found, and `--at 0` writes it back byte for
//! byte.

use rapidtherm::correct::{correct, Options, When};
use rapidtherm::model::warm::{Moment, WarmRobot};
use rapidtherm::model::Model;
use rapidtherm::rapid::{self, StatementKind};
use rapidtherm::robot::Robot;

fn source() -> Vec<u8> {
    std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/rapid_data/field_constructs.mod"
    ))
    .unwrap()
}

#[test]
fn field_constructs_are_read() {
    let src = source();
    let program = rapid::parse("field_constructs.mod", &src).unwrap();
    assert_eq!(program.modules[0].name.as_ref(), "1_T_ROB2");
    assert!(program.target("pWeld").is_some());
    // `\WObj?WObj`: an optional argument whose value is the parameter.
    let gun_move = &program.modules[0].routines[0];
    let StatementKind::Call(call) = &gun_move.body[0].kind else {
        panic!("MoveL first");
    };
    let wobj = call.optional("WObj").expect("\\WObj?WObj read");
    assert_eq!(wobj.value.as_ref().and_then(|v| v.as_name()), Some("WObj"));
}

#[test]
fn field_constructs_round_trip_at_minute_zero() {
    let src = source();
    let program = rapid::parse("field_constructs.mod", &src).unwrap();
    let warm = WarmRobot::new(Robot::irb140(), &Model::default(), 0.0).unwrap();
    let options = Options::new(When::At(Moment::Minute(0.0)));
    let outcome = correct(&program, &warm, &options, &mut |_, _| {}).unwrap();
    assert_eq!(outcome.outputs[0], src);
    let warm = WarmRobot::new(Robot::irb140(), &Model::default(), 120.0).unwrap();
    let options = Options::new(When::At(Moment::Minute(120.0)));
    let outcome = correct(&program, &warm, &options, &mut |_, _| {}).unwrap();
    assert!(outcome
        .corrections
        .iter()
        .any(|c| c.id == "pWeld" && c.rewritten));
}
