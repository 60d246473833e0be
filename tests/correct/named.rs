//! A run's moves by name are looked up once: what the uses found for each
//! name is kept, and the second walk over the moves (the moves' fates)
//! gets from it what looking each name up again gives.

use rapidtherm::rapid::parse;
use rapidtherm::resolve::{each_move_instruction_with, uses_with, Move, MoveLookup, Through};
use std::ops::Range;

/// A move as the walk gives it: where, and what each argument reaches.
type Seen = (
    u32,
    String,
    Vec<(Vec<(Range<usize>, Through)>, Vec<String>)>,
);

fn seen(m: &Move) -> Seen {
    let points = (m.points.iter())
        .map(|p| {
            let unread = p.unread_passed.iter().map(|s| s.to_string()).collect();
            (p.robtargets.clone(), unread)
        })
        .collect();
    (m.line, m.instruction.to_string(), points)
}

/// Declared targets moved to by name in runs: each name once, one twice,
/// one in another case, one declared nowhere, a routine's own data
/// shadowing a module's, a parameter its calls settle, a variable.
fn program() -> String {
    let mut s = String::from("MODULE M\n");
    for k in 0..400 {
        s.push_str(&format!(
            "  CONST robtarget Target_{k}:=[[{k},0,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n"
        ));
    }
    s.push_str("  PROC main()\n    VAR robtarget v;\n");
    for k in 0..400 {
        s.push_str(&format!("    MoveL Target_{k},v1000,z1,tool0;\n"));
    }
    s.push_str("    MoveL target_7,v1000,z1,tool0;\n    MoveL Nowhere,v1000,z1,tool0;\n");
    s.push_str("    MoveL v,v1000,z1,tool0;\n    go Target_3;\n  ENDPROC\n");
    s.push_str("  PROC other()\n    CONST robtarget Target_5:=[[5,5,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n");
    for k in 0..300 {
        s.push_str(&format!("    MoveL Target_{k},v1000,z1,tool0;\n"));
    }
    s.push_str(
        "  ENDPROC\n  PROC go(robtarget p)\n    MoveL p,v1000,z1,tool0;\n  ENDPROC\nENDMODULE\n",
    );
    s
}

#[test]
fn a_runs_names_are_looked_up_once_and_reach_the_same_targets() {
    let src = program();
    let p = parse("named.mod", src.as_bytes()).unwrap();
    // Looked up again: a lookup the uses did not fill.
    let fresh = MoveLookup::new(&p);
    let mut again = Vec::new();
    each_move_instruction_with(&p, &fresh, &mut |m| again.push(seen(m)));
    assert_eq!(fresh.runs_kept(), 0);
    // Looked up by the uses, kept, then read.
    let lookup = MoveLookup::new(&p);
    let _uses = uses_with(&p, &lookup);
    assert!(lookup.runs_kept() >= 2, "the runs' answers were kept");
    let mut kept = Vec::new();
    each_move_instruction_with(&p, &lookup, &mut |m| kept.push(seen(m)));
    // `go` is a procedure of the file, not a move.
    assert_eq!(kept.len(), 400 + 3 + 300 + 1);
    assert_eq!(kept, again);
}
