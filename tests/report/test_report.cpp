// The report's pieces: statistics, the top-view grid, the page's data and its
// safety against hostile program text, and deflex compare against simulate.
#include <doctest/doctest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <regex>

#include "../support.hpp"
#include "walls_measured.hpp"
#include "deflex/report/compare.hpp"
#include "deflex/report/html.hpp"
#include "deflex/report/stats.hpp"

namespace fs = std::filesystem;
using namespace deflex;
using doctest::Approx;

namespace {

// A recorder's page of `n` points in material along X, error e(i), one per line.
report::Page page_of(std::size_t n, double (*e)(std::size_t)) {
  report::RecorderOptions o;
  o.page = true;
  report::Recorder rec(o);
  for (std::size_t i = 0; i < n; ++i) {
    compensate::Point p;
    p.line = static_cast<std::uint32_t>(i + 1);
    p.motion = static_cast<std::uint32_t>(i);
    p.air = false;
    p.tip_mm = {static_cast<double>(i) * 0.1, 0, 0};
    p.force_N = {static_cast<double>(i), 0, 0};
    p.error_mm = e(i);
    rec.point(p, report::V3::Zero(), 0);
  }
  rec.finish();
  return rec.page();
}

std::string data_of(const std::string& page) {
  const std::string tag = "<script id=\"deflex-data\" type=\"application/json\">";
  const std::size_t a = page.find(tag);
  REQUIRE(a != std::string::npos);
  const std::size_t b = page.find("</script>", a);
  return page.substr(a + tag.size(), b - a - tag.size());
}

}  // namespace

