; expect: 2:5: error: M3870000000 is not an M code
G21 M3870000000
