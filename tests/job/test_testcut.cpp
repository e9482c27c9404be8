// job::testcut and job::probe: the test cut written in every dialect and read
// back, simulated by deflex itself (down-milling flank cuts at the planned
// a_e, a_p), and its probing program read by LinuxCNC's rs274 and checked
// against the stock the test cut leaves. The plans alone are in tests/plan;
// what the commands print in tests/cli/test_testcut.cpp.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <regex>

#include "deflex/job/check.hpp"
#include "deflex/job/stock.hpp"
#include "deflex/job/testcut.hpp"
#include "deflex/profile/profile.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using namespace deflex;

namespace {

const std::string kBox = "box:0,0,-30,200,200,0", kMachine = "samples/machines/mill3.yaml";

job::TestCutSettings settings(const test::TempDir& dir, const std::string& dialect = "") {
  job::TestCutSettings s;
  s.read.machine = kMachine;
  s.read.dialect = dialect;
  s.tool = "T1";
  s.tool_file = "samples/tools.yaml";
  s.material.material = "Al7075-T6";
  s.stock = kBox;
  s.output = dir / "testcut.nc";
  return s;
}

// The Error job::testcut throws (kind, message), and that it wrote nothing.
std::string refused(const job::TestCutSettings& s) {
  test::Streams st;
  try {
    (void)job::testcut(s, st.io);
  } catch (const Error& e) {
    CHECK(e.kind() == ErrorKind::settings);
    CHECK_FALSE(fs::exists(s.output));
    CHECK_FALSE(fs::exists(job::plan_path_for(s.output)));
    return e.what();
  }
  FAIL("not refused");
  return "";
}

// Every CL point of the test cut simulated on the block.
struct Rows : job::Observer {
  std::vector<report::PointRow> rows;
  bool wants_rows() const override { return true; }
  void row(const report::PointRow& r) override { rows.push_back(r); }
};

using P3 = std::array<double, 3>;
double dist(const P3& a, const P3& b) { return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }

// The moves of rs274's canonical output: kind, end point; and the DEFLEX
// PROBE comment before each probing move.
struct Canon {
  struct Move {
    std::string kind;  // STRAIGHT_TRAVERSE, STRAIGHT_FEED, STRAIGHT_PROBE
    P3 end{};
    std::string comment;  // the last DEFLEX PROBE comment before a probe
  };
  std::vector<Move> moves;
};

Canon rs274(const test::TempDir& dir, const std::string& prog) {
  REQUIRE_MESSAGE(fs::exists("/usr/bin/rs274"), "rs274 missing: run scripts/install-deps.sh --test");
  const std::string out = dir / "canon.txt";
  const std::string cmd = "cd " + dir.p.string() + " && /usr/bin/rs274 -g " + prog + " " + out + " </dev/null >/dev/null 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);
  const std::regex move(R"((STRAIGHT_TRAVERSE|STRAIGHT_FEED|STRAIGHT_PROBE)\((-?[\d.]+), (-?[\d.]+), (-?[\d.]+),)");
  const std::regex comment(R"re(COMMENT\("(DEFLEX PROBE .*)"\))re");
  Canon c;
  std::string last;
  std::istringstream in(test::read_file(out));
  for (std::string l; std::getline(in, l);) {
    std::smatch m;
    if (std::regex_search(l, m, comment)) last = m[1];
    if (!std::regex_search(l, m, move)) continue;
    c.moves.push_back({m[1], {std::stod(m[2]), std::stod(m[3]), std::stod(m[4])}, m[1] == "STRAIGHT_PROBE" ? last : ""});
  }
  return c;
}

void check_probing(const std::string& tool, const std::string& box);

// The nearest material cell centre's distance to a ball centre `c` (cells
// as columns up to their height), at most `reach`.
double clearance(const stock::ZMap& z, const P3& c, double reach) {
  const stock::GridSpec& g = z.grid();
  double best = reach;
  for (int j = std::max(0, z.iy(c[1] - reach)); j <= std::min(g.ny - 1, z.iy(c[1] + reach)); ++j)
    for (int i = std::max(0, z.ix(c[0] - reach)); i <= std::min(g.nx - 1, z.ix(c[0] + reach)); ++i) {
      const float h = z.at(i, j);
      if (h == stock::no_material) continue;
      const double dxy = std::hypot(z.cx(i) - c[0], z.cy(j) - c[1]);
      best = std::min(best, c[2] <= h ? dxy : std::hypot(dxy, c[2] - h));
    }
  return best;
}

}  // namespace

