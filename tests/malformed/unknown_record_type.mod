MODULE Weld
  ! seamtarget is defined in a system module that is not read here.
  PERS seamtarget sSeam := [[[450, 0, 200], [0, 0, 1, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]], 5];
  CONST robtarget pHome := [[515, 0, 610], [0, 0, 1, 0], [0, 0, 0, 0], [9E9, 9E9, 9E9, 9E9, 9E9, 9E9]];
ENDMODULE
