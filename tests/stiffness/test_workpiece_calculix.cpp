// The workpiece model against an independent solver: CalculiX (ccx, Debian's
// calculix-ccx; scripts/install-deps.sh --test installs it) on the same
// cantilever strip with its own element, 20-node hexahedra with reduced
// integration (C3D20R), on a structured mesh written here. The suite
// stiffness_calculix; skipped where ccx is absent.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "../support.hpp"
#include "deflex/stiffness/workpiece.hpp"
#include "workpiece_parts.hpp"

using namespace deflex;
using namespace deflex::stiffness;
using namespace deflex::stiffness::testing;
using V3 = Eigen::Vector3d;

namespace {

bool have_ccx() { return std::system("command -v ccx > /dev/null 2>&1") == 0; }

// A structured C3D20R mesh of the box [0,X]x[0,Y]x[0,Z] with n elements per
// axis, on a lattice of half steps (ids 1 + i + (2nx+1)(j + (2ny+1)k)).
struct HexMesh {
  int n[3];
  double size[3];
  int id(int i, int j, int k) const { return 1 + i + (2 * n[0] + 1) * (j + (2 * n[1] + 1) * k); }
  V3 at(int i, int j, int k) const {
    return {size[0] * i / (2 * n[0]), size[1] * j / (2 * n[1]), size[2] * k / (2 * n[2])};
  }
};

// Abaqus/CalculiX node order of a 20-node brick, as lattice offsets: the
// corners of the bottom then the top face, the bottom's mid-edges, the top's,
// then the vertical ones.
constexpr int kBrick[20][3] = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {0, 0, 2}, {2, 0, 2}, {2, 2, 2},
                               {0, 2, 2}, {1, 0, 0}, {2, 1, 0}, {1, 2, 0}, {0, 1, 0}, {1, 0, 2}, {2, 1, 2},
                               {1, 2, 2}, {0, 1, 2}, {0, 0, 1}, {2, 0, 1}, {2, 2, 1}, {0, 2, 1}};

// The deck: base nodes fixed, a unit force in y shared evenly by the nodes of
// the top face that `loaded` accepts (x of the node), their displacements
// printed.
template <class Loaded>
std::string deck(const HexMesh& m, double E, double nu, std::set<int>& top, const Loaded& loaded) {
  std::map<int, V3> nodes;
  std::ostringstream el;
  int e = 0;
  for (int ek = 0; ek < m.n[2]; ++ek)
    for (int ej = 0; ej < m.n[1]; ++ej)
      for (int ei = 0; ei < m.n[0]; ++ei) {
        el << ++e;
        for (int a = 0; a < 20; ++a) {
          const int i = 2 * ei + kBrick[a][0], j = 2 * ej + kBrick[a][1], k = 2 * ek + kBrick[a][2];
          nodes[m.id(i, j, k)] = m.at(i, j, k);
          el << (a == 15 ? ",\n" : ", ") << m.id(i, j, k);  // at most 16 entries a line
        }
        el << "\n";
      }
  std::ostringstream o, base;
  o.precision(12);
  o << "*NODE\n";
  for (const auto& [id, p] : nodes) {
    o << id << ", " << p(0) << ", " << p(1) << ", " << p(2) << "\n";
    if (p(2) < 1e-9) base << id << ",\n";
    if (p(2) > m.size[2] - 1e-9 && loaded(p(0))) top.insert(id);
  }
  o << "*ELEMENT, TYPE=C3D20R, ELSET=EALL\n" << el.str() << "*NSET, NSET=NBASE\n" << base.str() << "*NSET, NSET=NTOP\n";
  for (int id : top) o << id << ",\n";
  o << "*MATERIAL, NAME=AL\n*ELASTIC\n" << E << ", " << nu << "\n*SOLID SECTION, ELSET=EALL, MATERIAL=AL\n"
    << "*BOUNDARY\nNBASE, 1, 3\n*STEP\n*STATIC\n*CLOAD\n";
  for (int id : top) o << id << ", 2, " << 1.0 / static_cast<double>(top.size()) << "\n";
  o << "*NODE PRINT, NSET=NTOP\nU\n*END STEP\n";
  return o.str();
}

// The mean y-displacement of the printed nodes in ccx's .dat file.
double mean_uy(const std::string& dat_path, const std::set<int>& top) {
  std::ifstream in(dat_path);
  std::string line;
  double sum = 0;
  int n = 0;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    int id = 0;
    double ux = 0, uy = 0, uz = 0;
    if (ls >> id >> ux >> uy >> uz && top.count(id)) {
      sum += uy;
      ++n;
    }
  }
  REQUIRE(n == static_cast<int>(top.size()));
  return sum / n;
}

}  // namespace

