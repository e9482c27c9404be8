; expect: 3:9: error: subprogram repeat count L out of range: must be a whole number from 0 to 9999
G21 G90 G0 X0 Y0 Z0
M98 P10 L-3000000000
M30
O10
M99
