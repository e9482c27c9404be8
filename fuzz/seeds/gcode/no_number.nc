; expect: 2:8: error: address 'X' has no number
G21 G0 X
