; expect: 2:11: error: two X words in one block
G21 G0 X0 X1.
