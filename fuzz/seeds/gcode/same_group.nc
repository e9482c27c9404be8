; expect: 2:8: error: G1 and G0 are in the same modal group
G21 G0 G1 X1
