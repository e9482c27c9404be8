; expect: 2:5: error: G65 (macro call) is macro B
G21 G65 P9010 A1.
