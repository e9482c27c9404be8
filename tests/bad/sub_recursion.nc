; expect: 6:5: error: subprograms nested deeper than 8
G21 G90 G0 X0 Y0 Z0
M98 P1
M30
O1
M98 P1
M99
