; expect: 3:20: error: repeat count must be a whole number from 0 to 9999
G21 G90 G0 X0 Y0 Z10.
G81 X1. Z-1. R2. K99999999999 F100
