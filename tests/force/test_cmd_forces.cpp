// `deflex forces` and `deflex calibrate`, run in-process.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <sstream>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "../support.hpp"
#include "deflex/cli/command.hpp"
#include "deflex/cli/exit.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/force/material.hpp"

using deflex::Error;
using deflex::cli::Exit;

namespace {

const std::string src = DEFLEX_SOURCE_DIR;
const std::string tools = src + "/tests/force/data/tools.yaml";

struct Run {
  int code = -1;
  std::string out, err;
};

Run forces(std::vector<std::string> args, bool calibrate = false) {
  std::istringstream in;
  std::ostringstream out, err;
  deflex::cli::Io io{{in, out, err}};
  Run r;
  r.code = calibrate ? deflex::cli::cmd_calibrate(args, io) : deflex::cli::cmd_forces(args, io);
  r.out = out.str();
  r.err = err.str();
  return r;
}

Exit usage_error(std::vector<std::string> args) {
  try {
    forces(std::move(args));
  } catch (const Error& e) {
    return deflex::cli::exit_code(e.kind());
  }
  return Exit::ok;
}

std::vector<double> numbers_after(const std::string& json, const std::string& key) {
  const auto v = nlohmann::json::parse(json).at(key);
  REQUIRE(v.size() == 3);
  return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
}

}  // namespace

