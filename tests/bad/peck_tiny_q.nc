; expect: 3:18: error: peck depth Q gives more than 10000000 pecks
G21 G90 G0 X0 Y0 Z10.
G83 X1. Z-1. R2. Q0.000000000001 F100