TEST_SUITE("report") {
  TEST_CASE("error statistics: nearest-rank percentiles of |e|, NaN not counted") {
    std::vector<double> e;
    for (int i = 1; i <= 100; ++i) e.push_back((i % 2 ? -1 : 1) * i * 1e-3);  // |e| = 1..100 um
    e.push_back(report::kNone);
    const report::ErrorStats s = report::error_stats(e, 0.0905);
    CHECK(s.points == 100);
    CHECK(s.p50_abs == Approx(0.050));
    CHECK(s.p95_abs == Approx(0.095));
    CHECK(s.p99_abs == Approx(0.099));
    CHECK(s.max_abs == Approx(0.100));
    CHECK(s.max_under == Approx(0.100));
    CHECK(s.max_over == Approx(-0.099));
    CHECK(s.share_out == Approx(0.10));  // 91..100 um
    double sq = 0;
    for (int i = 1; i <= 100; ++i) sq += i * i * 1e-6;
    CHECK(s.rms == Approx(std::sqrt(sq / 100)));
  }

  TEST_CASE("top-view grid: passes one step-over apart leave no empty stripe; the largest |e| of a cell wins") {
    // Passes along X at y = 0, 1.0, 2.0, ... (step-over 1 mm), points every 0.5 mm.
    std::vector<Eigen::Vector3d> xyz;
    std::vector<double> e;
    for (int k = 0; k < 10; ++k)
      for (int i = 0; i <= 40; ++i) {
        xyz.emplace_back(0.5 * i, 1.0 * k, 0.1 * k);
        e.push_back(k == 4 && i == 20 ? -0.05 : 0.001 * k);
      }
    // A cell of half the step-over would leave every other row empty: the cell
    // is at least the step-over given, and gaps between filled cells are filled.
    const report::Grid g = report::make_grid(xyz, {&e}, 1.05);
    CHECK(g.cell_mm >= 1.05);
    int empty_inside = 0;
    for (int j = 1; j + 1 < g.ny; ++j)
      for (int i = 1; i + 1 < g.nx; ++i) empty_inside += std::isnan(g.values[0][static_cast<std::size_t>(j) * g.nx + i]);
    CHECK(empty_inside == 0);
    double most = 0;
    for (double v : g.values[0])
      if (!std::isnan(v) && std::fabs(v) > std::fabs(most)) most = v;
    CHECK(most == Approx(-0.05));
    // Without the step-over hint the same grid at 300 cells has stripes: the hint matters.
    const report::Grid fine = report::make_grid(xyz, {&e}, 0);
    int empty_fine = 0;
    for (double v : fine.values[0]) empty_fine += std::isnan(v);
    CHECK(empty_fine > 0);
  }

  TEST_CASE("report.html: decimated plots keep every peak; hostile program text cannot break out of the page") {
    // 100,000 points with one spike: the plots draw at most 4000 rows, the spike among them.
    const report::Page pg = page_of(100000, [](std::size_t i) { return i == 77777 ? 0.5 : 1e-4 * std::sin(i * 0.01); });
    const std::string evil = "G1 X1 (</script><script>alert(1)</script> @@DATA@@ /*@@THREE@@*/)";
    report::HtmlInput in;
    in.title = "<b>evil</b>";
    in.page = &pg;
    for (const auto& row : pg.worst["rows"]) in.line_text[row["line"].get<std::uint32_t>()] = evil;
    in.summary = {{"surface_error_mm", "x"}};
    const std::string page = report::report_html(in);
    // The program's text appears only inside the data, escaped: exactly the
    // template's scripts close, and the title is escaped.
    std::size_t closes = 0;
    for (std::size_t at = page.find("</script>"); at != std::string::npos; at = page.find("</script>", at + 1)) ++closes;
    CHECK(closes == 5);  // data, three.js, OrbitControls, dygraphs, the page's own
    CHECK(page.find("<title>&lt;b&gt;evil&lt;/b&gt;</title>") != std::string::npos);
    const report::Json d = report::Json::parse(data_of(page));
    CHECK(d["worst"]["rows"][0]["line"] == 77778);
    CHECK(d["worst"]["rows"][0]["text"].get<std::string>().find("</script>") != std::string::npos);
    const auto& x = d["series"]["x"];
    CHECK(x.size() <= 4000);
    double top = 0;
    for (const auto& v : d["series"]["e0"])
      if (!v.is_null()) top = std::max(top, v.get<double>());
    CHECK(top == Approx(500.0));  // um
  }

  TEST_CASE("report.html: the measured section only with measured points; past 5000 each run keeps its worst disagreement") {
    const report::Page pg = page_of(100, [](std::size_t i) { return 1e-3 * std::sin(i * 0.1); });
    report::HtmlInput in;
    in.page = &pg;
    in.summary = {{"surface_error_mm", "x"}};
    const std::string without = report::report_html(in);
    CHECK(without.find("<h2>Predicted against measured</h2>") == std::string::npos);
    CHECK(without.find("id=\"scatter\"") == std::string::npos);
    CHECK(without.find("@@MEASURED") == std::string::npos);
    CHECK(!report::Json::parse(data_of(without)).contains("measured"));

    // 12,001 points, every third without a prediction, one far off its
    // prediction (point 7001): 4001 drawn, runs of 3, that one among them.
    for (std::size_t i = 0; i < 12001; ++i) {
      const double m = 1e-3 * std::cos(i * 0.01);
      in.measured.push_back({0.1 * i, 1, -2, m, i % 3 != 1, i == 7001 ? m + 0.05 : m + 1e-4});
    }
    const std::string with = report::report_html(in);
    CHECK(with.find("<h2>Predicted against measured</h2>") != std::string::npos);
    CHECK(with.find("id=\"measured3d\"") != std::string::npos);
    CHECK(with.find("id=\"scatter\"") != std::string::npos);
    CHECK(with.find("@@MEASURED") == std::string::npos);
    const report::Json d = report::Json::parse(data_of(with))["measured"];
    CHECK(d["points"] == 12001);
    CHECK(d["per_bucket"] == 3);
    for (const char* col : {"x", "y", "z", "m", "p"}) CHECK(d[col].size() == 4001);
    // Each run of three keeps a point with a prediction (the disagreement is
    // what is kept), and point 7001's 50 um is there.
    double worst_mm = 0;
    for (std::size_t k = 0; k < d["p"].size(); ++k) {
      REQUIRE(!d["p"][k].is_null());
      worst_mm = std::max(worst_mm, std::fabs(d["p"][k].get<double>() - d["m"][k].get<double>()));
    }
    CHECK(worst_mm == Approx(0.05));
    bool has_7001 = false;
    for (const auto& x : d["x"]) has_7001 |= x.get<double>() == Approx(700.1);
    CHECK(has_7001);

    // A few points: all drawn, those without a prediction null in "p", errors in mm.
    in.measured.resize(4);
    const report::Json few = report::Json::parse(data_of(report::report_html(in)))["measured"];
    CHECK(few["per_bucket"] == 1);
    REQUIRE(few["p"].size() == 4);
    CHECK(few["p"][1].is_null());
    CHECK(few["p"][0].get<double>() == Approx(1e-3 + 1e-4));
    CHECK(few["m"][1].get<double>() == Approx(1e-3 * std::cos(0.01)).epsilon(1e-6));
  }

  TEST_CASE("simulate --measured: report.html holds every measured point, as measured.csv has them") {
    test::TempDir dir("page");
    const std::size_t n = test::write_walls_measured(dir / "m.csv", 3);
    const auto r = test::simulate_job(test::walls_measured_settings(dir / "m.csv", dir / "rep"));
    REQUIRE_MESSAGE(r.ok(), r.what);
    const std::string page = test::read_file(dir / "rep/report.html");
    CHECK(page.find("<h2>Predicted against measured</h2>") != std::string::npos);
    const report::Json d = report::Json::parse(data_of(page));
    const report::Json& m = d["measured"];
    const test::Csv csv = test::read_csv(dir / "rep/measured.csv");
    REQUIRE(csv.rows.size() == n);
    CHECK(m["points"] == n);
    REQUIRE(m["x"].size() == n);  // fewer than 5000: all drawn
    std::size_t without = 0;
    for (std::size_t i = 0; i < n; ++i) {
      CAPTURE(i);
      CHECK(std::fabs(m["x"][i].get<double>() - csv.num(i, "x_mm")) <= 0.5e-3 + 1e-9);  // to the micrometre
      const bool predicted = !csv.rows[i][csv.col("predicted_error_mm")].empty();
      CHECK(m["p"][i].is_null() == !predicted);
      if (predicted) CHECK(m["p"][i].get<double>() == Approx(csv.num(i, "predicted_error_mm")).epsilon(1e-9));
      without += !predicted;
    }
    CHECK(without == 3);  // the points above the block
    CHECK(d["summary"]["measured"]["without_prediction"] == 3);
  }

  TEST_CASE("deflex compare: each row equals simulate's figures for that program; CSV and JSON say the same") {
    std::string t = (fs::temp_directory_path() / "deflex-compare-XXXXXX").string();
    const fs::path dir = mkdtemp(t.data());
    const std::vector<std::string> common = {"--stock", "samples/stock/freeform_stock.stl", "--material", "Al7075-T6",
                                             "--cell-mm", "0.1"};
    std::vector<std::string> args = {"compare", "samples/strategies/zigzag_0.nc", "samples/strategies/contour.nc",
                                     "--format", "json", "--report", (dir / "cmp").string()};
    args.insert(args.end(), common.begin(), common.end());
    const auto c = test::run_cli(args);
    REQUIRE(c.rc == 0);
    const report::Json j = report::Json::parse(c.out);
    REQUIRE(j["programs"].size() == 2);
    for (int k = 0; k < 2; ++k) {
      const std::string prog = j["programs"][k]["file"];
      std::vector<std::string> sa = {"simulate", prog, "--report", (dir / ("s" + std::to_string(k))).string()};
      sa.insert(sa.end(), common.begin(), common.end());
      REQUIRE(test::run_cli(sa).rc == 0);
      const report::Json s = report::Json::parse(test::read_file((dir / ("s" + std::to_string(k)) / "summary.json").string()));
      CAPTURE(prog);
      CHECK(j["programs"][k]["error_max_mm"].get<double>() == Approx(s["surface_error_mm"]["max"].get<double>()).epsilon(1e-4));
      CHECK(j["programs"][k]["error_rms_mm"].get<double>() == Approx(s["surface_error_mm"]["rms"].get<double>()).epsilon(1e-4));
      CHECK(j["programs"][k]["cusp_max_mm"].get<double>() == Approx(s["cusp_height_mm"]["max"].get<double>()).epsilon(1e-4));
      CHECK(j["programs"][k]["time_s"].get<double>() == Approx(s["machining_time"]["total_s"].get<double>()).epsilon(1e-4));
    }
    // The zig-zag at 0 deg and the contour differ where they must: path and time.
    CHECK(j["programs"][0]["path_mm"] != j["programs"][1]["path_mm"]);
    const std::string csv = test::read_file((dir / "cmp" / "compare.csv").string());
    CHECK(csv.rfind("program,error_max_mm,", 0) == 0);
    CHECK(std::count(csv.begin(), csv.end(), '\n') == 3);
    CHECK(fs::exists(dir / "cmp" / "compare.html"));
    CHECK(test::run_cli({"compare", "samples/strategies/zigzag_0.nc"}).rc == 2);  // one program is not a comparison
    fs::remove_all(dir);
  }
}
