%%%
  VERSION: 1
  LANGUAGE: ENGLISH
%%%

MODULE Prüfstand
  ! UTF-8 mit BOM: Prüfpunkte für die Maßkontrolle
  PERS wobjdata wMeß := [FALSE, TRUE, "", [[0, 0, 0], [1, 0, 0, 0]], [[0, 0, 0], [1, 0, 0, 0]]];
  CONST robtarget pMeßpunkt1 := [[450.25, -120.5, 300.125], [0.0, 0.0, 1.0, 0.0], [-1, 0, -1, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]];
  CONST robtarget pMeßpunkt2 := [[450.25, 120.5, 300.125], [0.0, 0.0, 1.0, 0.0], [0, 0, 0, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]];
  VAR string sText := "Größe ""A"" prüfen! (kein Kommentar)";

  PROC main()
    MoveJ pMeßpunkt1, v300, fine, tool0\WObj:=wMeß;
    TPWrite sText;
    MoveJ pMeßpunkt2, v300, fine, tool0\WObj:=wMeß;
    MoveL [[500, 0, 350.5], [0, 0, 1, 0], [0, 0, 0, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]], v300, fine, tool0\WObj:=wMeß;
  ENDPROC
ENDMODULE
