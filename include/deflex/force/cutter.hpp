// Helical end-mill geometry sliced along the tool axis for the force model.
//
// Frame: z is measured upward from the tool tip along the spindle axis (mm).
// Generalized geometry after Engin & Altintas 2001 (Part I): every point of a
// cutting edge has a local radius r(z), an axial immersion angle kappa(z) (angle
// between the tool axis and the local surface normal; pi/2 on the cylinder) and
// a lag angle psi(z) behind the edge's point at the tip.
#pragma once
#include <string>
#include <vector>

#include "deflex/stock/end_shape.hpp"

namespace deflex::force {

// The cutting part of a helical end mill. For a ball end the corner radius is
// D/2 (it is ignored); for a flat end mill it is 0.
struct Cutter {
  stock::EndShape type = stock::EndShape::flat;
  double diameter_mm = 10.0;
  double corner_radius_mm = 0.0;  // bull nose only
  int flutes = 2;
  double helix_deg = 30.0;        // helix angle i0 on the cylinder, right-hand
  double flute_length_mm = 20.0;  // cutting length above the tip
};

// Throws deflex::Error(ErrorKind::config) when the geometry cannot be cut with.
void validate(const Cutter& c);

// Radius of the corner arc of the profile (0 flat, D/2 ball, r_c bull nose).
double corner_radius_of(const Cutter& c);

// Geometry of one edge point at height z above the tip.
struct EdgePoint {
  double r_mm = 0;       // distance from the tool axis
  double sin_kappa = 1;  // axial immersion angle kappa: sin, cos
  double cos_kappa = 0;
  double lag = 0;        // psi, rad: the edge at z trails its tip point by psi
};

// Lee & Altintas 1996 (ball), Engin & Altintas 2001 (torus, cylinder): a
// constant-lead flute, so psi(z) = z tan(i0) / R0 on every segment.
EdgePoint edge_point(const Cutter& c, double z_mm);

// One axial slice [z_lo, z_hi] of the cutter, evaluated at its mid height.
struct Slice {
  double z_mm = 0;         // mid height above the tip
  double r_mm = 0;         // local radius at z_mm
  double sin_kappa = 1;
  double cos_kappa = 0;
  double lag = 0;          // psi at z_mm, rad
  double width_mm = 0;     // chip width db = dz / sin(kappa) (Lee & Altintas 1996)
  double edge_mm = 0;      // edge length dS carrying the edge forces (= width_mm, see cutter.cpp)
};

// A cutter cut into equal slices of height dz from the tip up to `length_mm`.
// Slice i covers z in [i dz, (i+1) dz]; the engagement must use the same slicing.
struct CutterSlices {
  Cutter cutter;
  double dz_mm = 0;
  std::vector<Slice> slices;
  double pitch() const;  // tooth pitch angle 2 pi / flutes, rad
};

// Slices of height ~dz_mm (adjusted so that an integer number fills length_mm).
CutterSlices make_slices(const Cutter& c, double dz_mm, double length_mm);

}  // namespace deflex::force
