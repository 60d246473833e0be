//! A program read as its skeleton (`rapid::parse_skeleton`: the moves the
//! fast recogniser reads cut out, put back by the assembly) is the program
//! the grammar reads: the same targets with the same identifiers, places
//! and numbers, and the same estimated schedule, notes and errors, on
//! programs of nested blocks, calls, waits and moves of every kind.

use super::props::{body, program};
use proptest::prelude::*;
use rapidtherm::rapid::fastmove::skeleton;
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

fn same_both_ways(src: &[u8], start: f64) -> Result<usize, TestCaseError> {
    let whole = rapid::parse("p.mod", src).map_err(|e| TestCaseError::fail(format!("{e}")))?;
    let skel = skeleton(src);
    let read = rapid::parse_skeleton("p.mod", &skel, src)
        .map_err(|e| TestCaseError::fail(format!("{e}")))?;
    prop_assert_eq!(targets(&read), targets(&whole));
    prop_assert_eq!(estimated(&read, start), estimated(&whole, start));
    Ok(skel.cuts.len())
}

#[test]
fn a_program_of_blocks_reads_the_same_from_its_skeleton() {
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
    let cut = same_both_ways(src.as_bytes(), 10.0).unwrap();
    // Every move of the blocks and the error handler's.
    assert_eq!(cut, 2 + 1 + 3 + 2 + 2 + 1 + 1 + 2 + 1);
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
    let cut = same_both_ways(src.as_bytes(), 5.0).unwrap();
    // Every move but the one of the one-line IF.
    assert_eq!(cut, 9);
}

#[test]
fn a_declaration_after_a_cut_move_is_refused_as_the_grammar_refuses_it() {
    let src = b"MODULE m\nPROC main()\n  MoveL [[500,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]],v100,z1,tool0;\n  VAR num k;\nENDPROC\nENDMODULE\n";
    let whole = rapid::parse("m.mod", src).unwrap_err();
    let skel = skeleton(src);
    assert_eq!(skel.cuts.len(), 1);
    let read = rapid::parse_skeleton("m.mod", &skel, src).unwrap_err();
    assert_eq!(read.to_string(), whole.to_string());
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn a_program_reads_the_same_from_its_skeleton(main in prop::collection::vec(body(), 1..6), start in 0.0..500.0f64) {
        same_both_ways(program(&main).as_bytes(), start)?;
    }
}
