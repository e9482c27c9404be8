; expect: 2:5: error: tool number T out of range: must be a whole number from 0 to 99999999
G21 T99999999999 M6
