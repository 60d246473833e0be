//! What a move settles for the next (its speed, tool and work object by
//! name, the array it indexes) is asked again once a name may stand for
//! something else: a loop that assigns its speed or tool midway times
//! each turn with what the name then is, and a run of moves naming
//! different speeds and tools times each with its own.

use approx::assert_abs_diff_eq;
use rapidtherm::rapid;
use rapidtherm::robot::Robot;
use rapidtherm::schedule::{estimate, Estimate, EstimateOptions};

const EAX: &str = "[9E9,9E9,9E9,9E9,9E9,9E9]";

/// A robtarget pointing down (tool0 z along -z) at x, y, z.
fn down(x: f64, y: f64, z: f64) -> String {
    format!("[[{x},{y},{z}],[0,0,1,0],[0,0,0,0],{EAX}]")
}

fn run(src: &str) -> (rapid::Program, Estimate) {
    let program = rapid::parse("t.mod", src.as_bytes()).unwrap_or_else(|e| panic!("{e}"));
    let est = estimate(&program, &Robot::irb140(), &EstimateOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    (program, est)
}

/// Seconds between the first visits of two targets.
fn secs(est: &Estimate, a: &str, b: &str) -> f64 {
    let t = |id: &str| est.schedule.times(id).unwrap_or_else(|| panic!("{id}"))[0];
    (t(b) - t(a)) * 60.0
}

/// Four targets 100 mm apart along y, in an array.
fn scan() -> String {
    let p: Vec<String> = (0..4)
        .map(|k| down(500.0, 100.0 * k as f64, 400.0))
        .collect();
    format!("CONST robtarget pScan{{4}} := [{}];", p.join(", "))
}

/// A 200 mm tool along the flange's z.
const GUN: &str =
    "PERS tooldata tGun := [TRUE,[[0,0,200],[1,0,0,0]],[1,[0,0,50],[1,0,0,0],0,0,0]];";

#[test]
fn a_speed_assigned_in_the_loop_is_looked_up_again() {
    let src = format!(
        "MODULE T
    {}
    PERS speeddata vSlow := [50, 500, 5000, 1000];
    PROC main()
        VAR num i;
        FOR i FROM 1 TO 4 DO
            MoveL pScan{{i}}, vSlow, fine, tool0;
            vSlow := [400, 500, 5000, 1000];
        ENDFOR
    ENDPROC
ENDMODULE",
        scan()
    );
    let (_, est) = run(&src);
    // From the second turn on, vSlow is a value set at run time: the
    // fallback speed (v1000), 100 mm in 0.1 s, not vSlow's 2 s.
    assert_abs_diff_eq!(secs(&est, "pScan{1}", "pScan{2}"), 0.1, epsilon = 1e-6);
    assert_abs_diff_eq!(secs(&est, "pScan{2}", "pScan{3}"), 0.1, epsilon = 1e-6);
    assert!(
        est.notes
            .iter()
            .any(|n| n.contains("speed known only at run time")),
        "{:?}",
        est.notes
    );
}

#[test]
fn a_tool_assigned_in_the_loop_is_looked_up_again() {
    let src = format!(
        "MODULE T
    {}
    {GUN}
    PROC main()
        VAR num i;
        FOR i FROM 1 TO 3 DO
            MoveL pScan{{i}}, v100, fine, tGun;
            tGun := [TRUE,[[0,0,100],[1,0,0,0]],[1,[0,0,50],[1,0,0,0],0,0,0]];
        ENDFOR
    ENDPROC
ENDMODULE",
        scan()
    );
    let (_, est) = run(&src);
    // The second turn knows no tool (timed with tool0): it starts where
    // the first left the flange, 200 mm above pScan{1}, and goes 223.6 mm
    // at 100 mm/s; the third, 100 mm with tool0 again.
    let diagonal = (100f64.powi(2) + 200f64.powi(2)).sqrt() / 100.0;
    assert_abs_diff_eq!(secs(&est, "pScan{1}", "pScan{2}"), diagonal, epsilon = 1e-6);
    assert_abs_diff_eq!(secs(&est, "pScan{2}", "pScan{3}"), 1.0, epsilon = 1e-6);
    assert!(
        est.notes.iter().any(|n| n.contains("tool ? unknown here")),
        "{:?}",
        est.notes
    );
}

#[test]
fn a_run_of_moves_times_each_with_its_own_speed_and_tool() {
    let src = format!(
        "MODULE T
    {GUN}
    PROC main()
        MoveL {}, v100, fine, tool0;
        MoveL {}, v200, fine, tool0;
        MoveL {}, v200, fine, tool0;
        MoveL {}, v100, fine, tool0;
        MoveL {}, v100, fine, tGun;
        MoveL {}, v100, fine, tGun;
    ENDPROC
ENDMODULE",
        down(500.0, 0.0, 400.0),
        down(500.0, 100.0, 400.0),
        down(500.0, 200.0, 400.0),
        down(500.0, 300.0, 400.0),
        down(500.0, 200.0, 400.0),
        down(500.0, 100.0, 400.0),
    );
    let (program, est) = run(&src);
    assert_eq!(
        program.targets().moves_in_runs(),
        6,
        "the moves are read in a run of the fast lane's"
    );
    assert_abs_diff_eq!(secs(&est, "main#1", "main#2"), 0.5, epsilon = 1e-6);
    assert_abs_diff_eq!(secs(&est, "main#2", "main#3"), 0.5, epsilon = 1e-6);
    assert_abs_diff_eq!(secs(&est, "main#3", "main#4"), 1.0, epsilon = 1e-6);
    // The tool changes: the move starts at tGun's TCP where tool0 left
    // the flange, 200 mm below where the last move ended, and goes
    // 223.6 mm.
    let diagonal = (100f64.powi(2) + 200f64.powi(2)).sqrt() / 100.0;
    assert_abs_diff_eq!(secs(&est, "main#4", "main#5"), diagonal, epsilon = 1e-6);
    assert_abs_diff_eq!(secs(&est, "main#5", "main#6"), 1.0, epsilon = 1e-6);
}

/// A move by name after a move to another module's last declaration: the
/// walk asks first for the declaration after the last one it found (a
/// RobotStudio export moves in the order it declares). Here that is the
/// other module's LOCAL `p0`, which this module's own `p0` hides: the
/// move goes to this module's, 100 mm from `a49`, never to the other's.
#[test]
fn the_next_declaration_is_not_taken_where_another_hides_it() {
    let decl = |local: &str, name: String, at: String| {
        format!("    {local}CONST robtarget {name} := {at};\n")
    };
    let mut src = String::from("MODULE A\n");
    (0..50).for_each(|k| src.push_str(&decl("", format!("a{k}"), down(500.0, k as f64, 400.0))));
    (0..50).for_each(|k| src.push_str(&decl("LOCAL ", format!("p{k}"), down(300.0, 0.0, 700.0))));
    src.push_str("ENDMODULE\nMODULE B\n");
    (0..50).for_each(|k| {
        src.push_str(&decl(
            "LOCAL ",
            format!("p{k}"),
            down(500.0, 149.0 + k as f64, 400.0),
        ))
    });
    src.push_str("    PROC main()\n        MoveL a49, v100, fine, tool0;\n");
    (0..50).for_each(|k| src.push_str(&format!("        MoveL p{k}, v100, fine, tool0;\n")));
    src.push_str("    ENDPROC\nENDMODULE\n");
    let (_, est) = run(&src);
    assert!(est.schedule.times("A:p0").is_none_or(|t| t.is_empty()));
    // 100 mm at 100 mm/s.
    assert_abs_diff_eq!(secs(&est, "a49", "B:p0"), 1.0, epsilon = 0.05);
    assert_abs_diff_eq!(secs(&est, "B:p0", "B:p49"), 0.49, epsilon = 0.05);
}
