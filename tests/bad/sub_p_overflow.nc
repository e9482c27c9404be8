; expect: 3:5: error: subprogram repeat count over 9999
G21 G90 G0 X0 Y0 Z0
M98 P429496729510010
M30
O10
M99
