// `deflex stability` through the command line and job::stability(): the
// limit it prints is the lobes' envelope, a measured FRF that is the model's
// own gives the model's limit, --report writes its three files, and bad
// settings and a malformed FRF are errors before anything is computed.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "../support.hpp"
#include "deflex/job/stability.hpp"
#include "deflex/stability/frf.hpp"
#include "deflex/stability/model.hpp"
#include "deflex/stiffness/machine.hpp"
#include "deflex/stiffness/tool.hpp"

using namespace deflex;

namespace {

job::StabilitySettings t1_settings() {
  job::StabilitySettings s;
  s.tool = "T1";
  s.tool_file = "samples/tools.yaml";
  s.material.material = "Al7075-T6";
  s.material.material_file = "samples/materials.yaml";
  s.machine = "samples/machines/mill3.yaml";
  s.ae_mm = 3;
  return s;
}

}  // namespace

TEST_SUITE("stability") {

TEST_CASE("stability command: the limit is the envelope over the absolute minimum, the pockets its peaks") {
  const job::StabilityResult r = job::stability(t1_settings());
  REQUIRE(r.modes.size() == stability::kModelModes);
  CHECK(r.rpm_max == 12000);  // mill3's spindle
  CHECK(r.rpm_min == doctest::Approx(12000 / 50.0));
  CHECK(r.limit.size() == 1001);
  for (const auto& [rpm, ap] : r.limit) CHECK(ap >= r.lobes.ap_min_mm * (1 - 1e-9));
  REQUIRE(!r.pockets.empty());
  CHECK(std::is_sorted(r.pockets.begin(), r.pockets.end(), [](auto& a, auto& b) { return a.second > b.second; }));
  // A flat end: the engagement of --ap on its own shape is the textbook cut.
  job::StabilitySettings s = t1_settings();
  s.ap_mm = 5;
  const job::StabilityResult e = job::stability(s);
  CHECK((e.alpha - r.alpha).norm() <= 1e-9 * r.alpha.norm());
}

TEST_CASE("stability command: a measured FRF that is the model's own gives the model's limit") {
  test::TempDir dir("stab");
  const auto tools = stiffness::load_tool_library("samples/tools.yaml");
  const auto machine = stiffness::load_machine_stiffness("samples/machines/mill3.yaml");
  const stability::TipModel tip = stability::tip_model(tools.tools.at("T1"), machine, false);
  test::write_file(dir / "tap.csv", stability::frf_csv(tip.frf));
  job::StabilitySettings m = t1_settings(), f = t1_settings();
  m.rpm_min = f.rpm_min = 4000, m.rpm_max = f.rpm_max = 12000;
  f.machine.clear();
  f.frf = dir / "tap.csv";
  const job::StabilityResult a = job::stability(m), b = job::stability(f);
  CHECK(b.modes.empty());
  CHECK(b.lobes.ap_min_mm == deflex::test::within(a.lobes.ap_min_mm, 1e-6));
  for (std::size_t i = 0; i < a.limit.size(); i += 50) CHECK(b.limit[i].second == deflex::test::within(a.limit[i].second, 1e-6));
}

TEST_CASE("stability command: text, csv, json and the report folder") {
  test::TempDir dir("stab");
  const std::vector<std::string> base = {"stability", "--tool", "T1", "--material", "Al7075-T6", "--machine", "mill3",
                                         "--ae", "3", "--points", "100"};
  auto with = [&](std::vector<std::string> more) {
    std::vector<std::string> a = base;
    a.insert(a.end(), more.begin(), more.end());
    return test::run_cli(a);
  };
  const test::CliResult text = with({});
  REQUIRE(text.rc == 0);
  CHECK(text.out.find("absolute limit (stable at every speed)") != std::string::npos);
  const test::CliResult csv = with({"--format", "csv"});
  REQUIRE(csv.rc == 0);
  CHECK(csv.out.rfind("rpm,ap_limit_mm\n", 0) == 0);
  CHECK(std::count(csv.out.begin(), csv.out.end(), '\n') == 102);
  const test::CliResult js = with({"--format", "json", "--report", dir / "lobes"});
  REQUIRE(js.rc == 0);
  const auto j = nlohmann::json::parse(js.out);
  CHECK(j.at("modes").size() == 4);
  CHECK(j.at("limit").size() == 101);
  for (const char* f : {"stability.html", "stability.csv", "stability.json"}) CHECK(std::filesystem::exists(dir / "lobes" + "/" + f));
  const std::string html = test::read_file(dir / "lobes" + "/stability.html");
  CHECK(html.find("new Dygraph(") != std::string::npos);
  for (const char* mark : {"@@TITLE@@", "@@DATA@@", "/*@@DYGRAPHS@@*/"}) CHECK(html.find(mark) == std::string::npos);
}

TEST_CASE("stability command: settings and a malformed FRF are errors before anything is computed") {
  test::TempDir dir("stab");
  CHECK(test::run_cli({"stability", "--tool", "T1", "--ae", "3", "--rpm", "9000"}).rc == 2);
  CHECK(test::run_cli({"stability", "--tool", "T1", "--ae", "3", "--rpm", "9000:2000"}).rc == 2);
  CHECK(test::run_cli({"stability", "--tool", "T1", "--ae", "0"}).rc == 2);
  CHECK(test::run_cli({"stability", "--tool", "T1", "--ae", "3", "--up", "--down"}).rc == 2);
  CHECK(test::run_cli({"stability", "--tool", "T1", "--ae", "3", "--format", "xml"}).rc == 2);
  // A ball whose radius at --ap does not reach the wall a_e sets.
  CHECK(test::run_cli({"stability", "--tool", "T3", "--ae", "0.5", "--ap", "1.2"}).rc == 2);
  // With a measured FRF and no machine the speed range must be given.
  test::write_file(dir / "tap.csv", "frequency_Hz,re_xx_mm_per_N,im_xx_mm_per_N,re_yy_mm_per_N,im_yy_mm_per_N\n"
                                    "100,1e-5,-1e-6,1e-5,-1e-6\n200,1e-5,x,1e-5,-1e-6\n300,1e-5,-1e-6,1e-5,-1e-6\n");
  const std::string tap = dir / "tap.csv";
  CHECK(test::run_cli({"stability", "--tool", "T1", "--ae", "3", "--frf", tap}).rc == 2);
  const test::CliResult bad = test::run_cli({"stability", "--tool", "T1", "--ae", "3", "--frf", tap, "--rpm", "2000:9000"});
  CHECK(bad.rc == 1);
  CHECK(bad.err.find(tap + ":3:") != std::string::npos);
}

}  // TEST_SUITE
