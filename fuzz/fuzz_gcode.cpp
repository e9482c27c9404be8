// G-code reader + interpreter + writer: never crash, never hang past the
// --max-blocks budget, the untouched rewrite is the input byte for byte, and
// read in pieces (gcode/reader.hpp) the program gives the motions and
// messages it gives whole.
#include <cstdlib>
#include <memory>
#include <sstream>
#include <utility>
#include <string>
#include <vector>

#include "deflex/gcode/program.hpp"
#include "deflex/gcode/reader.hpp"
#include "deflex/interp/interpreter.hpp"
#include "deflex/profile/profile.hpp"
#include "deflex/writer/expand.hpp"
#include "deflex/writer/writer.hpp"
#include "fuzz_support.hpp"

using namespace deflex;

namespace {
class Null : public interp::MotionSink {
 public:
  void motion(const interp::Motion&) override {}
};

class Ends : public interp::MotionSink {
 public:
  std::vector<interp::Vec3> ends;
  void motion(const interp::Motion& m) override { ends.push_back(m.end_mm); }
};

// The interpretation of `text` cut after every `k` lines (k = 0: whole).
std::pair<std::string, std::vector<interp::Vec3>> run(const std::string& text, const interp::Options& o, std::size_t k) {
  std::ostringstream err;
  Diagnostics diags(&err, 20);
  Ends sink;
  if (!k) {
    interp::interpret(gcode::Program(SourceText("fuzz.nc", text)), o, diags, sink);
    return {err.str(), sink.ends};
  }
  interp::Interpreter it(o, diags, sink);
  gcode::Tape tape;
  std::vector<std::unique_ptr<gcode::Program>> pieces;  // alive until the next feed
  std::size_t pos = 0;
  std::uint32_t line = 1;
  while (pos < text.size() || pieces.empty()) {
    std::size_t end = pos, lines = 0;
    while (end < text.size() && lines < k) {
      const std::size_t nl = text.find('\n', end);
      end = nl == std::string::npos ? text.size() : nl + 1;
      ++lines;
    }
    auto p = std::make_unique<gcode::Program>(SourceText("fuzz.nc", text.substr(pos, end - pos), line), tape);
    line += p->line_count();
    pos = end;
    it.feed(*p, pos >= text.size());
    pieces.push_back(std::move(p));
  }
  it.finish();
  return {err.str(), sink.ends};
}

const std::vector<profile::Dialect>& dialects() {
  static const std::vector<profile::Dialect> v = [] {
    std::vector<profile::Dialect> d;
    for (const std::string& n : profile::dialect_names()) d.push_back(profile::load_dialect(n));
    return d;
  }();
  return v;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The dialect follows from the length, so seeds stay plain .nc files.
  const profile::Dialect& d = dialects()[size % dialects().size()];
  const std::string text(reinterpret_cast<const char*>(data), size);
  return fuzz::guarded([&] {
    gcode::Program prog(SourceText("fuzz.nc", text));
    Diagnostics diags(nullptr, 20);
    interp::Options o;
    o.dialect = d;
    o.max_blocks = 10000;  // the budget is under test too; small keeps runs fast
    // G41/G42: every D register has a radius (D n: n / 4 mm), so the
    // tool-centre path is computed for whatever contour the input holds.
    o.cutter_radius_mm = [](int reg) { return std::optional<double>(reg / 4.0); };
    Null sink;
    interp::interpret(prog, o, diags, sink);
    // Subprograms written inline read as a program of their own.
    {
      Diagnostics quiet(nullptr, 20);
      const std::string inline_text = writer::expand_subprograms(prog, o, quiet);
      if (!inline_text.empty()) {
        gcode::Program expanded(SourceText("expanded.nc", inline_text));
        Diagnostics again(nullptr, 20);
        interp::interpret(expanded, o, again, sink);
      }
    }
    writer::Rewriter w(prog, d);
    if (w.str() != text) {
      std::fprintf(stderr, "fuzz: rewrite is not byte-identical\n");
      std::abort();
    }
    // In pieces of 1 to 4 lines (subprogram calls jump across pieces: such a
    // program is read whole).
    if (!gcode::may_need_whole_file(text) && run(text, o, 1 + size % 4) != run(text, o, 0)) {
      std::fprintf(stderr, "fuzz: read in pieces, the program reads differently\n");
      std::abort();
    }
  });
}
