//! The RAPID system module that corrects targets on the controller: the
//! arm's numbers as data, the heating state in PERS data, the clock, the
//! update, the drift and the correcting functions. Only instructions and
//! functions of the RAPID reference manual are used (docs/runtime.md
//! lists each).

use super::spec::{RuntimeSpec, MAX_TERMS};

/// What the user may choose of the module.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModuleOptions {
    /// The module's name (its file is `NAME.sys`).
    pub name: String,
    /// The tool's version, for the header.
    pub version: String,
    /// Where the heating curves came from, for the header.
    pub heating_source: String,
}

/// A number as RAPID reads it: the shortest decimal that gives the value
/// back (the controller keeps it in single precision, ~7 digits).
fn num(v: f64) -> String {
    let v = if v == 0.0 { 0.0 } else { v };
    format!("{v}")
}

fn list(values: impl IntoIterator<Item = f64>) -> String {
    let parts: Vec<String> = values.into_iter().map(num).collect();
    format!("[{}]", parts.join(","))
}

/// The whole module, CRLF line ends as RobotStudio writes them.
pub fn module_text(spec: &RuntimeSpec, opts: &ModuleOptions) -> String {
    let g = &spec.geom;
    let terms = |f: &dyn Fn(usize, usize) -> f64| {
        let rows: Vec<String> = (0..6)
            .map(|a| list((0..MAX_TERMS).map(|k| f(a, k))))
            .collect();
        format!("[{}]", rows.join(","))
    };
    let term = |a: usize, k: usize| spec.curves[a].terms.get(k);
    let rises = terms(&|a, k| term(a, k).map_or(0.0, |t| t.delta));
    // A missing term has no time constant: 0 marks it, and the update
    // skips it.
    let taus = terms(&|a, k| term(a, k).map_or(0.0, |t| t.tau));
    let motors: Vec<String> = spec
        .links
        .iter()
        .map(|l| list(l.motors.map(|m| if m { 1.0 } else { 0.0 })))
        .collect();
    let b = spec.base_rotation.quaternion();
    let mut s = String::new();
    let mut line = |text: &str| {
        s.push_str(text);
        s.push_str("\r\n");
    };
    line(&format!("MODULE {}(SYSMODULE,NOSTEPIN)", opts.name));
    for l in [
        format!(
            "  ! Written by rapidtherm {} for the {}: corrects targets for the",
            opts.version, spec.arm
        ),
        "  ! arm's thermal drift when the program reaches them, from a heating".to_string(),
        "  ! state carried through running and stopped spans. Write it again with".to_string(),
        "  ! `rapidtherm correct --runtime`; do not edit. See docs/runtime.md.".to_string(),
        format!("  ! Heating curves: {}.", opts.heating_source),
    ] {
        line(&l);
    }
    line("");
    line("  ! The arm's lengths (mm) and joint convention: theta = sign * q + offset (deg).");
    for (n, v) in [
        ("rtA1", g.a1),
        ("rtA2", g.a2),
        ("rtB", g.b),
        ("rtC1", g.c1),
        ("rtC2", g.c2),
        ("rtC3", g.c3),
        ("rtC4", g.c4),
    ] {
        line(&format!("  CONST num {n} := {};", num(v)));
    }
    line(&format!("  CONST num rtSign{{6}} := {};", list(spec.signs)));
    line(&format!(
        "  CONST num rtOffset{{6}} := {};",
        list(spec.offsets_deg)
    ));
    line("  ! Each link (base, lower arm, upper arm, wrist) grows by rtGrow (1/degC)");
    line("  ! times its temperature above rtTref, the mean of the motors marked 1.");
    line(&format!(
        "  CONST num rtGrow{{4}} := {};",
        list(spec.links.iter().map(|l| l.per_degree))
    ));
    line(&format!(
        "  CONST num rtLinkMotor{{4,6}} := [{}];",
        motors.join(",")
    ));
    line(&format!("  CONST num rtTref := {};", num(spec.t_ref)));
    line("  ! Motor temperature = rtT0 + the rises of its terms; a rise tends to rtRise");
    line("  ! while the program runs and to 0 while the robot stands, with time");
    line("  ! constant rtTau (min; 0: no such term).");
    line(&format!(
        "  CONST num rtT0{{6}} := {};",
        list(spec.curves.iter().map(|c| c.t0))
    ));
    line(&format!("  CONST num rtRise{{6,{MAX_TERMS}}} := {rises};"));
    line(&format!("  CONST num rtTau{{6,{MAX_TERMS}}} := {taus};"));
    line("  ! Longer than this (min) between two corrections: the robot stood, and cooled.");
    line(&format!(
        "  CONST num rtStopGap := {};",
        num(spec.stop_gap_min)
    ));
    line("  ! The robot's base frame in the world (its rotation: a drift is a direction).");
    line(&format!(
        "  CONST orient rtBaseRot := [{},{},{},{}];",
        num(b.w),
        num(b.i),
        num(b.j),
        num(b.k)
    ));
    line("");
    line("  ! The state: kept through program restarts and power failures. TASK PERS:");
    line("  ! each motion task (each robot of a MultiMove system) keeps its own.");
    line(&format!(
        "  TASK PERS num rtX{{6,{MAX_TERMS}}} := {};",
        terms(&|_, _| 0.0)
    ));
    line("  ! Day (since 2000-01-01) and minute of the day of the last update; -1: cold.");
    line("  TASK PERS num rtDay := -1;");
    line("  TASK PERS num rtMinute := 0;");
    s.push_str(BODY);
    s.push_str("ENDMODULE\r\n");
    s
}

