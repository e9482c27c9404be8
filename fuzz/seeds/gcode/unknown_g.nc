; expect: 2:5: error: unknown G code G7
G21 G7 X1.
