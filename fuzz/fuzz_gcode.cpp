// G-code reader + interpreter + writer: never crash, never hang past the
// --max-blocks budget, and the untouched rewrite is the input byte for byte.
#include <cstdlib>
#include <string>
#include <vector>

#include "deflex/gcode/program.hpp"
#include "deflex/interp/interpreter.hpp"
#include "deflex/profile/profile.hpp"
#include "deflex/writer/writer.hpp"
#include "fuzz_support.hpp"

using namespace deflex;

namespace {
class Null : public interp::MotionSink {
 public:
  void motion(const interp::Motion&) override {}
};

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
    Null sink;
    interp::interpret(prog, o, diags, sink);
    writer::Rewriter w(prog, d);
    if (w.str() != text) {
      std::fprintf(stderr, "fuzz: rewrite is not byte-identical\n");
      std::abort();
    }
  });
}
