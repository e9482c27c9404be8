#include "deflex/compensate/apply.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "deflex/gcode/skeleton.hpp"
#include "deflex/writer/writer.hpp"

namespace deflex::compensate {
namespace {

// Where a missing axis word goes: after the highest axis word below it, else
// after the last G word, else after N, else after the last word of the block.
std::uint32_t insert_position(const gcode::Block& b, char axis) {
  const gcode::Word* best = nullptr;
  for (const gcode::Word& w : b.words)
    if ((w.letter == 'X' || w.letter == 'Y' || w.letter == 'Z') && w.letter < axis) best = &w;
  if (!best)
    for (const gcode::Word& w : b.words)
      if (w.letter == 'G') best = &w;
  if (!best)
    for (const gcode::Word& w : b.words)
      if (w.letter == 'N') best = &w;
  if (!best && !b.words.empty()) best = &b.words.back();
  return best ? best->end : b.begin;
}

// The value a control will read back from a number deflex writes, mm.
double written_mm(double value_mm, bool inch, const profile::Dialect& d) {
  std::string s = writer::format_number(inch ? value_mm / 25.4 : value_mm, inch, d);
  double v = std::strtod(s.c_str(), nullptr);
  return inch ? v * 25.4 : v;
}

struct Collect : interp::MotionSink {
  std::vector<interp::Motion> motions;
  void motion(const interp::Motion& m) override { motions.push_back(m); }
};

}  // namespace

std::string apply_offsets(const gcode::Program& prog, const profile::Dialect& d,
                          const std::vector<interp::Motion>& motions, const std::vector<V3>& offsets,
                          WriteStats* stats) {
  writer::Rewriter w(prog, d);
  WriteStats st;
  Diagnostics quiet(nullptr, 0);
  gcode::Block b;
  static const char axes[] = {'X', 'Y', 'Z'};
  double carried[3] = {NAN, NAN, NAN};  // what the output program's control holds, mm
  for (std::size_t i = 0; i < motions.size(); ++i) {
    const interp::Motion& m = motions[i];
    const V3 o = offsets.empty() ? V3(V3::Zero()) : offsets[i];
    if (!m.plain) {
      // Cycles, G28/G30/G53, subprograms, G91: never moved, and never preceded
      // by a moved point (compensate::movable), so they end where they did.
      for (int a = 0; a < 3; ++a) carried[a] = m.end_mm[a];
      continue;
    }
    bool lexed = false;
    for (int a = 0; a < 3; ++a) {
      const double want = m.end_mm[a] + o[a];
      if (!lexed) { prog.lex(m.line, b, quiet); lexed = true; }
      const gcode::Word* word = b.find(axes[a]);
      if (word) {
        // Splice only when the number written changes (an offset below the
        // last written digit leaves the programmer's text alone).
        if (o[a] != 0.0 && written_mm(want, m.inch, d) != written_mm(m.end_mm[a], m.inch, d)) {
          w.set_number(*word, m.inch ? want / 25.4 : want, m.inch);
          carried[a] = written_mm(want, m.inch, d);
          ++st.numbers_changed;
        } else {
          carried[a] = m.end_mm[a];
        }
      } else if (!(std::fabs(carried[a] - want) <= 1e-9)) {
        // The block relies on the modal value, which the previous block moved
        // (or which is unknown): say what this block means.
        if (std::isnan(carried[a]) && o[a] == 0.0) continue;
        w.insert_word(insert_position(b, axes[a]), axes[a], m.inch ? want / 25.4 : want, m.inch);
        carried[a] = written_mm(want, m.inch, d);
        ++st.words_inserted;
      }
    }
  }
  if (stats) *stats = st;
  if (w.edits() == 0) return prog.bytes();
  return w.str();
}

void safety_check(const gcode::Program& original, const std::vector<interp::Motion>& om, const std::string& text,
                  const interp::Options& opt, const std::vector<bool>& movable, double max_offset_mm) {
  gcode::Program out(SourceText(original.source().name() + " (compensated)", text));
  auto fail = [&](std::uint32_t line, const std::string& what) {
    throw Error(Exit::internal, original.source().name() + ":" + std::to_string(line) +
                                    ":1: error: safety check failed: " + what +
                                    "; nothing was written (this is a bug in deflex, please report it)");
  };
  if (out.line_count() != original.line_count()) fail(1, "the written program has a different number of lines");
  Diagnostics quiet(nullptr, 0);
  gcode::Block a, b;
  for (std::uint32_t l = 1; l <= original.line_count(); ++l) {
    original.lex(l, a, quiet);
    out.lex(l, b, quiet);
    if (gcode::skeleton_hash(original, a) != gcode::skeleton_hash(out, b))
      fail(l, "the block changed in more than its coordinate words");
  }
  std::ostringstream errs;
  Diagnostics diags(&errs, 0);
  Collect c;
  interp::interpret(out, opt, diags, c);
  if (diags.errors()) fail(1, "the written program does not read back cleanly:\n" + errs.str());
  if (c.motions.size() != om.size()) fail(1, "the written program has a different number of motions");
  // Numbers are written with the dialect's decimals: allow their rounding.
  const double round_mm = 0.5 * std::pow(10.0, -opt.dialect.decimals_mm) * 1.001;
  const double round_in = 0.5 * std::pow(10.0, -opt.dialect.decimals_inch) * 25.4 * 1.001;
  for (std::size_t i = 0; i < om.size(); ++i) {
    const interp::Motion &x = om[i], &y = c.motions[i];
    if (x.kind != y.kind || x.line != y.line) fail(x.line, "a motion changed its kind or its block");
    const double r = x.inch ? round_in : round_mm;
    const double allowed = movable[i] ? max_offset_mm + r : r;
    double d = 0;
    for (int k = 0; k < 3; ++k) d = std::max(d, std::fabs(y.end_mm[k] - x.end_mm[k]));
    if (d > allowed) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "a %s motion moved by %.6f mm (allowed %.6f mm)",
                    movable[i] ? "compensated" : "fixed", d, allowed);
      fail(x.line, buf);
    }
  }
}

}  // namespace deflex::compensate