TEST_SUITE("job") {
  TEST_CASE("testcut in every dialect: program and plan written, the program read back clean and in travel") {
    for (const std::string& d : profile::dialect_names()) {
      CAPTURE(d);
      test::TempDir dir("testcut");
      test::Streams st;
      const job::TestCutResult r = job::testcut(settings(dir, d), st.io);
      CHECK(r.plan_file == dir / "testcut.yaml");
      CHECK(r.plan.dialect == d);
      job::CheckSettings c;
      c.program = r.program;
      c.read.machine = kMachine;
      c.read.dialect = d;
      test::Streams cs;
      const job::CheckResult k = job::check(c, cs.io);
      CAPTURE(cs.err.str());
      CHECK(k.errors == 0);
      CHECK(k.warnings == 0);
      const plan::TestCutPlan p = plan::read_plan_yaml(test::read_file(r.plan_file), r.plan_file);
      CHECK(p.features.size() == 12);
      CHECK(p.machine == "mill3");
      const std::string text = test::read_file(r.program);
      CHECK(text.find("MATERIAL Al7075-T6") != std::string::npos);
      CHECK(text.find("T1 FLAT D10.000 4 FLUTES") != std::string::npos);
    }
  }

  TEST_CASE("testcut simulated: each feature's probe region is a down-milling flank cut at the planned a_e, a_p") {
    test::TempDir dir("testcut");
    test::Streams st;
    const job::TestCutResult r = job::testcut(settings(dir), st.io);
    job::Settings s;
    s.program = r.program;
    s.read.machine = kMachine;
    s.tool_file = "samples/tools.yaml";
    s.material.material = "Al7075-T6";
    s.stock = kBox;
    Rows rows;
    test::Streams ss;
    job::Run run = job::open(s, job::Purpose::simulate, ss.io);
    (void)job::simulate(run, ss.io, &rows);
    for (const plan::WallFeature& f : r.plan.features) {
      CAPTURE(f.id);
      int n = 0;
      for (const report::PointRow& p : rows.rows) {
        const double u = p.tip_mm[f.feed_axis];
        if (p.line < static_cast<std::uint32_t>(f.first_line) || p.line > static_cast<std::uint32_t>(f.last_line) ||
            u < f.u0_mm || u > f.u1_mm)
          continue;
        ++n;
        CHECK(p.ae_mm == deflex::test::within(f.ae_mm, 0.06 / f.ae_mm));
        CHECK(p.ap_mm == deflex::test::within(f.ap_mm, 0.06 / f.ap_mm));
        // deflex's rule (compensate/normals.cpp): a flank cut's normal is +Y'
        // of the feed frame (left of the feed) exactly when it is down-milling.
        CHECK_FALSE(std::isnan(p.flank_min_mm));
        CHECK(p.normal.x() == doctest::Approx(f.normal[0]));
        CHECK(p.normal.y() == doctest::Approx(f.normal[1]));
        // Down-milling pushes the tool off the wall it cuts (an undercut);
        // up-milling would pull it in (Altintas ch. 2).
        CHECK(p.delta_mm.dot(p.normal) > 0);
      }
      CHECK(n >= 10);
    }
  }

  TEST_CASE("testcut refuses before writing: a block too small (walls, slopes), feed and fz together, no box") {
    test::TempDir dir("testcut");
    job::TestCutSettings s = settings(dir);
    s.stock = "box:0,0,-30,100,100,0";
    CHECK(refused(s).find("the smallest block that fits is 182 x 182 x 20 mm") != std::string::npos);
    s = settings(dir);
    s.tool = "T3";
    s.stock = "box:0,0,-30,60,60,0";
    CHECK(refused(s).find("too small for the test cut of T3: the smallest block that fits is 66 x 12 x 5 mm") != std::string::npos);
    s = settings(dir);
    s.feed_mm_per_min = 1000;
    s.fz_mm = 0.05;
    CHECK(refused(s) == "give feed_mm_per_min or fz_mm, not both");
    s = settings(dir);
    s.stock = "samples/parts/none.stl";
    CHECK(refused(s).find("must be the test block, box:") != std::string::npos);
    s = settings(dir);
    s.tool = "1";
    CHECK(refused(s).find("tool must be a tool number T<n>") != std::string::npos);
  }

  TEST_CASE("probe, LinuxCNC, read by rs274: probing moves on the normal lines, no rapid below the top, the ball never in the cut stock") {
    for (const char* tool : {"T1", "T3"}) {  // walls, then a ball's slopes
      CAPTURE(std::string(tool));
      check_probing(tool, tool == std::string("T1") ? kBox : "box:0,0,-30,100,40,0");
    }
  }
}

