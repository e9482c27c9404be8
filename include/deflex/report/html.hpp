// report.html: one self-contained page (opens offline) a process engineer can
// show: provenance, the summary as written -> compensated, the machined surface
// in 3D coloured by the surface error (three.js), top views with ticks and a
// colour bar, plots along the program (dygraphs), a histogram and the worst
// lines with their source text.
//
// The numbers are those of points.csv and summary.json; only the drawing is
// decimated (report::Page). The libraries (Debian's libjs-three and
// libjs-dygraphs) are compiled into deflex (cmake/embed_report.cmake).
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/report/json.hpp"
#include "deflex/report/recorder.hpp"

namespace deflex::report {

// A measured point beside its prediction (simulate --measured), work frame, mm.
struct MeasuredMark {
  double x_mm = 0, y_mm = 0, z_mm = 0;
  double measured_error_mm = 0;
  bool predicted = false;          // false: no prediction within reach
  double predicted_error_mm = 0;
};

struct HtmlInput {
  std::string title;
  std::vector<std::pair<std::string, std::string>> provenance;  // label, value
  Json summary;                         // as written to summary.json
  const Page* page = nullptr;           // what it draws (Recorder::page())
  std::map<std::uint32_t, std::string> line_text;  // the worst lines' text, by line
  double tolerance_mm = 0.01;
  std::vector<std::vector<std::string>> facts;  // {label, text, summary key}: rows under the summary
  std::vector<MeasuredMark> measured;   // empty: the page has no measured section
};

// The page's text.
std::string report_html(const HtmlInput& in);

// The SHA-256 of `bytes`, as 64 hex digits (OpenSSL).
std::string sha256_hex(std::string_view bytes);
// The same over bytes given piece by piece.
class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;
  void add(std::string_view bytes);
  std::string hex();  // once, after the last add()

 private:
  void* ctx_;  // EVP_MD_CTX
};

}  // namespace deflex::report