/// The routines: the same for every arm (the numbers above are the
/// arm's). Each step is the one `mirror` computes.
const BODY: &str = "\r
  ! The operator's cold start: the next correction starts from a cold arm.\r
  PROC RtWarmReset()\r
    FOR a FROM 1 TO 6 DO\r
      FOR k FROM 1 TO 2 DO\r
        rtX{a,k} := 0;\r
      ENDFOR\r
    ENDFOR\r
    rtDay := -1;\r
    rtMinute := 0;\r
  ENDPROC\r
\r
  ! Days from 2000-01-01 to a date (days from civil, integer DIV).\r
  FUNC num RtDays(num y, num m, num d)\r
    VAR num yy;\r
    VAR num era;\r
    VAR num yoe;\r
    VAR num mp;\r
    VAR num doy;\r
    VAR num doe;\r
    yy := y;\r
    IF m <= 2 yy := yy - 1;\r
    era := yy DIV 400;\r
    yoe := yy - era * 400;\r
    IF m > 2 THEN\r
      mp := m - 3;\r
    ELSE\r
      mp := m + 9;\r
    ENDIF\r
    doy := (153 * mp + 2) DIV 5 + d - 1;\r
    doe := yoe * 365 + yoe DIV 4 - yoe DIV 100 + doy;\r
    RETURN era * 146097 + doe - 730425;\r
  ENDFUNC\r
\r
  ! The controller's clock: the day and the minute of the day, kept apart\r
  ! so that single precision keeps fractions of a second.\r
  PROC RtNow(INOUT num day, INOUT num minute)\r
    VAR string date;\r
    VAR num y;\r
    VAR num mo;\r
    VAR num d;\r
    VAR bool ok;\r
    date := CDate();\r
    minute := GetTime(\\Hour) * 60 + GetTime(\\Min) + GetTime(\\Sec) / 60;\r
    ! Midnight between the two readings: read both again.\r
    IF CDate() <> date THEN\r
      date := CDate();\r
      minute := GetTime(\\Hour) * 60 + GetTime(\\Min) + GetTime(\\Sec) / 60;\r
    ENDIF\r
    ok := StrToVal(StrPart(date, 1, 4), y);\r
    ok := StrToVal(StrPart(date, 6, 2), mo);\r
    ok := StrToVal(StrPart(date, 9, 2), d);\r
    day := RtDays(y, mo, d);\r
  ENDPROC\r
