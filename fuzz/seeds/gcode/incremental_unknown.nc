; expect: 2:12: error: incremental X move before the X position is known
G21 G91 G0 X5.
