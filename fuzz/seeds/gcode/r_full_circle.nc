; expect: 3:12: error: R-form arc whose end is its start: a full circle cannot be written with R
G21 G90 G0 X10. Y0 Z0
G2 X10. Y0 R5. F100
