; expect: 3:12: error: R4.0000 mm is too small for the 10.0000 mm chord
G21 G90 G0 X0 Y0 Z0
G2 X10. Y0 R4. F100
