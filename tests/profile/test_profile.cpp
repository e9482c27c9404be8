#include <doctest/doctest.h>

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
  CHECK(profile::load_dialect("fanuc").decimal_rule == profile::DecimalRule::least_input_increment);
  CHECK(profile::load_dialect("linuxcnc").decimal_rule == profile::DecimalRule::calculator);
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
    CHECK(e.code() == Exit::config);
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