namespace {

// The test cut of `tool` on `box`, its probing program read by rs274 and
// checked against the stock the cut leaves.
void check_probing(const std::string& tool, const std::string& box) {
  {
    test::TempDir dir("probe");
    test::Streams st;
    job::TestCutSettings ts = settings(dir);
    ts.tool = tool;
    ts.stock = box;
    const job::TestCutResult cut = job::testcut(ts, st.io);
    job::ProbeSettings ps;
    ps.plan = cut.plan_file;
    ps.read.dialect = "linuxcnc";
    ps.output = dir / "probe.ngc";
    const job::ProbeResult pr = job::probe(ps, st.out, st.io);
    const std::string text = test::read_file(ps.output);
    CHECK(text.find("(PROBEOPEN probe_results.txt)") < text.find("G38.2"));
    CHECK(text.find("(PROBECLOSE)") > text.rfind("G38.2"));
    const Canon c = rs274(dir, "probe.ngc");
    job::StockSettings ss;
    ss.read.machine = kMachine;
    ss.stock = box;
    ss.tool_file = "samples/tools.yaml";
    ss.stock_from = {{cut.program, ""}};
    ss.cell_mm = 0.1;
    const stock::ZMap z = job::rest_stock(ss, st.io);
    const double r = 1.0, top = 0, tol = 0.02;
    const std::regex comment(R"(DEFLEX PROBE (\d+) (\w+) AT (\S+) (\S+) (\S+) N (\S+) (\S+) (\S+) BALL (\S+))");
    std::size_t probes = 0;
    P3 at{}, n{};  // the last probed point and its normal
    for (std::size_t k = 1; k < c.moves.size(); ++k) {
      const Canon::Move &a = c.moves[k - 1], &b = c.moves[k];
      if (b.kind == "STRAIGHT_TRAVERSE") CHECK_MESSAGE(b.end[2] >= top + 5 - 1e-9, "a rapid below the clearance");
      if (a.kind == "STRAIGHT_TRAVERSE") CHECK(a.end[2] >= top + 5 - 1e-9);
      if (b.kind == "STRAIGHT_PROBE") {
        ++probes;
        std::smatch m;
        REQUIRE(std::regex_match(b.comment, m, comment));
        CHECK(std::stoul(m[1]) == probes);
        at = {std::stod(m[3]), std::stod(m[4]), std::stod(m[5])};
        n = {std::stod(m[6]), std::stod(m[7]), std::stod(m[8])};
        CHECK(std::stod(m[9]) == r);
        const P3 start{at[0] + n[0] * (r + 2), at[1] + n[1] * (r + 2), at[2] + n[2] * (r + 2)};
        const P3 end{at[0] + n[0] * (r - 1), at[1] + n[1] * (r - 1), at[2] + n[2] * (r - 1)};
        // To the program's 0.001 mm and the comment's 4-decimal normal (a
        // slope's tilted normal rounds in two coordinates).
        CHECK(dist(a.end, start) < 1e-3);
        CHECK(dist(b.end, end) < 1e-3);
      }
      // The ball centre along the move, every 0.05 mm: no material within r,
      // but where a probing move (or the backing off after it) passes the
      // touching distance on purpose.
      const bool probing = b.kind == "STRAIGHT_PROBE" || a.kind == "STRAIGHT_PROBE";
      const int steps = std::max(1, static_cast<int>(std::ceil(dist(a.end, b.end) / 0.05)));
      for (int i = 0; i <= steps; ++i) {
        const double t = static_cast<double>(i) / steps;
        const P3 p{a.end[0] + t * (b.end[0] - a.end[0]), a.end[1] + t * (b.end[1] - a.end[1]), a.end[2] + t * (b.end[2] - a.end[2])};
        if (probing && (p[0] - at[0]) * n[0] + (p[1] - at[1]) * n[1] + (p[2] - at[2]) * n[2] < r - 1e-6) continue;
        const double d = clearance(z, p, r + 1);
        if (d < r - tol) FAIL_CHECK("ball in the material at " << p[0] << " " << p[1] << " " << p[2] << " (" << d << " mm)");
      }
    }
    CHECK(probes == pr.points);
    CHECK(probes > 30);
    // A slope's cut surface is its plane, to the cusp and a cell.
    for (const plan::WallFeature& f : cut.plan.features) {
      if (f.kind != "slope") continue;
      CAPTURE(f.id);
      for (double zs = f.z0_mm + 0.3; zs < f.z1_mm - 0.3; zs += 0.2) {
        // The plane's height at the centre of the cell under it; the cusp
        // between passes 0.1 R apart is (0.3 mm)^2 / 8R = 4 um.
        const int j = z.iy(f.point_mm[1] - f.normal[2] * (zs - f.point_mm[2]) / f.normal[1]);
        const double plane = f.point_mm[2] - f.normal[1] * (z.cy(j) - f.point_mm[1]) / f.normal[2];
        CHECK(std::abs(z.at(z.ix((f.u0_mm + f.u1_mm) / 2), j) - plane) < 0.01);
      }
    }
  }
}

}  // namespace
