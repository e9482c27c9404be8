// report.html of the main job (scripts/main.sh) opened in a real browser:
// headless Chromium from Debian. No console message and no script error; the
// 3D views, the top views and the plots drawn (their regions of a screenshot
// are not blank); every summary number the page shows equals summary.json.
// Skipped where Chromium (or libpng, to read the screenshot) is absent: the case
// carries doctest::skip() and is the suite `report_browser`, a CTest entry of
// its own that ctest then reports skipped (cmake/tests.cmake).
#include <doctest/doctest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <regex>

#ifdef DEFLEX_HAVE_PNG
#include <png.h>
#endif

#include "../support.hpp"
#include "walls_measured.hpp"
#include "deflex/report/json.hpp"

namespace fs = std::filesystem;
using namespace deflex;

namespace {

using test::TempDir;

#ifdef DEFLEX_HAVE_PNG
constexpr bool kHavePng = true;
#else
constexpr bool kHavePng = false;
#endif

std::string chromium() {
  for (const char* c : {"/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome"})
    if (::access(c, X_OK) == 0) return c;
  return "";
}

// Runs Chromium headless on `page` with the same window each time (the
// screenshot and the DOM must share one layout): `what` its action, its
// standard output to `out`, its log to `log`. SwiftShader draws WebGL on the CPU.
int browse(const std::string& exe, const fs::path& profile, const std::string& what, const fs::path& page,
           const fs::path& out, const fs::path& log) {
  const std::string cmd = exe + " --headless --no-sandbox --enable-unsafe-swiftshader --use-angle=swiftshader"
                                " --force-device-scale-factor=1 --window-size=1400,4200 --hide-scrollbars"
                                " --virtual-time-budget=15000 --enable-logging=stderr --v=0 --user-data-dir='" +
                          profile.string() + "' " + what + " 'file://" + page.string() + "' >'" + out.string() +
                          "' 2>'" + log.string() + "'";
  return std::system(cmd.c_str());
}

#ifdef DEFLEX_HAVE_PNG
struct Image {
  int w = 0, h = 0;
  std::vector<unsigned char> rgb;
  bool background(int x, int y, const unsigned char bg[3]) const {
    const unsigned char* p = &rgb[3 * (static_cast<std::size_t>(y) * w + x)];
    return std::abs(p[0] - bg[0]) < 6 && std::abs(p[1] - bg[1]) < 6 && std::abs(p[2] - bg[2]) < 6;
  }
};

Image read_png(const std::string& path) {
  png_image im{};
  im.version = PNG_IMAGE_VERSION;
  Image out;
  REQUIRE(png_image_begin_read_from_file(&im, path.c_str()));
  im.format = PNG_FORMAT_RGB;
  out.w = static_cast<int>(im.width);
  out.h = static_cast<int>(im.height);
  out.rgb.resize(PNG_IMAGE_SIZE(im));
  REQUIRE(png_image_finish_read(&im, nullptr, out.rgb.data(), 0, nullptr));
  return out;
}

// Share of the pixels of rect [x, y, w, h] (inset by 4 px) that differ from `bg`.
double drawn_share(const Image& im, const report::Json& r, const unsigned char bg[3]) {
  const int x0 = r[0].get<int>() + 4, y0 = r[1].get<int>() + 4;
  const int x1 = std::min(im.w, r[0].get<int>() + r[2].get<int>() - 4);
  const int y1 = std::min(im.h, r[1].get<int>() + r[3].get<int>() - 4);
  double n = 0, drawn = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      n += 1;
      drawn += !im.background(x, y, bg);
    }
  return n > 0 ? drawn / n : 0.0;
}
// Share of the pixels of rect [x, y, w, h] that are clearly red (material left beyond the tolerance).
double red_share(const Image& im, const report::Json& r) {
  double n = 0, red = 0;
  for (int y = r[1].get<int>(); y < std::min(im.h, r[1].get<int>() + r[3].get<int>()); ++y)
    for (int x = r[0].get<int>(); x < std::min(im.w, r[0].get<int>() + r[2].get<int>()); ++x) {
      const unsigned char* p = &im.rgb[3 * (static_cast<std::size_t>(y) * im.w + x)];
      n += 1;
      red += p[0] > 180 && p[1] < 150 && p[2] < 150;
    }
  return n > 0 ? red / n : 0.0;
}

// A page as Chromium shows it: the DOM after its scripts ran, the console's
// lines, the regions of its drawings (the page's data-layout), the screenshot.
struct Rendered {
  std::string dom, console;
  report::Json layout;
  Image shot;
};

