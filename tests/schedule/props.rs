//! Property: any program the reader accepts schedules without panicking,
//! and a schedule it gives is sane (finite times within the run, readable
//! back from its CSV).

use proptest::prelude::*;
use rapidtherm::rapid;
use rapidtherm::robot::Robot;
use rapidtherm::schedule::{estimate, EstimateOptions, Schedule};

const EAX: &str = "[9E9,9E9,9E9,9E9,9E9,9E9]";

fn target() -> impl Strategy<Value = String> {
    (
        -900.0..900.0f64,
        -900.0..900.0f64,
        -200.0..900.0f64,
        0..3usize,
    )
        .prop_map(|(x, y, z, k)| {
            let q = ["[0,0,1,0]", "[0.7071068,0,0.7071068,0]", "[1,0,0,0]"][k];
            format!("[[{x:.1},{y:.1},{z:.1}],{q},[0,0,0,0],{EAX}]")
        })
}

fn speed() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("v100".to_string()),
        Just("vmax".to_string()),
        Just("vOdd".to_string()),
        Just("vZero".to_string()),
        Just("[1E308,-1,0,0]".to_string()),
        Just("v100 \\T:=-3".to_string()),
        Just("v100 \\V:=0".to_string()),
    ]
}

fn leaf() -> impl Strategy<Value = String> {
    prop_oneof![
        (target(), speed()).prop_map(|(t, s)| format!("MoveL {t}, {s}, z1, tool0;")),
        (target(), speed()).prop_map(|(t, s)| format!("MoveJ {t}, {s}, z1, tool0;")),
        (target(), target()).prop_map(|(a, b)| format!("MoveC {a}, {b}, v100, z1, tool0;")),
        (-10.0..1e6f64).prop_map(|t| format!("WaitTime {t:.3};")),
        Just("WaitTime 1E308;".to_string()),
        Just("MoveL pA, v100, fine, tool0 \\Conc;".to_string()),
        Just("p := Offs(pA, 0, 0, 10); MoveL p, v100, fine, tool0;".to_string()),
        Just("MoveL RelTool(CRobT(), 0, 0, 5 \\Rz:=10), v100, fine, tool0;".to_string()),
        Just(
            "MoveAbsJ [[0,10,20,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]], v100, fine, tool0;".to_string()
        ),
        Just("MoveL arr{n}, v100, fine, tool0;".to_string()),
        Just("Sub;".to_string()),
        Just("%\"Sub\"%;".to_string()),
        Just("GOTO lbl;".to_string()),
        Just("RETURN;".to_string()),
        Just("Unknown 1, 2;".to_string()),
        Just("VelSet 0, 0;".to_string()),
    ]
}

/// A statement of a routine body: a move, a wait, a call, or a block of
/// them (FOR, IF, WHILE, TEST), nested.
pub(super) fn body() -> impl Strategy<Value = String> {
    leaf().prop_recursive(3, 24, 4, |inner| {
        let list = prop::collection::vec(inner, 0..4).prop_map(|v| v.join("\n"));
        prop_oneof![
            (-3i32..4, -3i32..4, -2i32..3, list.clone()).prop_map(|(a, b, s, body)| {
                format!("FOR i FROM {a} TO {b} STEP {s} DO\n{body}\nENDFOR")
            }),
            (0..3usize, list.clone(), list.clone()).prop_map(|(c, a, b)| {
                let cond = ["TRUE", "nVar > 1", "Present(x)"][c];
                format!("IF {cond} THEN\n{a}\nELSE\n{b}\nENDIF")
            }),
            list.clone()
                .prop_map(|b| format!("WHILE TRUE DO\n{b}\nENDWHILE")),
            list.prop_map(|b| format!("TEST nVar\nCASE 1:\n{b}\nDEFAULT:\nWaitTime 1;\nENDTEST")),
        ]
    })
}

/// A module whose `main` runs `main` (statements of [`body`]), with the
/// data they name and a procedure `Sub` that calls `main` back; a move
/// in `Sub`'s error handler and a routine variable, which the walk does
/// not run but the program lists.
pub(super) fn program(main: &[String]) -> String {
    format!(
        "MODULE P
  CONST robtarget pA := [[500,0,400],[0,0,1,0],[0,0,0,0],{EAX}];
  CONST robtarget arr{{2}} := [[[500,0,400],[0,0,1,0],[0,0,0,0],{EAX}],[[500,50,400],[0,0,1,0],[0,0,0,0],{EAX}]];
  VAR speeddata vOdd;
  VAR speeddata vZero;
  CONST num n := 2;
  VAR num nVar;
  VAR robtarget p;
  PROC main()
    {}
    lbl:
  ENDPROC
  PROC Sub()
    VAR num k;
    main;
    WaitTime 0.5;
  ERROR
    MoveL [[500,20,400],[0,0,1,0],[0,0,0,0],{EAX}], v100, fine, tool0;
    RETRY;
  ENDPROC
ENDMODULE
",
        main.join("\n")
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn any_program_schedules_or_errors_cleanly(main in prop::collection::vec(body(), 1..5), start in 0.0..500.0f64) {
        let src = program(&main);
        // The generator writes valid RAPID; the reader is tested elsewhere.
        let program = rapid::parse("p.mod", src.as_bytes()).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        let opts = EstimateOptions { start_min: start, cycles: 2, ..EstimateOptions::default() };
        if let Ok(est) = estimate(&program, &Robot::irb140(), &opts) {
            prop_assert!(est.duration_min.is_finite() && est.duration_min >= 0.0);
            for id in est.schedule.targets() {
                for &t in est.schedule.times(id).unwrap() {
                    prop_assert!(t.is_finite());
                    prop_assert!(t >= start - 1e-9 && t <= start + est.duration_min + 1e-9, "{id} at {t}");
                }
            }
            let back = Schedule::read("s.csv", est.to_csv().as_bytes());
            prop_assert!(back.is_ok(), "{:?}", back.err());
        }
    }
}
