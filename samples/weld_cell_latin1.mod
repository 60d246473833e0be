MODULE SchweissZelle
    ! Schweißzelle 3: Nahtfolge für Bauteil « Träger » (Latin-1, CRLF)
    ! Programmé par l'équipe de maintenance, révision B
    PERS tooldata tBrenner := [TRUE, [[0, 0, 180], [0.965926, 0, 0.258819, 0]], [2.5, [0, 0, 80], [1, 0, 0, 0], 0, 0, 0]];
    PERS wobjdata wTräger := [FALSE, TRUE, "", [[0, 0, 10], [1, 0, 0, 0]], [[0, 0, 0], [1, 0, 0, 0]]];
    CONST robtarget pNahtAnfang := [[470, -60, 155], [0, 0, 1, 0], [-1, 0, -1, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]];
    CONST robtarget pNahtMitte := [[530, -60, 155.5], [0, 0, 1, 0], [-1, 0, -1, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]];
    CONST robtarget pNahtEnde := [[630, -60, 156], [0, 0, 1, 0], [-1, 0, -1, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]];
    ! Anfahrpunkt über der Naht « Höhe 50 mm »
    CONST robtarget pÜber := [[470, -60, 205], [0, 0, 1, 0], [-1, 0, -1, 0], [9E+09, 9E+09, 9E+09, 9E+09, 9E+09, 9E+09]];
    VAR string sMeldung := "Naht fertig: Qualität prüfen";

    PROC Naht1()
        ! Anfahren
        MoveJ pÜber, v500, z20, tBrenner\WObj:=wTräger;
        MoveL pNahtAnfang, v100, fine, tBrenner\WObj:=wTräger;
        MoveL pNahtMitte, v20, z1, tBrenner\WObj:=wTräger;
        MoveL pNahtEnde, v20, fine, tBrenner\WObj:=wTräger;
        MoveL Offs(pNahtEnde, 0, 0, 50), v200, z20, tBrenner\WObj:=wTräger;
        TPWrite sMeldung;
    ENDPROC
ENDMODULE
