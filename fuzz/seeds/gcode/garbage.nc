; expect: 2:11: error: unexpected character
G21 G0 X0 @
