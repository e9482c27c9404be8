// The workpiece model's refusals, each before any mesh is made and located,
// a material without elastic constants, and `deflex stiffness --part`.
#include <doctest/doctest.h>

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "../support.hpp"
#include "deflex/cli/command.hpp"
#include "deflex/cli/exit.hpp"
#include "deflex/force/material.hpp"
#include "deflex/job/workpiece.hpp"
#include "deflex/stiffness/workpiece.hpp"
#include "helpers.hpp"
#include "workpiece_parts.hpp"

using namespace deflex;
using namespace deflex::stiffness;
using namespace deflex::stiffness::testing;
using test::error_of;
using V3 = Eigen::Vector3d;

namespace {

const std::string kMaterials = std::string(DEFLEX_SOURCE_DIR) + "/samples/materials.yaml";

job::WorkpieceSettings strip_job(const std::string& part) {
  job::WorkpieceSettings s;
  s.part = part;
  s.fixtures = {"box:-1,-1,-1,11,3,0.001"};
  s.points_mm = {V3(5, 1, 40)};
  s.material = "Al6082-T4";
  s.material_file = kMaterials;
  s.mesh_mm = 2;
  return s;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// An ASCII STL of the triangles, the last one left out when `open`.
std::string box_stl_text(bool open) {
  const double v[8][3] = {{0, 0, 0}, {10, 0, 0}, {10, 2, 0}, {0, 2, 0}, {0, 0, 40}, {10, 0, 40}, {10, 2, 40}, {0, 2, 40}};
  const int f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                        {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  std::ostringstream o;
  o << "solid box\n";
  for (int t = 0; t < (open ? 11 : 12); ++t) {
    o << " facet normal 0 0 0\n  outer loop\n";
    for (int k = 0; k < 3; ++k) o << "   vertex " << v[f[t][k]][0] << " " << v[f[t][k]][1] << " " << v[f[t][k]][2] << "\n";
    o << "  endloop\n endfacet\n";
  }
  o << "endsolid box\n";
  return o.str();
}

}  // namespace

TEST_SUITE("stiffness") {

TEST_CASE("workpiece: a fixture that holds nothing, no fixture, a point off the part: refused before meshing") {
  const test::TempDir dir("workpiece");
  const std::string strip = box_step(dir, "strip", 10, 2, 40);
  job::WorkpieceSettings s = strip_job(strip);
  s.fixtures = {"box:20,20,20,30,30,30"};
  std::string m = error_of([&] { job::workpiece_compliance(s); }, ErrorKind::settings);
  CHECK(has(m, "the fixture box box:20,20,20,30,30,30 touches no part of the surface of " + strip + ": nothing would hold it"));

  s = strip_job(strip);
  s.fixtures.clear();
  CHECK(has(error_of([&] { job::workpiece_compliance(s); }, ErrorKind::settings), "no fixture holds the part"));
  s.fixtures = {"box:1,2,3"};
  CHECK(has(error_of([&] { job::workpiece_compliance(s); }, ErrorKind::settings), "box:1,2,3"));

  s = strip_job(strip);
  s.points_mm = {V3(5, 1, 40), V3(5, 6, 20)};
  m = error_of([&] { job::workpiece_compliance(s); }, ErrorKind::settings);
  CHECK(has(m, "the point (5.000, 6.000, 20.000) is not on the part " + strip +
                   ": nearest surface point (5.000, 2.000, 20.000) at 4.000 mm"));
  s.points_mm = {V3(5, 2.5, 20)};  // half a millimetre off: on it
  s.mesh_mm = -1;
  CHECK(has(error_of([&] { job::workpiece_compliance(s); }, ErrorKind::settings), "mesh size must be >= 0"));
}

TEST_CASE("workpiece: a part that bounds no volume is refused: an open STL at its first open edge, a lone STEP face") {
  const test::TempDir dir("workpiece");
  test::write_file(dir / "open.stl", box_stl_text(true));
  std::string m = error_of([&] { read_part_surface(dir / "open.stl"); }, ErrorKind::config);
  CHECK(has(m, dir / "open.stl" + ": error: the part is not a closed solid: 3 edges of its surface border one triangle only"));
  test::write_file(dir / "closed.stl", box_stl_text(false));
  CHECK(read_part_surface(dir / "closed.stl").triangles.size() == 12);

  job::WorkpieceSettings s = strip_job(face_step(dir));
  s.fixtures = {"box:-1,-1,-1,11,11,1"};
  s.points_mm = {V3(5, 5, 0)};
  m = error_of([&] { job::workpiece_compliance(s); }, ErrorKind::config);
  CHECK(has(m, "face.step: error: the part is not a closed solid"));
}

TEST_CASE("workpiece: a material without elastic constants is refused at its entry, before the part is read") {
  const std::string head = "materials:\n  X:\n    model: mechanistic\n    K_tc_N_per_mm2: 700\n    K_rc_N_per_mm2: 200\n"
                           "    source: test\n";
  const test::TempDir dir("workpiece");
  test::write_file(dir / "m.yaml", head);
  job::WorkpieceSettings s = strip_job(dir / "missing.step");
  s.material = "X";
  s.material_file = dir / "m.yaml";
  const std::string m = error_of([&] { job::workpiece_compliance(s); }, ErrorKind::config);
  CHECK(has(m, dir / "m.yaml:3:5: error: material 'X' has no elastic: {E_MPa: .., poisson: ..}"));
}

TEST_CASE("deflex stiffness --part: the matrix, its principal compliances and the mesh, as text and JSON") {
  const test::TempDir dir("workpiece");
  const std::string strip = box_step(dir, "strip", 10, 2, 40);
  auto run = [&](std::vector<std::string> extra) {
    std::vector<std::string> args{"--part", strip, "--fixture", "box:-1,-1,-1,11,3,0.001", "--at", "5,1,40",
                                  "--material", "Al6082-T4", "--material-file", kMaterials, "--mesh-mm", "2"};
    args.insert(args.end(), extra.begin(), extra.end());
    std::istringstream in;
    std::ostringstream out, err;
    cli::Io io{{in, out, err}};
    CHECK(cli::cmd_stiffness(args, io) == 0);
    return out.str();
  };
  const std::string text = run({"--at", "10,1,20"});
  CHECK(has(text, "material Al6082-T4 (E 70000 MPa, nu 0.33), held by box:-1,-1,-1,11,3,0.001"));
  CHECK(has(text, "point (5.000, 1.000, 40.000) mm"));
  CHECK(has(text, "point (10.000, 1.000, 20.000) mm"));
  CHECK(has(text, "principal compliances (um/N along the direction):"));
  CHECK(has(text, "quadratic tets"));
  const auto j = nlohmann::json::parse(run({"--format", "json"}));
  REQUIRE(j["points"].size() == 1);
  const auto& c = j["points"][0]["compliance_mm_per_N"];
  CHECK(c[1][1].get<double>() > 0.03);  // the strip's bending, ~0.046 mm/N
  CHECK(c[0][1].get<double>() == deflex::test::within(c[1][0].get<double>(), 1e-6));
  CHECK(j["mesh"]["dofs"].get<int>() > 0);
  CHECK(j["E_MPa"].get<double>() == 70000);

  std::istringstream in;
  std::ostringstream out, err;
  cli::Io io{{in, out, err}};
  CHECK(cli::cmd_stiffness({"--help"}, io) == 0);
  CHECK(has(out.str(), "--fixture"));
  CHECK(has(out.str(), "every mesh node on its surface"));
  auto code = [&](std::vector<std::string> args) {
    try {
      cli::cmd_stiffness(args, io);
    } catch (const Error& e) {
      return cli::exit_code(e.kind());
    }
    return cli::Exit::ok;
  };
  CHECK(code({"--part", strip, "--fixture", "box:-1,-1,-1,11,3,0.001", "--at", "5,1"}) == cli::Exit::usage);
  CHECK(code({"--part", strip, "--tool", "T1", "--at", "5,1,40"}) == cli::Exit::usage);
  CHECK(code({"--tool-file", "x.yaml", "--tool", "T1", "--fixture", "box:0,0,0,1,1,1"}) == cli::Exit::usage);
}

}  // TEST_SUITE
