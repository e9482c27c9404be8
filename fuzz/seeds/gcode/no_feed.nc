; expect: 3:4: error: G1 move with no feed rate
G21 G90 G0 X0 Y0 Z0
G1 X10.
