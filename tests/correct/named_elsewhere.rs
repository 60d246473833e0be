//! Targets whose frames or values another place decides (issue 49): a
//! move with a work object declared `PERS` without a value (another task
//! or module sets it) is left alone `set-elsewhere`, not refused as "no
//! wobjdata of that name"; a target the program reads by its name at run
//! time (`GetDataVal "p30", p`) is `runtime`, not `unused`.

const PROGRAM: &str = "MODULE M
  CONST robtarget p10 := [[500,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget p20 := [[520,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget p30 := [[540,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PERS wobjdata wSet;
  PROC main()
    VAR robtarget p;
    MoveL p10, v100, fine, tool0;
    MoveL p20, v100, fine, tool0 \\WObj:=wSet;
    GetDataVal \"p30\", p;
    MoveL p, v100, fine, tool0;
  ENDPROC
ENDMODULE
";

/// A target's reason and detail in the JSON report's `left_alone`.
fn left_alone(json: &serde_json::Value, id: &str) -> (String, String) {
    let rows = json["left_alone"].as_array().unwrap();
    let row = rows
        .iter()
        .find(|r| r["id"] == id)
        .unwrap_or_else(|| panic!("{id} not left alone: {json}"));
    let text = |k: &str| row[k].as_str().unwrap().to_string();
    (text("reason"), text("detail"))
}

#[test]
fn frames_set_elsewhere_and_data_read_by_name_are_said_as_such() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("m.mod"), PROGRAM).unwrap();
    let out = super::rapidtherm(
        &["correct", "m.mod", "--at", "60", "--format", "json"],
        dir.path(),
    );
    super::assert_exit(&out, 0);
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let (reason, detail) = left_alone(&json, "p20");
    assert_eq!(reason, "set-elsewhere");
    assert!(
        detail.contains("`wSet` is PERS data declared without a value"),
        "{detail}"
    );
    let (reason, detail) = left_alone(&json, "p30");
    assert_eq!(reason, "runtime");
    assert!(
        detail.contains("GetDataVal at line 10 reaches it by its name"),
        "{detail}"
    );
    // The gate fails on them unless accepted, as on any target left cold.
    let gate = |accept: &[&str]| {
        let mut args = vec!["correct", "m.mod", "--at", "60", "--check"];
        args.extend_from_slice(accept);
        super::rapidtherm(&args, dir.path()).status.code()
    };
    assert_eq!(gate(&[]), Some(1));
    let corrected = super::rapidtherm(
        &["correct", "m.mod", "--at", "60", "--in-place"],
        dir.path(),
    );
    super::assert_exit(&corrected, 0);
    assert_eq!(gate(&["--accept", "set-elsewhere,runtime"]), Some(0));
}