TEST_SUITE("force") {

TEST_CASE("deflex forces --format csv: one row per step; the mean is Altintas' closed form") {
  // Half-immersion down-milling, F12 (D 12, 4 flutes, helix 45): the means
  // between phi 90 and 180 deg (Altintas 2012 ch. 2, Fz = -Fa in deflex).
  const double kt = 700, kr = 210, ka = 90, kte = 20, kre = 25, kae = 1.5, fz = 0.08, ap = 5;
  const Run r = forces({"--tool-file", tools, "--tool", "F12", "--kt", "700", "--kr", "210", "--ka", "90",
                        "--kte", "20", "--kre", "25", "--kae", "1.5", "--ae", "6", "--ap", "5", "--fz",
                        "0.08", "--down", "--steps", "180"});
  REQUIRE(r.code == 0);
  std::istringstream in(r.out);
  std::string line;
  std::getline(in, line);
  CHECK(line == "angle_deg,Fx_N,Fy_N,Fz_N");
  double sum[3] = {0, 0, 0};
  int rows = 0;
  while (std::getline(in, line)) {
    double ang, x, y, z;
    REQUIRE(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf", &ang, &x, &y, &z) == 4);
    CHECK(ang == doctest::Approx(2.0 * rows));
    sum[0] += x, sum[1] += y, sum[2] += z;
    ++rows;
  }
  REQUIRE(rows == 180);
  const double pi = std::numbers::pi, N = 4, s = pi / 2, e = pi;
  auto fx = [&](double p) {
    return N * ap * fz / (8 * pi) * (kt * std::cos(2 * p) - kr * (2 * p - std::sin(2 * p))) +
           N * ap / (2 * pi) * (-kte * std::sin(p) + kre * std::cos(p));
  };
  auto fy = [&](double p) {
    return N * ap * fz / (8 * pi) * (kt * (2 * p - std::sin(2 * p)) + kr * std::cos(2 * p)) -
           N * ap / (2 * pi) * (kte * std::cos(p) + kre * std::sin(p));
  };
  auto fzf = [&](double p) { return N * ap / (2 * pi) * (ka * fz * std::cos(p) - kae * p); };
  CHECK(sum[0] / rows == deflex::test::within(fx(e) - fx(s), 0.005));
  CHECK(sum[1] / rows == deflex::test::within(fy(e) - fy(s), 0.005));
  CHECK(sum[2] / rows == deflex::test::within(fzf(e) - fzf(s), 0.005));
  CHECK(sum[1] > 0);  // down-milling on a -Y wall pushes the tool to +Y
}

TEST_CASE("deflex forces --format json: Morelli's three cases with Al 6082-T4") {
  const std::pair<const char*, const char*> cases[] = {{"12", "IIM"}, {"15", "IIML"}, {"18", "IImL"}};
  for (const auto& [ap, code] : cases) {
    const Run r = forces({"--tool-file", tools, "--tool", "F12", "--material", "Al6082-T4",
                          "--material-file", src + "/samples/materials.yaml", "--ae", "2.5", "--ap", ap,
                          "--fz", "0.1", "--down", "--format", "json"});
    REQUIRE(r.code == 0);
    CHECK(nlohmann::json::parse(r.out)["shape_code"] == code);
    const auto mean = numbers_after(r.out, "mean_N"), peak = numbers_after(r.out, "peak_abs_N");
    for (int a = 0; a < 2; ++a) CHECK(peak[a] >= std::abs(mean[a]));
    CHECK(mean[2] == 0.0);  // Morelli gives no K_ac and no edge terms
  }
}

TEST_CASE("deflex forces --format json --rpm: the spindle's torque and power by hand") {
  // Altintas 2012 ch. 2: the mean tangential force of N teeth between entry st
  // and exit ex is N a / (2 pi) K_tc f (cos st - cos ex) (no edge terms given),
  // acting at R; P = M 2 pi n / 60.
  const Run r = forces({"--tool-file", tools, "--tool", "F12", "--kt", "700", "--kr", "200", "--ka", "0", "--ae",
                        "2.5", "--ap", "12", "--fz", "0.1", "--down", "--rpm", "6000", "--format", "json"});
  REQUIRE(r.code == 0);
  const auto [st, ex] = deflex::test::textbook_immersion(12, 2.5, false);
  const double Ft_N = 4 * 12 / (2 * std::numbers::pi) * 700 * 0.1 * (std::cos(st) - std::cos(ex));
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["mean_torque_Nm"].get<double>() == deflex::test::within(Ft_N * 6 / 1000, 1e-3));
  CHECK(j["power_kW"].get<double>() == deflex::test::within(Ft_N * 6 / 1000 * 2 * std::numbers::pi * 6000 / 60 / 1000, 1e-3));
  CHECK(usage_error({"--tool-file", tools, "--tool", "F12", "--kt", "700", "--kr", "200", "--ka", "0", "--ae", "2.5",
                     "--ap", "12", "--fz", "0.1", "--down", "--rpm", "-1", "--format", "json"}) == Exit::usage);
}

TEST_CASE("deflex forces: no shape code for up-milling or a ball end") {
  const Run up = forces({"--tool-file", tools, "--tool", "F12", "--kt", "700", "--kr", "200", "--ka", "0",
                         "--ae", "2.5", "--ap", "12", "--fz", "0.1", "--up", "--format", "json"});
  REQUIRE(up.code == 0);
  CHECK(up.out.find("shape_code") == std::string::npos);
  const Run ball = forces({"--tool-file", tools, "--tool", "B10", "--material", "C35", "--ae", "10", "--ap",
                           "1", "--fz", "0.1", "--down", "--format", "json"});
  REQUIRE(ball.code == 0);
  CHECK(ball.out.find("shape_code") == std::string::npos);
  // Light up-milling draws the tool into the +Y wall (overcut), down-milling
  // pushes it off the -Y wall (undercut): both give a mean Fy > 0 here.
  CHECK(numbers_after(up.out, "mean_N")[1] > 0);
  CHECK(numbers_after(ball.out, "mean_N")[1] > 0);
}

TEST_CASE("deflex forces: bad usage is Exit::usage, a bad library Exit::config") {
  const std::vector<std::string> base = {"--tool-file", tools, "--tool", "F12", "--ae", "2", "--ap", "5",
                                         "--fz", "0.1"};
  auto with = [&](std::initializer_list<std::string> more) {
    auto v = base;
    v.insert(v.end(), more);
    return v;
  };
  CHECK(usage_error(with({"--kt", "1", "--kr", "1", "--ka", "1"})) == Exit::usage);  // no --up/--down
  CHECK(usage_error(with({"--kt", "1", "--kr", "1", "--ka", "1", "--up", "--down"})) == Exit::usage);
  CHECK(usage_error(with({"--material", "C35", "--kt", "1", "--kr", "1", "--ka", "1", "--up"})) == Exit::usage);
  CHECK(usage_error(with({"--kt", "1", "--up"})) == Exit::usage);
  CHECK(usage_error(with({"--kt", "1", "--kr", "1", "--ka", "1", "--up", "--format", "xml"})) == Exit::usage);
  CHECK(usage_error(with({"--kt", "1", "--kr", "1", "--ka", "1", "--up", "--steps", "2"})) == Exit::usage);
  CHECK(usage_error(with({"--kt", "x", "--kr", "1", "--ka", "1", "--up"})) == Exit::usage);
  CHECK(usage_error(with({"--material", "nope", "--up"})) == Exit::usage);
  CHECK(usage_error({"--tool-file", tools, "--tool", "F12", "--ap", "5", "--fz", "0.1", "--up", "--kt", "1",
                     "--kr", "1", "--ka", "1"}) == Exit::usage);  // no --ae
  CHECK(usage_error({"--tool-file", tools, "--tool", "F12", "--ae", "2", "--ap", "50", "--fz", "0.1", "--up",
                     "--kt", "1", "--kr", "1", "--ka", "1"}) == Exit::usage);  // deeper than the flutes
  CHECK(usage_error({"--tool-file", src + "/tests/force/data/bad_tools.yaml", "--tool", "BAD", "--ae", "2", "--ap", "5", "--fz", "0.1", "--up",
                     "--kt", "1", "--kr", "1", "--ka", "1"}) == Exit::config);
  CHECK(usage_error({"--tool-file", "/nonexistent.yaml", "--tool", "X", "--ae", "2", "--ap", "5", "--fz",
                     "0.1", "--up", "--kt", "1", "--kr", "1", "--ka", "1"}) == Exit::io);
}

TEST_CASE("deflex forces --help teaches the conventions") {
  const Run r = forces({"--help"});
  CHECK(r.code == 0);
  for (const char* s : {"clockwise from +Y", "+Y side", "-Y side", "N/mm^2", "on the tool", "angle_deg,Fx_N,Fy_N,Fz_N"})
    CHECK(r.out.find(s) != std::string::npos);
}

TEST_CASE("deflex calibrate: recovers the sample's coefficients and writes a loadable entry") {
  const std::string out_yaml =
      (std::filesystem::temp_directory_path() / ("deflex_cal_" + std::to_string(::getpid()) + ".yaml")).string();
  const Run r = forces({src + "/samples/calibration/slot_tests_al7075.csv", "--name", "fitted", "-o", out_yaml},
                       true);
  REQUIRE(r.code == 0);
  CHECK(r.out.find("rms residual") != std::string::npos);
  CHECK(r.out.find("written to") != std::string::npos);
  const auto lib = deflex::force::load_material_library(out_yaml);
  const auto& m = deflex::force::find_material(lib, "fitted");
  CHECK(m.k.Ktc_N_per_mm2 == deflex::test::within(850, 0.03));
  CHECK(m.k.Kte_N_per_mm == deflex::test::within(24, 0.03));
  CHECK(m.source.find("slot_tests_al7075.csv") != std::string::npos);
  std::filesystem::remove(out_yaml);

  const Run plain = forces({src + "/samples/calibration/slot_tests_al7075.csv"}, true);
  CHECK(plain.out.find("materials:\n  \"Al7075-T6 (synthetic)\":") != std::string::npos);
  CHECK_THROWS_AS(forces({}, true), Error);
}

}  // TEST_SUITE
