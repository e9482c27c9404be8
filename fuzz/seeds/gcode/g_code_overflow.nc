; expect: 2:5: error: G2199999999 is not a G code
G21 G2199999999
