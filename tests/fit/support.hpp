// Helpers of the fit's tests: a hidden machine (mill3 changed as a shop's
// machine might differ from its profile), the four-wall program, and a
// program's surface simulated on a machine the ordinary way.
#pragma once
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "../job/support.hpp"
#include "deflex/fit/solve.hpp"
#include "deflex/fit/surface.hpp"

namespace deflex::test {

inline const std::string kSrc = DEFLEX_SOURCE_DIR;

inline std::string read(const std::string& path) {
  std::ifstream f(path);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

inline void replace(std::string& s, const std::string& from, const std::string& to) {
  const std::size_t at = s.find(from);
  REQUIRE(at != std::string::npos);
  s.replace(at, from.size(), to);
}

// mill3 with its structure X and Y stiffer (x1.4, x1.2: 84 and 60 N/um, 40 %
// apart), its clamp x0.6, and forces x1.2 (force_scale).
inline std::string hidden_machine(const TempDir& dir, bool softer_clamp = true, bool harder_forces = true) {
  std::string t = read(kSrc + "/samples/machines/mill3.yaml");
  if (softer_clamp) {
    replace(t, "radial_N_per_um: 400", "radial_N_per_um: 240");
    replace(t, "rotational_Nm_per_rad: 6.0e5", "rotational_Nm_per_rad: 3.6e5");
    replace(t, "axial_N_per_um: 500", "axial_N_per_um: 300");
  }
  replace(t, "{x: 60, y: 50, z: 150}", "{x: 84, y: 60, z: 150}");
  if (harder_forces) t += "force_scale: 1.2\n";
  const std::string path = dir / "hidden.yaml";
  std::ofstream(path) << t;
  return path;
}

inline job::Settings walls(const std::string& machine) {
  job::Settings s;
  s.program = kSrc + "/tests/data/fit/walls_xy.nc";
  s.read.machine = machine;
  s.tool_file = kSrc + "/samples/tools.yaml";
  s.material.material = "Al6082-T4";
  s.material.material_file = kSrc + "/samples/materials.yaml";
  s.stock = "box:0,0,-20,100,100,0";
  return s;
}

// Every sample of the program's surface simulated on `machine`, as the
// ordinary simulation gives it (not through the fit's basis).
struct Simulated {
  std::vector<compensate::Point> points;
  std::unique_ptr<fit::Surface> surface;
  std::vector<double> errors;
};
inline Simulated simulate_on(const job::Settings& s) {
  Streams st;
  job::Run run = job::open(s, job::Purpose::fit, st.io);
  compensate::Settings cs = run.settings;
  cs.flank_profiles = true;
  Simulated r;
  r.points = compensate::simulate(run.motions, {}, run.physics, cs);
  r.surface = std::make_unique<fit::Surface>(r.points, job::tool_of(run));
  r.errors = r.surface->errors(r.points);
  return r;
}

// Every fitted parameter within 5 % of `truth`, the truth inside its 95 %
// interval; a held one says why; each of `must_fit` fitted.
inline void check_recovered(const fit::FitResult& r, const fit::Scales& truth, std::initializer_list<fit::Param> must_fit) {
  for (int k = 0; k < fit::kParams; ++k) {
    const fit::ParamFit& p = r.params[k];
    CAPTURE(fit::name(fit::Param(k)));
    CAPTURE(p.scale);
    CAPTURE(p.lo95);
    CAPTURE(p.hi95);
    CAPTURE(p.why_held);
    CHECK(p.fitted == p.why_held.empty());
    if (!p.fitted) continue;
    CHECK(std::abs(p.scale / truth[k] - 1) < 0.05);
    CHECK(p.lo95 <= truth[k]);
    CHECK(truth[k] <= p.hi95);
  }
  for (fit::Param p : must_fit) CHECK(r.params[int(p)].fitted);
}

}  // namespace deflex::test
