// Settings named in messages (diag/settings.hpp): each front end names them
// its way, and nothing else in a message changes.
#include <doctest/doctest.h>

#include <algorithm>
#include <sstream>
#include <string>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/diag/settings.hpp"

using namespace deflex;

namespace {
std::string shout(std::string_view k) { return "<" + std::string(k) + ">"; }
}  // namespace

TEST_SUITE("diag") {
  TEST_CASE("{keyword}: by the keyword, or by a front end's name; other braces stay as they are") {
    CHECK(name_settings("{tolerance_mm} must be > 0 mm", {}) == "tolerance_mm must be > 0 mm");
    CHECK(name_settings("{tolerance_mm} must be > 0 mm", shout) == "<tolerance_mm> must be > 0 mm");
    // A file or comment with braces is not a setting, nor is an unclosed brace.
    CHECK(name_settings("/tmp/{x}/a.nc: {gain", shout) == "/tmp/{x}/a.nc: {gain");
    CHECK(name_settings("{{stock}} {stock_from}", shout) == "{<stock>} <stock_from>");
    CHECK(name_settings("", shout).empty());
    CHECK(settings_named("{kt_N_per_mm2}, {kr_N_per_mm2} and {kt_N_per_mm2} {x}") ==
          std::vector<std::string>{"kt_N_per_mm2", "kr_N_per_mm2"});
    for (std::string_view k : setting_keywords())
      CHECK(name_settings("{" + std::string(k) + "}", shout) == shout(k));
  }

  TEST_CASE("an Error: what() by keyword, message() by the front end's names, the errors behind it") {
    const Error e(ErrorKind::settings, "{material_file} needs {material}");
    CHECK(std::string(e.what()) == "material_file needs material");
    CHECK(e.message(shout) == "<material_file> needs <material>");
    CHECK(e.settings() == std::vector<std::string>{"material_file", "material"});
    CHECK(Error(ErrorKind::io, "/tmp/{x}: cannot read").settings().empty());

    std::ostringstream out;
    Diagnostics d(&out, 0);
    d.set_keep(false);  // errors are kept all the same
    d.set_names(shout);
    const SourceText src("p.nc", "G1 X1\nG1 Y\n");
    d.report(Severity::warning, src, 1, 1, "a warning");
    d.report(Severity::error, src, 2, 4, "no number; {max_blocks}");
    CHECK(out.str().find("p.nc:2:4: error: no number; <max_blocks>") != std::string::npos);
    Error failed(ErrorKind::input, "p.nc: error: the program has errors");
    failed.with_errors_of(d);
    REQUIRE(failed.diagnostics().size() == 1);
    CHECK(failed.diagnostics()[0].line == 2);
    CHECK(failed.diagnostics()[0].col == 4);
    CHECK(failed.diagnostics()[0].message == "no number; <max_blocks>");
  }
}
