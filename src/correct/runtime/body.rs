//! The module's routines, the same for every arm (the numbers are the
//! arm's, written above them by [`super::module`]). `@N` stands for the
//! module's name: the five global routines are `@N`, `@NJ`, `@NT`,
//! `@NJT` and `@NReset`; everything else is LOCAL, so that the module
//! adds no other name to the task. Each step is the one `mirror`
//! computes; docs/runtime.md says, instruction by instruction, what ABB's
//! manual says of it.

/// The routines, `@N` for the module's name, CRLF line ends.
pub fn routines(name: &str) -> String {
    BODY.replace("@N", name).replace('\n', "\r\n")
}

const BODY: &str = r#"
  ! The operator's cold start: the next correction starts from a cold arm.
  PROC @NReset()
    FOR a FROM 1 TO 6 DO
      FOR k FROM 1 TO 2 DO
        rtX{a,k} := 0;
      ENDFOR
    ENDFOR
    rtKnown := FALSE;
    rtOn := FALSE;
    ErrWrite \I, "@N: reset", "The heating state was set to a cold arm by @NReset.";
  ENDPROC

  ! Days from 2000-01-01 to a date (days from civil, integer DIV); negative
  ! before 2000.
  LOCAL FUNC num rtDays(num y, num m, num d)
    VAR num yy;
    VAR num era;
    VAR num yoe;
    VAR num mp;
    VAR num doy;
    VAR num doe;
    yy := y;
    IF m <= 2 yy := yy - 1;
    IF yy >= 0 THEN
      era := yy DIV 400;
    ELSE
      era := (yy - 399) DIV 400;
    ENDIF
    yoe := yy - era * 400;
    IF m > 2 THEN
      mp := m - 3;
    ELSE
      mp := m + 9;
    ENDIF
    doy := (153 * mp + 2) DIV 5 + d - 1;
    doe := yoe * 365 + yoe DIV 4 - yoe DIV 100 + doy;
    RETURN era * 146097 + doe - 730425;
  ENDFUNC

  ! The controller's clock, read once: the date, the time, the date again
  ! (midnight between: both again), so the day and the time are one
  ! moment's. Day since 2000 and minute of the day, apart so that single
  ! precision keeps the seconds.
  LOCAL PROC rtNow(INOUT num day, INOUT num minute)
    VAR string date;
    VAR string time;
    VAR num y;
    VAR num mo;
    VAR num d;
    VAR num h;
    VAR num mi;
    VAR num s;
    VAR bool ok;
    date := CDate();
    time := CTime();
    IF CDate() <> date THEN
      date := CDate();
      time := CTime();
    ENDIF
    ok := StrToVal(StrPart(date, 1, 4), y);
    ok := StrToVal(StrPart(date, 6, 2), mo);
    ok := StrToVal(StrPart(date, 9, 2), d);
    ok := StrToVal(StrPart(time, 1, 2), h);
    ok := StrToVal(StrPart(time, 4, 2), mi);
    ok := StrToVal(StrPart(time, 7, 2), s);
    day := rtDays(y, mo, d);
    minute := h * 60 + mi + s / 60;
  ENDPROC

  ! dt minutes running (heating) or stopped (cooling), exactly.
  LOCAL PROC rtAdvance(num dt, bool running)
    VAR num u;
    VAR num g;
    FOR a FROM 1 TO 6 DO
      FOR k FROM 1 TO 2 DO
        IF rtTau{a,k} > 0 THEN
          u := dt / rtTau{a,k};
          ! 1 - e^-u; by its series where Exp would lose the digits.
          IF u < 0.01 THEN
            g := u * (1 - u / 2 * (1 - u / 3 * (1 - u / 4)));
          ELSE
            g := 1 - Exp(-u);
          ENDIF
          IF running THEN
            rtX{a,k} := rtX{a,k} + (rtRise{a,k} - rtX{a,k}) * g;
          ELSE
            rtX{a,k} := rtX{a,k} - rtX{a,k} * g;
          ENDIF
        ENDIF
      ENDFOR
    ENDFOR
  ENDPROC

  ! Each link's growth now (1 over its cold length), from the motors'.
  LOCAL PROC rtGrowth()
    VAR num t{6};
    VAR num e{4};
    VAR num sum;
    VAR num n;
    FOR a FROM 1 TO 6 DO
      t{a} := rtT0{a} + rtX{a,1} + rtX{a,2};
    ENDFOR
    FOR l FROM 1 TO 4 DO
      sum := 0;
      n := 0;
      FOR a FROM 1 TO 6 DO
        sum := sum + rtLinkMotor{l,a} * t{a};
        n := n + rtLinkMotor{l,a};
      ENDFOR
      e{l} := 0;
      IF n > 0 e{l} := rtGrow{l} * (sum / n - rtTref);
    ENDFOR
    rtE1 := e{1};
    rtE2 := e{2};
    rtE3 := e{3};
    rtE4 := e{4};
  ENDPROC

  ! Bring the state to now. The time that passed is the running clock's
  ! (a clock set by hand, a summer time or a time sync is no time); the
  ! controller's date and time only since the module last ran (a load, a
  ! P-start, a restart), where the clock does not run. Each case the
  ! operator should know is written to the event log.
  LOCAL PROC rtUpdate()
    VAR num day;
    VAR num minute;
    VAR num wall;
    VAR num dt;
    rtNow day, minute;
    wall := (day - rtDay) * 1440 + (minute - rtMinute);
    dt := 0;
    IF rtOn THEN
      dt := rtElapsed() / 60;
    ENDIF
    IF NOT rtKnown THEN
      dt := 0;
      ErrWrite \I, "@N: cold start", "No heating state was kept: the corrections start from a cold arm." \RL2:="@NReset sets the state to a cold arm at any time.";
    ELSEIF rtOn THEN
      IF Abs(wall - dt) > rtJump THEN
        ErrWrite \W, "@N: clock jumped", "The date and time moved " + NumToStr(wall, 1) + " min in " + NumToStr(dt, 1) + " min of running." \RL2:="A clock set, or a power failure: the running clock's time is taken.";
      ENDIF
    ELSEIF wall < 0 THEN
      ErrWrite \W, "@N: clock behind", "The date and time are " + NumToStr(-wall, 1) + " min before the last correction." \RL2:="No time is taken to have passed.";
    ELSE
      dt := wall;
      ErrWrite \I, "@N: started", "The heating state was kept; " + NumToStr(dt, 1) + " min since the last correction.";
    ENDIF
    IF dt > rtStopGap THEN
      ErrWrite \I, "@N: robot stood", "No correction for " + NumToStr(dt, 1) + " min: the arm cooled for that time.";
      rtAdvance dt, FALSE;
    ELSEIF dt > 0 THEN
      rtAdvance dt, TRUE;
    ENDIF
    rtKnown := TRUE;
    rtDay := day;
    rtMinute := minute;
    ClkReset rtClk;
    ClkStart rtClk;
    rtOn := TRUE;
    rtGrowth;
  ENDPROC

  ! Seconds on the running clock since the last update. A clock run past
  ! what it holds (ClkRead: ERR_OVERFLOW after about 49 days without a
  ! correction) counts as not running: the date and time take over.
  LOCAL FUNC num rtElapsed()
    RETURN ClkRead(rtClk);
  ERROR
    IF ERRNO = ERR_OVERFLOW THEN
      rtOn := FALSE;
      RETURN 0;
    ENDIF
    RAISE;
  ENDFUNC

  ! The state brought to now where the last update is older than rtEvery
  ! seconds (a clock that is not running: since loading or a P-start).
  LOCAL PROC rtFresh()
    VAR num since;
    IF rtOn THEN
      since := rtElapsed();
      IF rtOn AND since < rtEvery RETURN;
    ENDIF
    rtUpdate;
  ENDPROC

  ! The warm flange's move at joints j, in the world frame, mm.
  LOCAL FUNC pos rtDrift(jointtarget j)
    VAR num q{6};
    VAR num cx;
    VAR num cz;
    VAR num ax;
    VAR num ay;
    VAR num az;
    VAR num bx;
    VAR num bz;
    VAR num th23;
    VAR pos d;
    VAR pose r;
    q{1} := rtSign{1} * j.robax.rax_1 + rtOffset{1};
    q{2} := rtSign{2} * j.robax.rax_2 + rtOffset{2};
    q{3} := rtSign{3} * j.robax.rax_3 + rtOffset{3};
    q{4} := rtSign{4} * j.robax.rax_4 + rtOffset{4};
    q{5} := rtSign{5} * j.robax.rax_5 + rtOffset{5};
    q{6} := rtSign{6} * j.robax.rax_6 + rtOffset{6};
    th23 := q{2} + q{3};
    cx := rtC2 * rtE2 * Sin(q{2}) + rtC3 * rtE3 * Sin(th23) + rtA2 * rtE3 * Cos(th23) + rtA1 * rtE1;
    cz := rtC2 * rtE2 * Cos(q{2}) + rtC3 * rtE3 * Cos(th23) - rtA2 * rtE3 * Sin(th23);
    ax := Cos(q{4}) * Sin(q{5});
    ay := Sin(q{4}) * Sin(q{5});
    az := Cos(q{5});
    bx := Cos(th23) * ax + Sin(th23) * az;
    bz := -Sin(th23) * ax + Cos(th23) * az;
    d.x := cx * Cos(q{1}) - rtB * rtE1 * Sin(q{1}) + rtC4 * rtE4 * (Cos(q{1}) * bx - Sin(q{1}) * ay);
    d.y := cx * Sin(q{1}) + rtB * rtE1 * Cos(q{1}) + rtC4 * rtE4 * (Sin(q{1}) * bx + Cos(q{1}) * ay);
    d.z := cz + rtC1 * rtE1 + rtC4 * rtE4 * bz;
    r.trans := [0, 0, 0];
    r.rot := rtBaseRot;
    RETURN PoseVect(r, d);
  ENDFUNC

  ! What to add to a target's position so that the warm robot reaches
  ! what the cold one meant, for a world drift d of the flange. A tool
  ! the robot holds: the drift undone, in the target's frame (the work
  ! object, under the active program displacement). A stationary tool
  ! (the robot holds the work): the work moved by d seen from the tool,
  ! so the target moves with it, turned by the target's own rotation.
  LOCAL FUNC pos rtShift(pos d, robtarget p, PERS tooldata t \PERS wobjdata WObj)
    VAR pose r;
    VAR pos v;
    r.trans := [0, 0, 0];
    IF NOT t.robhold THEN
      r.rot := t.tframe.rot;
      v := PoseVect(PoseInv(r), d);
      r.rot := p.rot;
      RETURN PoseVect(r, v);
    ENDIF
    IF Present(WObj) THEN
      IF NOT WObj.ufprog THEN
        ! A user frame a mechanical unit moves (coordinated motion): its
        ! turn at the move is not known here.
        ErrWrite "@N: target as written", "Its work object moves with " + WObj.ufmec + ":" \RL2:="coordinated motion is not corrected.";
        RETURN [0, 0, 0];
      ENDIF
      r := PoseMult(PoseMult(WObj.uframe, WObj.oframe), C_PROGDISP.pdisp);
    ELSE
      r := C_PROGDISP.pdisp;
    ENDIF
    r.trans := [0, 0, 0];
    RETURN -1 * PoseVect(PoseInv(r), d);
  ENDFUNC

  ! A robtarget the table knows (row r: its cold joints' drift per unit
  ! growth of each link), corrected for the arm's warmth now: a lookup,
  ! four products and a turn into its frame.
  FUNC robtarget @NT(robtarget p, num r, PERS tooldata t \PERS wobjdata WObj)
    VAR robtarget out;
    ! Under a program displacement the arm stands elsewhere than the row's
    ! joints: the controller's joints, by the slower path.
    IF C_PROGDISP.pdisp.rot.q1 < 1 OR C_PROGDISP.pdisp.trans.x <> 0 OR C_PROGDISP.pdisp.trans.y <> 0 OR C_PROGDISP.pdisp.trans.z <> 0 RETURN @N(p, t \WObj?WObj);
    rtFresh;
    out := p;
    out.trans := p.trans + rtShift(rtE1 * rtD{r,1} + rtE2 * rtD{r,2} + rtE3 * rtD{r,3} + rtE4 * rtD{r,4}, p, t \WObj?WObj);
    RETURN out;
  ENDFUNC

  ! A robtarget the program computes at run time, corrected likewise: its
  ! joints from the controller (CalcJointT, in its own configuration).
  ! Where the controller finds none, the target goes as written, said.
  FUNC robtarget @N(robtarget p, PERS tooldata t \PERS wobjdata WObj)
    VAR jointtarget j;
    VAR robtarget out;
    rtFresh;
    j := CalcJointT(p, t \WObj?WObj);
    out := p;
    out.trans := p.trans + rtShift(rtDrift(j), p, t \WObj?WObj);
    RETURN out;
  ERROR
    IF ERRNO = ERR_ROBLIMIT OR ERRNO = ERR_OUTSIDE_REACH THEN
      ErrWrite "@N: target as written", "The controller finds no joints for it in its configuration:" \RL2:="it is moved to as written.";
      RETURN p;
    ENDIF
    RAISE;
  ENDFUNC

  ! A jointtarget the table knows (row r: its joints' change per unit
  ! growth of each link, the same pose on the warm arm with the joints
  ! nearest the written ones; no configuration involved).
  FUNC jointtarget @NJT(jointtarget j, num r)
    VAR jointtarget out;
    VAR pos a;
    VAR pos b;
    rtFresh;
    a := rtE1 * rtGa{r,1} + rtE2 * rtGa{r,2} + rtE3 * rtGa{r,3} + rtE4 * rtGa{r,4};
    b := rtE1 * rtGb{r,1} + rtE2 * rtGb{r,2} + rtE3 * rtGb{r,3} + rtE4 * rtGb{r,4};
    out := j;
    out.robax.rax_1 := j.robax.rax_1 + a.x;
    out.robax.rax_2 := j.robax.rax_2 + a.y;
    out.robax.rax_3 := j.robax.rax_3 + a.z;
    out.robax.rax_4 := j.robax.rax_4 + b.x;
    out.robax.rax_5 := j.robax.rax_5 + b.y;
    out.robax.rax_6 := j.robax.rax_6 + b.z;
    RETURN out;
  ENDFUNC

  ! Whether two jointtargets' robot axes are within a degree of each other.
  LOCAL FUNC bool rtNear(jointtarget a, jointtarget b)
    RETURN Abs(a.robax.rax_1 - b.robax.rax_1) < 1 AND Abs(a.robax.rax_2 - b.robax.rax_2) < 1 AND Abs(a.robax.rax_3 - b.robax.rax_3) < 1 AND Abs(a.robax.rax_4 - b.robax.rax_4) < 1 AND Abs(a.robax.rax_5 - b.robax.rax_5) < 1 AND Abs(a.robax.rax_6 - b.robax.rax_6) < 1;
  ENDFUNC

  ! A jointtarget the program computes at run time: its cold flange pose,
  ! reached by the warm arm, solved by the controller in the written
  ! joints' configuration. No solution there, or one that turns an axis
  ! by a degree or more (a wrist across a quadrant): the joints go as
  ! written, said.
  FUNC jointtarget @NJ(jointtarget j)
    VAR robtarget p;
    VAR jointtarget out;
    rtFresh;
    p := CalcRobT(j, tool0);
    p.trans := p.trans + rtShift(rtDrift(j), p, tool0);
    out := CalcJointT(p, tool0);
    out.extax := j.extax;
    IF NOT rtNear(out, j) THEN
      ErrWrite "@N: joints as written", "Its warm joints lie in another configuration:" \RL2:="it is moved to as written.";
      RETURN j;
    ENDIF
    RETURN out;
  ERROR
    IF ERRNO = ERR_ROBLIMIT OR ERRNO = ERR_OUTSIDE_REACH THEN
      ErrWrite "@N: joints as written", "The controller finds no joints for it in its configuration:" \RL2:="it is moved to as written.";
      RETURN j;
    ENDIF
    RAISE;
  ENDFUNC
"#;
