; expect: 2:5: error: G51 (scaling/mirror) is not interpreted
G21 G51 X0 Y0 P2000
