; expect: 3:9: error: canned cycle bottom Z above the R level
G21 G90 G0 X0 Y0 Z10.
G81 X1. Z5. R2. F100