Rendered render(const std::string& exe, const fs::path& page, const fs::path& work) {
  REQUIRE(browse(exe, work / "profile", "--dump-dom", page, work / "dom.html", work / "dom.log") == 0);
  REQUIRE(browse(exe, work / "profile", "--screenshot='" + (work / "shot.png").string() + "'", page, work / "shot.out",
                 work / "shot.log") == 0);
  Rendered r;
  r.dom = test::read_file((work / "dom.html").string());
  const std::string log = test::read_file((work / "dom.log").string()) + test::read_file((work / "shot.log").string());
  for (std::size_t at = log.find("CONSOLE"); at != std::string::npos; at = log.find("CONSOLE", at + 1))
    r.console += log.substr(at, log.find('\n', at) - at) + "\n";
  std::smatch m;
  const std::regex lay("data-layout=\"([^\"]*)\"");
  REQUIRE(std::regex_search(r.dom, m, lay));
  std::string lj = m[1];
  for (std::size_t at; (at = lj.find("&quot;")) != std::string::npos;) lj.replace(at, 6, "\"");
  r.layout = report::Json::parse(lj);
  r.shot = read_png((work / "shot.png").string());
  return r;
}
#endif

// The text a summary figure is shown with (as the page's um() and share format them).
std::string shown(const std::string& key, double v) {
  char b[64];
  if (key.find("out_of_tolerance_share") != std::string::npos) std::snprintf(b, sizeof b, "%.1f %%", 100 * v);
  else std::snprintf(b, sizeof b, "%.1f", 1000 * v);
  return b;
}

// The text a figure of summary.json's "measured" is shown with in the agreement table.
std::string shown_measured(const std::string& key, const report::Json& v) {
  if (v.is_null()) return "–";
  char b[64];
  if (key.ends_with("_mm")) std::snprintf(b, sizeof b, "%.1f", 1000 * v.get<double>());
  else if (key.ends_with("_share")) std::snprintf(b, sizeof b, "%.1f %%", 100 * v.get<double>());
  else if (key == "correlation") std::snprintf(b, sizeof b, "%.3f", v.get<double>());
  else std::snprintf(b, sizeof b, "%zu", v.get<std::size_t>());
  return b;
}

}  // namespace