TEST_SUITE("stiffness_calculix") {

TEST_CASE("workpiece: the strip's compliance agrees with CalculiX's (C3D20R) within 3 %" * doctest::skip(!have_ccx())) {
  const test::TempDir dir("workpiece-ccx");
  const HexMesh m{{5, 2, 20}, {10, 2, 40}};
  std::set<int> top;
  {
    std::ofstream inp(dir / "strip.inp");
    inp << deck(m, 70000, 0.33, top, [](double) { return true; });
  }
  const int rc = std::system(("cd '" + dir.p.string() + "' && OMP_NUM_THREADS=1 ccx -i strip > ccx.log 2>&1").c_str());
  if (rc != 0) FAIL("ccx failed: " << test::read_file(dir / "ccx.log"));
  const double ccx = mean_uy(dir / "strip.dat", top);

  const WorkpieceModel model(read_part_surface(box_step(dir, "strip", 10, 2, 40)),
                             {parse_fixture("box:-1,-1,-1,11,3,0.001")}, aluminium());
  const double ours = model.compliance_at(V3(5, 1, 40)).matrix_mm_per_N(1, 1);
  MESSAGE("strip: deflex C_yy ", ours, " mm/N (a patch at the middle of the top face), CalculiX ", ccx,
          " mm/N (the force shared by the top face's nodes, their mean displacement), ", 100 * (ours / ccx - 1), " %");
  CHECK(ours == deflex::test::within(ccx, 0.03));
}

TEST_CASE("workpiece: the plate 100 x 2 x 40 mm along its free edge agrees with CalculiX's (C3D20R) within 3 %" *
          doctest::skip(!have_ccx())) {
  // The deflection at three points of the free top edge, from the middle to
  // near a free side, under a unit force in y spread along the whole edge
  // (the top face): by Maxwell-Betti, the mean along the edge of the edge's
  // deflection under a unit load at the point. A load on a small patch would
  // measure each solver's local indentation under it (its own patch shape,
  // ccx's equal shares on a 20-node brick's corner and mid-side nodes) more
  // than the plate. CalculiX: 50 x 2 x 20 bricks, the force shared by the top
  // face's nodes, the mean displacement of those within 2 mm of the point;
  // deflex (2 mm elements): transfer() from 21 points along the edge to the
  // point, by the trapezoid rule.
  const test::TempDir dir("workpiece-ccx-plate");
  const HexMesh m{{50, 2, 20}, {100, 2, 40}};
  std::set<int> top;
  {
    std::ofstream inp(dir / "plate.inp");
    inp << deck(m, 70000, 0.33, top, [](double) { return true; });
  }
  const int rc = std::system(("cd '" + dir.p.string() + "' && OMP_NUM_THREADS=1 ccx -i plate > ccx.log 2>&1").c_str());
  if (rc != 0) FAIL("ccx failed: " << test::read_file(dir / "ccx.log"));
  WorkpieceOptions o;
  o.mesh_mm = 2;
  const WorkpieceModel model(read_part_surface(box_step(dir, "plate", 100, 2, 40)),
                             {parse_fixture("box:-1,-1,-1,101,3,0.001")}, aluminium(), o);
  for (const double x : {50.0, 30.0, 10.0}) {
    std::set<int> near;  // the top face's nodes within 2 mm of the point
    for (int id : top) {
      const int i = (id - 1) % (2 * m.n[0] + 1);
      if (std::fabs(m.size[0] * i / (2 * m.n[0]) - x) <= 2 + 1e-9) near.insert(id);
    }
    const double ccx = mean_uy(dir / "plate.dat", near);
    const int n = 20;
    double ours = 0;
    for (int i = 0; i <= n; ++i) {
      const double w = (i == 0 || i == n) ? 0.5 / n : 1.0 / n;
      ours += w * model.transfer(V3(100.0 * i / n, 1, 40), V3(x, 1, 40))(1, 1);
    }
    MESSAGE("plate edge at x = ", x, " mm under the spread load: deflex ", ours, " mm/N, CalculiX ", ccx, " mm/N, ",
            100 * (ours / ccx - 1), " %");
    CHECK(ours == deflex::test::within(ccx, 0.03));
  }
}

}  // TEST_SUITE
