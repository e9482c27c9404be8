#include <doctest/doctest.h>

#include <sstream>

#include <yaml-cpp/yaml.h>

#include <nlohmann/json.hpp>

#include "../support.hpp"
#include "deflex/cli/command.hpp"
#include "deflex/cli/exit.hpp"
#include "deflex/diag/diagnostics.hpp"
#include "deflex/report/compliance.hpp"
#include "deflex/stiffness/beam.hpp"
#include "helpers.hpp"

using namespace deflex;
using namespace deflex::stiffness;
using namespace deflex::stiffness::testing;

namespace {
struct Run {
  int code = 0;
  std::string out, err;
};
Run run(const std::vector<std::string>& args) {
  std::istringstream in;
  std::ostringstream out, err;
  cli::Io io{{in, out, err}};
  Run r;
  r.code = cli::cmd_stiffness(args, io);
  r.out = out.str();
  r.err = err.str();
  return r;
}
cli::Exit usage_code(const std::vector<std::string>& args) {
  try {
    run(args);
  } catch (const Error& e) {
    return cli::exit_code(e.kind());
  }
  return cli::Exit::ok;
}
}  // namespace

TEST_SUITE("stiffness") {
  TEST_CASE("cmd: JSON output carries the beam table at the requested heights") {
    const std::string lib = sample_path("samples/tools.yaml");
    const Run r = run({"--tool-file", lib, "--tool", "T2", "--machine", "mill3", "--at", "0", "2.5",
                       "--at", "10", "--format", "json"});
    CHECK(r.code == 0);
    const YAML::Node j = YAML::Load(r.out);
    REQUIRE(j["compliance"].size() == 3);
    const ToolLibrary tools = load_tool_library(lib);  // find_tool returns into it: keep it alive
    const Tool& t = find_tool(tools, "T2");
    const ComplianceTable c =
        beam_compliance(t, load_machine_stiffness(sample_path("samples/machines/mill3.yaml")), false);
    const double hs[3] = {0, 2.5, 10};
    for (int k = 0; k < 3; ++k) {
      const YAML::Node row = j["compliance"][k];
      CHECK(row["height_mm"].as<double>() == hs[k]);
      for (int i = 0; i < 3; ++i)
        for (int m = 0; m < 3; ++m)
          CHECK(row["matrix_mm_per_N"][i][m].as<double>() ==
                deflex::test::within(c.at(hs[k])(i, m), 1e-6));
    }
  }

  TEST_CASE("cmd: --tool-only drops the machine; text output names units") {
    const std::string lib = sample_path("samples/tools.yaml");
    const Run with = run({"--tool-file", lib, "--tool", "T5", "--machine", "mill3", "--at", "0", "--format", "json"});
    const Run without = run({"--tool-file", lib, "--tool", "T5", "--machine", "mill3", "--tool-only",
                             "--at", "0", "--format", "json"});
    const double c_with = YAML::Load(with.out)["compliance"][0]["matrix_mm_per_N"][0][0].as<double>();
    const double c_without = YAML::Load(without.out)["compliance"][0]["matrix_mm_per_N"][0][0].as<double>();
    CHECK(c_with > c_without);
    const Run text = run({"--tool-file", lib, "--tool", "T5"});
    CHECK(text.out.find("mm/N") != std::string::npos);
    CHECK(text.out.find("h = 0.000 mm") != std::string::npos);
    CHECK(text.out.find("clamped rigidly") != std::string::npos);
  }

  TEST_CASE("cmd: bad usage is Exit::usage, a bad library Exit::io") {
    const std::string lib = sample_path("samples/tools.yaml");
    CHECK(usage_code({"--tool", "T1"}) == cli::Exit::usage);
    CHECK(usage_code({"--tool-file", lib, "--tool", "T1", "--method", "fem"}) == cli::Exit::usage);
    CHECK(usage_code({"--tool-file", lib, "--tool", "T1", "--at", "99"}) == cli::Exit::usage);
    CHECK(usage_code({"--tool-file", lib, "--tool", "T1", "--bogus"}) == cli::Exit::usage);
    CHECK(usage_code({"--tool-file", lib, "--tool", "T9"}) == cli::Exit::usage);
    CHECK(usage_code({"--tool-file", "/nonexistent/tools.yaml", "--tool", "T1"}) == cli::Exit::io);
    CHECK(run({"--help"}).out.find("usage: deflex stiffness") == 0);
  }

  TEST_CASE("report: JSON has exactly the documented shape") {
    Compliance c;
    c << 1e-4, 2e-6, 0, 2e-6, 1e-4, 0, 0, 0, 3e-6;
    const std::string j = deflex::report::compliance_json({{1.5, c}});
    CHECK(j == "{\"compliance\":[{\"height_mm\":1.5,\"matrix_mm_per_N\":[[0.0001,2e-06,0.0],"
               "[2e-06,0.0001,0.0],[0.0,0.0,3e-06]]}]}\n");
    const auto parsed = nlohmann::json::parse(j);
    CHECK(parsed["compliance"][0]["matrix_mm_per_N"][2][2].get<double>() == 3e-6);
  }
}
