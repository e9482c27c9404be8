; expect: 2:5: error: G52 (local coordinate system) is not interpreted
G21 G52 X10.
