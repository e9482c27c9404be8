; expect: 3:1: error: macro B
G21 G90 G0 X0 Y0 Z0
#100=5.
G1 X#100 F100
