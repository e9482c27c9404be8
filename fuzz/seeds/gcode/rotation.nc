; expect: 2:5: error: G68 (coordinate rotation) is not interpreted
G21 G68 X0 Y0 R30.
