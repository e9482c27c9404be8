; expect: 12:1: error: more than 10000000 motions (subprogram and canned-cycle repeats); --max-blocks raises the limit
G21 G90 G0 X0 Y0 Z0
M98 P1 L9999
M30
O1
M98 P2 L9999
M99
O2
M98 P3 L9999
M99
O3
G1 X1. F100
G1 X0
M99
