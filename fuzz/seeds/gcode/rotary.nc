; expect: 2:21: error: axis A: deflex reads 3-axis programs
G21 G90 G0 X0 Y0 Z0 A90.
