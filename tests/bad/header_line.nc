; expect: 2:1: error: letters that form no word: 'p' is not followed by a number ('profile.nc')
profile.nc (Exported by FreeCAD)
G21 G90 G0 X0 Y0 Z5.
M30
