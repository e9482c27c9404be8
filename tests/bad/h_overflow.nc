; expect: 2:9: error: offset register H out of range: must be a whole number from 0 to 99999999
G21 G43 H6000000000
