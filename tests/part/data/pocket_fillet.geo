// The pocketed block of tests/part/test_part_import.cpp built by gmsh's
// OpenCASCADE kernel and written as STEP by gmsh (beside the file the test
// writes with OCCT's STEPControl_Writer itself; gmsh 4.8 builds the B-rep by
// its own calls and writes it through OCCT's STEP processor too):
//   gmsh -0 pocket_fillet.geo -o pocket_fillet_gmsh.step
// (or gmshOpen + gmshWrite through its API, as this copy was written, gmsh 4.8.4).
// A 100 x 100 x 30 block (z from -30 to 0) less a 60 x 60 x 12 pocket in its
// middle; the pocket's four vertical edges rounded R5, its rim R2.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, -30, 100, 100, 30};
Box(2) = {20, 20, -12, 60, 60, 13};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
e = 1e-3;
corners() = Curve In BoundingBox{20 - e, 20 - e, -12 - e, 80 + e, 80 + e, e};
edges() = {};
radii() = {};
For i In {0 : #corners() - 1}
  bb() = BoundingBox Curve{corners(i)};
  If (bb(3) - bb(0) < e && bb(4) - bb(1) < e)
    edges() += corners(i);
    radii() += 5;
  ElseIf (bb(2) > -e)
    edges() += corners(i);
    radii() += 2;
  EndIf
EndFor
Fillet{3}{edges()}{radii()}
