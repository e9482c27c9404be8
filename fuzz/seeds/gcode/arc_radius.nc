; expect: 3:13: error: arc end off the radius by 0.1000 mm
G21 G90 G0 X10. Y0 Z0
G3 X0 Y10.1 I-10. J0 F100
