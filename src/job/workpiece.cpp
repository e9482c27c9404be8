// job::workpiece_compliance() (workpiece.hpp).
#include "deflex/job/workpiece.hpp"

#include <cmath>

#include "deflex/diag/diagnostics.hpp"
#include "workpiece_run.hpp"
#include "deflex/force/material.hpp"
#include "deflex/job/setup.hpp"
#include "deflex/profile/profile.hpp"

namespace deflex::job {

namespace detail {

// The named entry's elastic constants; an entry without them is a config
// error at its line.
stiffness::Material elastic_of(const std::string& name, const std::string& library) {
  if (name.empty()) throw Error(ErrorKind::settings, "give {material} M: the workpiece's material, with its elastic constants");
  const force::MaterialLibrary lib = force::load_material_library(library);
  const force::MaterialEntry& m = force::find_material(lib, name);
  if (!m.elastic)
    throw Error(ErrorKind::config, m.location + ": error: material '" + m.name +
                                       "' has no elastic: {E_MPa: .., poisson: ..}: the workpiece's compliance needs them");
  stiffness::Material e;
  e.name = m.name;
  e.E_MPa = m.elastic->E_MPa;
  e.poisson = m.elastic->poisson;
  return e;
}

}  // namespace detail

namespace {

namespace st = deflex::stiffness;

void check_settings(const WorkpieceSettings& s) {
  if (s.part.empty()) throw Error(ErrorKind::settings, "the workpiece's compliance needs the part model: {part} P (STEP, IGES or a closed STL)");
  if (s.fixtures.empty())
    throw Error(ErrorKind::settings, "no fixture holds the part: give at least one box:X0,Y0,Z0,X1,Y1,Z1 around "
                                     "the faces the vice or clamps hold");
  if (s.points_mm.empty()) throw Error(ErrorKind::settings, "give at least one point X,Y,Z of the part's surface");
  for (const auto& p : s.points_mm)
    if (!p.allFinite()) throw Error(ErrorKind::settings, "a point of the part's surface must be finite numbers X,Y,Z (mm)");
  if (!(s.mesh_mm >= 0) || !std::isfinite(s.mesh_mm))
    throw Error(ErrorKind::settings, "the workpiece's mesh size must be >= 0 mm (0: half the thinnest wall)");
}

void read_material(const WorkpieceSettings& s, WorkpieceResult& r) {
  const profile::Config cfg = profile::load_config();
  r.material_file = material_library_path(s.material_file, cfg);
  r.elastic = detail::elastic_of(!s.material.empty() ? s.material : config_string(cfg, "material"), r.material_file);
  r.material = r.elastic.name;
}

}  // namespace

WorkpieceResult workpiece_compliance(const WorkpieceSettings& s) {
  check_settings(s);
  std::vector<st::Fixture> fixtures;
  for (const auto& f : s.fixtures) fixtures.push_back(st::parse_fixture(f));
  WorkpieceResult r;
  r.part = s.part;
  read_material(s, r);
  const st::PartSurface surface = st::read_part_surface(s.part);
  st::check_fixtures(surface, fixtures);
  st::WorkpieceOptions o;
  o.mesh_mm = s.mesh_mm;
  for (const auto& p : s.points_mm) st::check_on_part(surface, p, o.on_part_mm);
  const st::WorkpieceModel model(surface, fixtures, r.elastic, o);
  r.points = model.compliance_at(s.points_mm);
  r.mesh = model.info();
  return r;
}

}  // namespace deflex::job