TEST_SUITE("report_browser") {
  // scripts/install-deps.sh --test installs Chromium and libpng.
  TEST_CASE("report.html of the main job in headless Chromium: no errors, views and plots drawn, numbers = summary.json" *
            doctest::skip(chromium().empty() || !kHavePng)) {
#ifdef DEFLEX_HAVE_PNG
    const std::string exe = chromium();
    TempDir tmp;
    const fs::path rep = tmp.p / "report";
    // The main job of scripts/main.sh.
    const auto r = test::run_cli({"compensate", "samples/programs/six_surfaces.nc", "--stock",
                                  "samples/stock/six_surfaces_stock.stl", "--part", "samples/parts/six_surfaces.stl",
                                  "-o", (tmp.p / "comp.nc").string(), "--report", rep.string()});
    REQUIRE(r.rc == 0);
    const fs::path page = rep / "report.html";
    REQUIRE(fs::exists(page));

    const Rendered shown_page = render(exe, page, tmp.p);
    const std::string& dom = shown_page.dom;

    // No console message at all (the page logs nothing when all is well) and no script error.
    CHECK_MESSAGE(shown_page.console.empty(), shown_page.console);
    CHECK(dom.find("<pre id=\"errors\"></pre>") != std::string::npos);
    REQUIRE(dom.find("data-ready=\"yes\"") != std::string::npos);

    // Every figure of the summary table equals summary.json's, as the page rounds it.
    const report::Json summary = report::Json::parse(test::read_file((rep / "summary.json").string()));
    const std::regex cell("data-key=\"(surface_error[a-z_]*_mm)\\.([a-z0-9_]+)\">([^<]*)<");
    int compared = 0;
    for (auto it = std::sregex_iterator(dom.begin(), dom.end(), cell); it != std::sregex_iterator(); ++it) {
      const std::string map = (*it)[1], field = (*it)[2], text = (*it)[3];
      CAPTURE(map + "." + field);
      REQUIRE(summary[map].contains(field));
      CHECK(text == shown(field, summary[map][field].get<double>()));
      ++compared;
    }
    CHECK(compared == 16);  // 8 figures, as written and compensated
    const std::regex pts("data-key=\"compensated_points\">([0-9]+) of ([0-9]+)<");
    std::smatch m;
    REQUIRE(std::regex_search(dom, m, pts));
    CHECK(std::stoul(m[1]) == summary["compensated_points"].get<std::size_t>());
    CHECK(std::stoul(m[2]) == summary["cl_points"].get<std::size_t>());

    // No measurements given: no section for them.
    CHECK(dom.find("<h2>Predicted against measured</h2>") == std::string::npos);
    CHECK(dom.find("id=\"scatter\"") == std::string::npos);

    // The drawings: each region of the screenshot holds more than its background.
    const report::Json& layout = shown_page.layout;
    const Image& shot = shown_page.shot;
    CHECK(layout["measured3d"].empty());
    const unsigned char view_bg[3] = {0xf7, 0xf7, 0xf7}, white[3] = {0xff, 0xff, 0xff};
    REQUIRE(layout["view3d"].size() == 2);  // as written and compensated, side by side
    for (const auto& v : layout["view3d"]) CHECK(drawn_share(shot, v, view_bg) > 0.05);
    // The top views are mostly white where the error is within the tolerance;
    // their axes, ticks and colour bar are drawn on both, and the error of the
    // program as written (10.8 % of the points outside) shows red on its map
    // and its 3D view, the compensated one (none outside) none.
    REQUIRE(layout["top"].size() == 2);
    for (const auto& v : layout["top"]) CHECK(drawn_share(shot, v, white) > 0.03);
    REQUIRE(layout["topmaps"].size() == 2);  // the maps within the canvases, without the colour bars
    CHECK(red_share(shot, layout["topmaps"][0]) > 0.01);
    CHECK(red_share(shot, layout["topmaps"][1]) == 0);
    CHECK(red_share(shot, layout["view3d"][0]) > 0.002);
    CHECK(red_share(shot, layout["view3d"][1]) == 0);
    REQUIRE(layout["plots"].size() >= 6);
    for (const auto& v : layout["plots"]) {
      if (v[1].get<int>() + v[3].get<int>() > shot.h) continue;  // below the window
      CHECK(drawn_share(shot, v, white) > 0.02);
    }
#endif
  }
  TEST_CASE("report.html with measured points in headless Chromium: both point views and the scatter drawn, the agreement = summary.json" *
            doctest::skip(chromium().empty() || !kHavePng)) {
#ifdef DEFLEX_HAVE_PNG
    const std::string exe = chromium();
    TempDir tmp;
    test::write_walls_measured(tmp / "m.csv", 3);
    const auto r = test::simulate_job(test::walls_measured_settings(tmp / "m.csv", tmp / "rep"));
    REQUIRE_MESSAGE(r.ok(), r.what);
    const Rendered shown_page = render(exe, tmp.p / "rep/report.html", tmp.p);
    const std::string& dom = shown_page.dom;
    CHECK_MESSAGE(shown_page.console.empty(), shown_page.console);
    CHECK(dom.find("<pre id=\"errors\"></pre>") != std::string::npos);
    REQUIRE(dom.find("data-ready=\"yes\"") != std::string::npos);
    CHECK(dom.find("<h2>Predicted against measured</h2>") != std::string::npos);

    // Measured on the left, predicted on the right, and the scatter: each drawn.
    const report::Json& layout = shown_page.layout;
    const unsigned char view_bg[3] = {0xf7, 0xf7, 0xf7}, white[3] = {0xff, 0xff, 0xff};
    REQUIRE(layout["measured3d"].size() == 2);
    for (const auto& v : layout["measured3d"]) CHECK(drawn_share(shown_page.shot, v, view_bg) > 0.01);
    CHECK(layout["measured3d"][0][0].get<int>() < layout["measured3d"][1][0].get<int>());
    REQUIRE(layout["scatter"].size() == 1);
    CHECK(drawn_share(shown_page.shot, layout["scatter"][0], white) > 0.02);

    // The agreement table says what summary.json says.
    const report::Json summary = report::Json::parse(test::read_file((tmp.p / "rep/summary.json").string()));
    const std::regex cell("data-key=\"measured\\.([a-z_]+)\">([^<]*)<");
    int compared = 0;
    for (auto it = std::sregex_iterator(dom.begin(), dom.end(), cell); it != std::sregex_iterator(); ++it) {
      const std::string key = (*it)[1], text = (*it)[2];
      CAPTURE(key);
      REQUIRE(summary["measured"].contains(key));
      CHECK(text == shown_measured(key, summary["measured"][key]));
      ++compared;
    }
    CHECK(compared == 9);
    CHECK(summary["measured"]["without_prediction"] == 3);
#endif
  }
}
