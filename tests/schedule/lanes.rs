//! A program read every way the reader reads (`tests/common/ways.rs`: the
//! fast lane, reading ahead or at the parse's place, the moves it knows
//! held in runs) is the program the grammar reads statement by statement: the same
//! targets with the same identifiers, places and numbers, and the same
//! estimated schedule, notes and errors, on programs of nested blocks,
//! calls, waits and moves of every kind. The generated comparison counts
//! the programs whose moves the lane read, and fails unless most were.

use super::props::{body, program};
use crate::ways;
use proptest::prelude::*;
use rapidtherm::rapid::{self, Program};
use rapidtherm::robot::Robot;
use rapidtherm::schedule::{estimate, EstimateOptions};

/// What the walk and the schedule see of a program's targets.
fn targets(p: &Program) -> Vec<String> {
    let numbers = |v: &rapid::RobTargetValue| -> Vec<u64> {
        v.numbers().map(|n| n.value.to_bits()).collect()
    };
    p.targets()
        .iter()
        .map(|t| {
            format!(
                "{} {:?} {}:{} {:?} {:?} {:?} {:?} {:?} {:?}",
                t.id,
                t.kind,
                t.origin.pos.line,
                t.origin.pos.col,
                t.origin.routine,
                t.value.as_ref().map(numbers),
                t.instruction,
                t.tool,
                t.wobj,
                t.derived.as_ref().map(|d| (&d.expr, &d.bases)),
            )
        })
        .chain(
            p.jointtargets()
                .iter()
                .map(|j| format!("{} {:?}", j.id, j.origin.pos.line)),
        )
        .collect()
}

/// The estimate's whole say, or its error's.
fn estimated(p: &Program, start: f64) -> String {
    let opts = EstimateOptions {
        start_min: start,
        cycles: 2,
        ..EstimateOptions::default()
    };
    match estimate(p, &Robot::irb140(), &opts) {
        Ok(e) => format!(
            "{}\n{}\n{:?}\n{:?}",
            e.to_csv(),
            e.joint_schedule.to_csv(),
            e.duration_min.to_bits(),
            e.notes
        ),
        Err(e) => format!("error: {e}"),
    }
}

/// Every way, the same targets and the same estimate; how many move
/// literals the lane read.
fn same_both_ways(src: &[u8], start: f64) -> Result<usize, TestCaseError> {
    let ways = ways::same_every_way(src, |p| (targets(p), estimated(p, start)))?
        .ok_or_else(|| TestCaseError::fail("every way refused the program"))?;
    Ok(ways.lane().targets().moves_in_runs())
}

#[test]
fn a_program_of_blocks_reads_the_same_with_the_lane() {
    let moves = |n: usize| -> String {
        (0..n)
            .map(|i| format!("    MoveL [[{},{},400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, z1, tool0;", 450 + i, i))
            .collect::<Vec<_>>()
            .join("\n")
    };
    let main = [
        format!(
            "IF nVar > 1 THEN\n{}\nELSEIF TRUE THEN\n{}\nELSE\n{}\nENDIF",
            moves(2),
            moves(1),
            moves(3)
        ),
        format!("FOR i FROM 1 TO 3 DO\n{}\nENDFOR", moves(2)),
        format!(
            "TEST nVar\nCASE 1:\n{}\nCASE 2, 3:\nDEFAULT:\n{}\nENDTEST",
            moves(2),
            moves(1)
        ),
        format!("WHILE TRUE DO\n{}\nENDWHILE", moves(1)),
        "Sub;".to_string(),
        moves(2),
    ];
    let src = program(&main);
    let read = same_both_ways(src.as_bytes(), 10.0).unwrap();
    // Every move of the blocks and the error handler's.
    assert_eq!(read, 2 + 1 + 3 + 2 + 2 + 1 + 1 + 2 + 1);
}

#[test]
fn moves_of_every_kind_of_routine_and_handler_read_the_same() {
    let mv = |x: u32| {
        format!(
            "MoveL [[{x},0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, z1, tool0;"
        )
    };
    let src = format!(
        "MODULE m
  VAR num nVar;
  PROC main()
    VAR num k;
    {a}
  lbl:
    {b}
    IF nVar = 1 GOTO lbl2;
    IF TRUE {c}
    {d}
  lbl2:
    f;
    Sub;
  BACKWARD
    {e}
  ERROR
    {f}
    RETRY;
  UNDO
    {g}
  ENDPROC
  PROC Sub()
    {h}
  ENDPROC
  TRAP tr
    {i}
  ENDTRAP
  FUNC num f()
    {j}
    RETURN 1;
  ENDFUNC
ENDMODULE
",
        a = mv(450),
        b = mv(451),
        c = mv(452),
        d = mv(453),
        e = mv(454),
        f = mv(455),
        g = mv(456),
        h = mv(457),
        i = mv(458),
        j = mv(459),
    );
    let read = same_both_ways(src.as_bytes(), 5.0).unwrap();
    // Every move but the one of the one-line IF.
    assert_eq!(read, 9);
}

#[test]
fn a_declaration_after_a_lane_move_is_refused_as_the_grammar_refuses_it() {
    let src = b"MODULE m\nPROC main()\n  MoveL [[500,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]],v100,z1,tool0;\n  VAR num k;\nENDPROC\nENDMODULE\n";
    let read = ways::read_every_way(src).unwrap();
    assert!(read.is_none(), "every way refuses it alike");
}

#[test]
fn a_program_reads_the_same_with_the_lane() {
    let strategy = (prop::collection::vec(body(), 1..6), 0.0..500.0f64);
    ways::counted("estimated", 64, 9, strategy, |(main, start)| {
        same_both_ways(program(&main).as_bytes(), start)
    });
}
