#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <unistd.h>

#include "../support.hpp"

using namespace deflex;
namespace fs = std::filesystem;

TEST_SUITE("profile") {

TEST_CASE("every built-in dialect loads, with the decimal rule it documents") {
  auto names = profile::dialect_names();
  CHECK(names.size() == 5);
  for (const auto& n : names) CHECK_NOTHROW(profile::load_dialect(n));
  // The rule each postproc/<name>.yaml states: a number without a decimal
  // point counts least input increments of 0.001 mm (0.0001 in) on Fanuc, Haas
  // and Siemens in ISO mode; on LinuxCNC and Heidenhain in ISO it is the value
  // itself. So X1000 is 1 mm or 1000 mm, and in G20 0.1 in or 1000 in.
  struct Rule {
    const char* dialect;
    profile::DecimalRule rule;
    double x1000_mm, x1000_inch_mm;
  };
  const Rule rules[] = {
      {"fanuc", profile::DecimalRule::least_input_increment, 1.0, 2.54},
      {"haas", profile::DecimalRule::least_input_increment, 1.0, 2.54},
      {"siemens-iso", profile::DecimalRule::least_input_increment, 1.0, 2.54},
      {"linuxcnc", profile::DecimalRule::calculator, 1000.0, 25400.0},
      {"heidenhain-iso", profile::DecimalRule::calculator, 1000.0, 25400.0},
  };
  for (const Rule& r : rules) {
    CAPTURE(r.dialect);
    CHECK(std::find(names.begin(), names.end(), r.dialect) != names.end());
    CHECK(profile::load_dialect(r.dialect).decimal_rule == r.rule);
    const test::Interpreted mm = test::interpret_text("N10 G21 G90 G0 X1000\n", r.dialect);
    const test::Interpreted inch = test::interpret_text("N10 G20 G90 G0 X1000\n", r.dialect);
    REQUIRE(mm.motions.size() == 1);
    REQUIRE(inch.motions.size() == 1);
    CHECK(mm.motions[0].end_mm[0] == doctest::Approx(r.x1000_mm));
    CHECK(inch.motions[0].end_mm[0] == doctest::Approx(r.x1000_inch_mm));
  }
  CHECK(profile::load_dialect("haas").cycle_repeat_word == 'L');
  CHECK(profile::load_dialect("heidenhain-iso").comment_style == profile::CommentStyle::semicolon);
  CHECK_THROWS_AS(profile::load_dialect("okuma"), Error);
}

TEST_CASE("YAML errors carry file:line:col") {
  fs::path dir = fs::temp_directory_path() / ("deflex-profile-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::string f = (dir / "m.yaml").string();
  test::write_file(f, "name: m\ndialect: fanuc\ntravel_mm:\n  x: [0, oops]\n");
  auto what = [&] {
    try { profile::load_machine(f); } catch (const Error& e) { return std::string(e.what()); }
    return std::string("no error");
  };
  CHECK(what().find(f + ":4:10: error: travel_mm.x must be a number, not 'oops'") != std::string::npos);
  test::write_file(f, "name: m\ndialekt: fanuc\n");
  CHECK(what().find(f + ":2:1: error: unknown key 'dialekt'") != std::string::npos);
  test::write_file(f, "name: m\n  bad: [\n");
  CHECK(what().find(f + ":2:") != std::string::npos);
  test::write_file(f, "name: m\ndialect: okuma\n");
  CHECK_THROWS(profile::load_machine(f));
  try {
    test::write_file(f, "name: [\n");
    profile::load_machine(f);
  } catch (const Error& e) {
    CHECK(e.kind() == ErrorKind::config);
  }
  fs::remove_all(dir);
}

TEST_CASE("the sample machine profile reads") {
  auto m = profile::load_machine("mill3");
  CHECK(m.dialect == "fanuc");
  CHECK(m.travel.set);
  CHECK(m.travel.max_mm[2] == 0.0);
  CHECK(m.work_offsets_mm.at("G54")[2] == -300.0);
}

}  // TEST_SUITE
