// Every JSON deflex prints is built by deflex::report (nlohmann::json): it
// parses back whatever the file names and messages contain, and uses the same
// field names in every command.
#include <doctest/doctest.h>

#include <filesystem>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "../support.hpp"

using namespace deflex;
namespace fs = std::filesystem;
using nlohmann::json;

TEST_SUITE("cli") {

TEST_CASE("json: check --format json on a file named my \"wall\".nc parses, with every diagnostic") {
  const fs::path dir = fs::temp_directory_path() / ("deflex-json-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string f = (dir / "my \"wall\"\\1.nc").string();
  // Line 2: an unknown word (error); line 1 has no G21 (a warning, later).
  test::write_file(f, "G90 G54\nG1 X10 Y0 Z0 F100 Q\"x\nM30\n");
  const auto r = test::run_cli({"check", f, "--format", "json"});
  CHECK(r.rc == 1);
  json j;
  REQUIRE_NOTHROW(j = json::parse(r.out));
  CHECK(j["file"] == f);
  CHECK(j["errors"].get<int>() >= 1);
  const json& d = j["diagnostics"];
  REQUIRE(d.is_array());
  CHECK(static_cast<int>(d.size()) == j["errors"].get<int>() + j["warnings"].get<int>() +
                                          static_cast<int>(std::count_if(d.begin(), d.end(), [](const json& x) {
                                            return x["severity"] == "note";
                                          })));
  bool error_on_line_2 = false;
  for (const json& x : d) {
    CHECK(x["file"] == f);
    for (const char* k : {"file", "line", "col", "severity", "message"}) CHECK(x.contains(k));
    error_on_line_2 = error_on_line_2 || (x["severity"] == "error" && x["line"] == 2 && x["col"].get<int>() > 0);
  }
  CHECK(error_on_line_2);
  fs::remove_all(dir);
}

TEST_CASE("json: diff --format json names its files file_a and file_b and parses") {
  const auto r = test::run_cli({"diff", "samples/programs/pocket_finish.nc", "tests/golden/pocket_other.nc", "--format", "json"});
  json j;
  REQUIRE_NOTHROW(j = json::parse(r.out));
  CHECK(j["file_a"] == "samples/programs/pocket_finish.nc");
  CHECK(j["file_b"] == "tests/golden/pocket_other.nc");
  CHECK(j["other"].size() == 1);
  CHECK(j["max_displacement_mm"].get<double>() == 0.5);
}

}  // TEST_SUITE
