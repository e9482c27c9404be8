; expect: 3:7: error: the letter 'O' where a digit was expected
G21 G90 G0 X0. Y0. Z5.
G1 X11O. Y2. F100.
M30