\r
  ! dt minutes running (heating) or stopped (cooling), exactly.\r
  PROC RtAdvance(num dt, bool running)\r
    VAR num u;\r
    VAR num g;\r
    FOR a FROM 1 TO 6 DO\r
      FOR k FROM 1 TO 2 DO\r
        IF rtTau{a,k} > 0 THEN\r
          u := dt / rtTau{a,k};\r
          ! 1 - e^-u; by its series where Exp would lose the digits.\r
          IF u < 0.01 THEN\r
            g := u * (1 - u / 2 * (1 - u / 3 * (1 - u / 4)));\r
          ELSE\r
            g := 1 - Exp(-u);\r
          ENDIF\r
          IF running THEN\r
            rtX{a,k} := rtX{a,k} + (rtRise{a,k} - rtX{a,k}) * g;\r
          ELSE\r
            rtX{a,k} := rtX{a,k} - rtX{a,k} * g;\r
          ENDIF\r
        ENDIF\r
      ENDFOR\r
    ENDFOR\r
  ENDPROC\r
\r
  ! Bring the state to now. A clock set back counts as no time.\r
  PROC RtWarmUpdate()\r
    VAR num day;\r
    VAR num minute;\r
    VAR num dt;\r
    RtNow day, minute;\r
    IF rtDay >= 0 THEN\r
      dt := (day - rtDay) * 1440 + (minute - rtMinute);\r
      IF dt > rtStopGap THEN\r
        RtAdvance dt, FALSE;\r
      ELSEIF dt > 0 THEN\r
        RtAdvance dt, TRUE;\r
      ENDIF\r
    ENDIF\r
    rtDay := day;\r
    rtMinute := minute;\r
  ENDPROC\r
\r
  ! The warm flange's move at joints j, robot base frame, mm.\r
  FUNC pos RtDrift(jointtarget j)\r
    VAR num t{6};\r
    VAR num q{6};\r
    VAR num e{4};\r
    VAR num sum;\r
    VAR num n;\r
    VAR num cx;\r
    VAR num cz;\r
    VAR num ax;\r
    VAR num ay;\r
    VAR num az;\r
    VAR num bx;\r
    VAR num bz;\r
    VAR num th23;\r
    VAR pos d;\r
    FOR a FROM 1 TO 6 DO\r
      t{a} := rtT0{a} + rtX{a,1} + rtX{a,2};\r
    ENDFOR\r
    FOR l FROM 1 TO 4 DO\r
      sum := 0;\r
      n := 0;\r
      FOR a FROM 1 TO 6 DO\r
        sum := sum + rtLinkMotor{l,a} * t{a};\r
        n := n + rtLinkMotor{l,a};\r
      ENDFOR\r
      e{l} := 0;\r
      IF n > 0 e{l} := rtGrow{l} * (sum / n - rtTref);\r
    ENDFOR\r
    q{1} := rtSign{1} * j.robax.rax_1 + rtOffset{1};\r
    q{2} := rtSign{2} * j.robax.rax_2 + rtOffset{2};\r
    q{3} := rtSign{3} * j.robax.rax_3 + rtOffset{3};\r
    q{4} := rtSign{4} * j.robax.rax_4 + rtOffset{4};\r
    q{5} := rtSign{5} * j.robax.rax_5 + rtOffset{5};\r
    q{6} := rtSign{6} * j.robax.rax_6 + rtOffset{6};\r
    th23 := q{2} + q{3};\r
    cx := rtC2 * e{2} * Sin(q{2}) + rtC3 * e{3} * Sin(th23) + rtA2 * e{3} * Cos(th23) + rtA1 * e{1};\r
    cz := rtC2 * e{2} * Cos(q{2}) + rtC3 * e{3} * Cos(th23) - rtA2 * e{3} * Sin(th23);\r
    ax := Cos(q{4}) * Sin(q{5});\r
    ay := Sin(q{4}) * Sin(q{5});\r
    az := Cos(q{5});\r
    bx := Cos(th23) * ax + Sin(th23) * az;\r
    bz := -Sin(th23) * ax + Cos(th23) * az;\r
    d.x := cx * Cos(q{1}) - rtB * e{1} * Sin(q{1}) + rtC4 * e{4} * (Cos(q{1}) * bx - Sin(q{1}) * ay);\r
    d.y := cx * Sin(q{1}) + rtB * e{1} * Cos(q{1}) + rtC4 * e{4} * (Sin(q{1}) * bx + Cos(q{1}) * ay);\r
    d.z := cz + rtC1 * e{1} + rtC4 * e{4} * bz;\r
    RETURN d;\r
  ENDFUNC\r
