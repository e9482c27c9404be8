// Earlier operations with tool libraries of their own, through the job API
// (Settings::stock_from): a roughing whose T21 (a flat D20) is only in its own
// library faces the box at Z-2 before the ball finish at Z-3, so the finish
// cuts a_p 1 mm, not 3 (tests/engage/test_stock_from.cpp); a tool that
// library lacks is a config error at the roughing's line naming the library.
// The same in a job file's stock_from entries; the command line's form of
// it (--stock-from-tools) is in tests/cli/test_earlier.cpp.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include "support.hpp"

using namespace deflex;

namespace {

// The facing pass of tests/engage/data/face_rough.nc with tool `t`, and the
// flat D20 of samples/tools.yaml (T4) as T21 alone in a library.
struct Roughing : test::TempDir {
  Roughing() : TempDir("job-earlier") {
    for (const char* t : {"T21", "T22"}) {
      std::string s = test::read_file("tests/engage/data/face_rough.nc");
      s.replace(s.find("T4 M06"), 6, std::string(t) + " M06");
      test::write_file(*this / (std::string("rough") + (t + 1) + ".nc"), s);
    }
    const std::string all = test::read_file("samples/tools.yaml");
    const std::size_t a = all.find("\n  T4:"), b = all.find("\n  T5:");
    test::write_file(*this / "rough_tools.yaml", "tools:\n  T21:" + all.substr(a + 6, b - a - 6) + "\n");
  }
};

// The a_p of the finish's points inside the box along X, mm, to 1 um.
struct Depths : job::Observer {
  std::set<long> ap_um;
  bool wants_rows() const override { return true; }
  void row(const report::PointRow& r) override {
    if (r.tip_mm.x() > 10 && r.tip_mm.x() < 30) ap_um.insert(std::lround(1000 * r.ap_mm));
  }
};

job::Settings finish_on_box() {
  job::Settings s;
  s.program = "tests/engage/data/ball_finish.nc";
  s.material.material = "Al7075-T6";
  s.stock = "box:0,0,-10,40,30,0";
  return s;
}

// The finish simulated with `s`: its run and its depths.
struct Finish {
  job::Run run;
  std::set<long> ap_um;
};
Finish simulate_finish(const job::Settings& s) {
  test::Streams st;
  Depths depths;
  Finish f{job::open(s, job::Purpose::simulate, st.io), {}};
  (void)job::simulate(f.run, st.io, &depths);
  f.ap_um = depths.ap_um;
  return f;
}

// The messages of job::open() on `s`, which must fail with a config error.
std::string config_error(const job::Settings& s) {
  test::Streams st;
  try {
    (void)job::open(s, job::Purpose::simulate, st.io);
    FAIL("a tool missing from the library was accepted");
  } catch (const Error& x) {
    CHECK(x.kind() == ErrorKind::config);
  }
  return st.err.str();
}

}  // namespace

TEST_SUITE("job") {
  TEST_CASE("stock_from: the earlier program's tools come from its own library") {
    const Roughing d;
    job::Settings s = finish_on_box();
    s.stock_from = {{d / "rough21.nc", d / "rough_tools.yaml"}};
    const Finish f = simulate_finish(s);
    CHECK(f.ap_um == std::set<long>{1000});
    bool named = false;
    for (const auto& [key, value] : job::provenance(f.run, ""))
      named |= key == "stock from" && value == d / "rough21.nc" + " (tools: " + d / "rough_tools.yaml" + ")";
    CHECK(named);
    // Without its library T21 is looked up in the run's, which lacks it; a
    // tool its own library lacks names that library. Both before any stock.
    for (const auto& [program, library, named_lib] :
         {std::tuple{d / "rough21.nc", std::string(), std::string("samples/tools.yaml")},
          std::tuple{d / "rough22.nc", d / "rough_tools.yaml", d / "rough_tools.yaml"}}) {
      s.stock_from = {{program, library}};
      const std::string prog = program;  // CAPTURE takes it by reference in a lambda: no structured binding (clang 14)
      CAPTURE(prog);
      const std::string e = config_error(s);
      const std::string tool = prog.ends_with("21.nc") ? "T21" : "T22";
      CHECK(e.find(prog + ":7:1: error: tool " + tool + " is not in the tool library " + named_lib) !=
            std::string::npos);
    }
  }

  TEST_CASE("job file stock_from: {program, tool_file} entries beside plain paths") {
    namespace fs = std::filesystem;
    const Roughing d;
    const std::string head = "program: " + fs::absolute("tests/engage/data/ball_finish.nc").string() +
                             "\nstock: box:0,0,-10,40,30,0\nmaterial: Al7075-T6\nstock_from:\n";
    auto settings_of = [&](const std::string& name, const std::string& entries) {
      test::write_file(d / name, head + entries);
      job::Settings s;
      std::vector<std::string> programs;
      job::apply_job_file(d / name, s, programs);
      REQUIRE(programs.size() == 1);  // the job's program goes there, as beside a command line's
      s.program = programs[0];
      return s;
    };
    const job::Settings s = settings_of("job.yaml", "  - {program: rough21.nc, tool_file: rough_tools.yaml}\n  - " +
                                                        fs::absolute("tests/engage/data/face_rough.nc").string() + "\n");
    REQUIRE(s.stock_from.size() == 2);
    CHECK(simulate_finish(s).ap_um == std::set<long>{1000});
    // A tool the entry's library lacks: the error names that library and the line.
    const job::Settings missing =
        settings_of("missing.yaml", "  - program: rough22.nc\n    tool_file: rough_tools.yaml\n");
    const std::string e = config_error(missing);
    CHECK(e.find(d / "rough22.nc" + ":7:1: error: tool T22 is not in the tool library " + d / "rough_tools.yaml") !=
          std::string::npos);
    // An entry's keys are checked like every key of the job.
    test::write_file(d / "typo.yaml", "stock_from:\n  - {program: rough21.nc, tools: rough_tools.yaml}\n");
    job::Settings t;
    std::vector<std::string> programs;
    try {
      job::apply_job_file(d / "typo.yaml", t, programs);
      FAIL("an unknown key was accepted");
    } catch (const Error& x) {
      CHECK(x.kind() == ErrorKind::config);
      CHECK(std::string(x.what()).find(d / "typo.yaml" + ":2:27: error: unknown key 'tools' in stock_from entry") !=
            std::string::npos);
    }
  }
}
