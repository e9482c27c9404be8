; expect: 2:11: error: comment not closed
G21 G0 X0 (never closed