\r
  ! The base-frame drift in the world.\r
  FUNC pos RtWorld(pos d)\r
    VAR pose r;\r
    r.trans := [0, 0, 0];\r
    r.rot := rtBaseRot;\r
    RETURN PoseVect(r, d);\r
  ENDFUNC\r
\r
  ! A robtarget corrected for the arm's warmth now: the target that makes\r
  ! the warm robot reach what the cold one meant.\r
  FUNC robtarget RtWarm(robtarget p, PERS tooldata t \\PERS wobjdata WObj)\r
    VAR jointtarget j;\r
    VAR pos d;\r
    VAR pose obj;\r
    VAR robtarget out;\r
    RtWarmUpdate;\r
    ! A stationary tool, a work object the robot holds or one a mechanical\r
    ! unit moves: the target is left as it is (docs/runtime.md).\r
    IF NOT t.robhold RETURN p;\r
    IF Present(WObj) THEN\r
      IF WObj.robhold OR NOT WObj.ufprog RETURN p;\r
      j := CalcJointT(p, t \\WObj:=WObj);\r
    ELSE\r
      j := CalcJointT(p, t);\r
    ENDIF\r
    d := RtWorld(RtDrift(j));\r
    IF Present(WObj) THEN\r
      obj := PoseMult(WObj.uframe, WObj.oframe);\r
      obj.trans := [0, 0, 0];\r
      d := PoseVect(PoseInv(obj), d);\r
    ENDIF\r
    out := p;\r
    out.trans := p.trans - d;\r
    RETURN out;\r
  ENDFUNC\r
\r
  ! A jointtarget corrected likewise: its cold flange position, reached by\r
  ! the warm arm, in the configuration of its own joints.\r
  FUNC jointtarget RtWarmJ(jointtarget j)\r
    VAR robtarget p;\r
    VAR jointtarget out;\r
    RtWarmUpdate;\r
    p := CalcRobT(j, tool0);\r
    p.trans := p.trans - RtWorld(RtDrift(j));\r
    out := CalcJointT(p, tool0);\r
    out.extax := j.extax;\r
    RETURN out;\r
  ENDFUNC\r
";

/// Whether `name` can name the module: a RAPID name (a letter, then
/// letters, digits or `_`) of at most 31 characters, since its jointtarget
/// function adds a `J` and RAPID names are at most 32. A usage error
/// otherwise, raised while the plan is made, before anything is read.
/// The file the module named `name` is written to.
pub fn module_file(name: &str) -> String {
    format!("{name}.sys")
}

pub fn check_module_name(name: &str) -> crate::error::Result<()> {
    let ok = name.len() <= 31
        && name.bytes().next().is_some_and(|b| b.is_ascii_alphabetic())
        && name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_');
    if ok {
        return Ok(());
    }
    Err(crate::error::Error::usage(format!(
        "--runtime-module `{name}`: a RAPID name (a letter, then letters, digits or _; at most 31, its jointtarget function adds a J)"
    )))
}
