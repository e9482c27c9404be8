; expect: 3:5: error: subprogram O7777 is not in this file
G21 G90 G0 X0 Y0 Z0
M98 P7777
M30
