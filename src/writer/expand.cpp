#include "deflex/writer/expand.hpp"

#include <vector>

#include "deflex/writer/writer.hpp"

namespace deflex::writer {
namespace {

struct NoMotions : interp::MotionSink {
  void motion(const interp::Motion&) override {}
};

// The M code of a call or return in the block (980, 990), else 0.
int flow_code(const gcode::Block& b) {
  for (const gcode::Word& w : b.words)
    if (w.letter == 'M' && (w.code10() == 980 || w.code10() == 990)) return w.code10();
  return 0;
}

}  // namespace

std::string expand_subprograms(const gcode::Program& prog, const interp::Options& opt, Diagnostics& diags) {
  // The lines in the order the control runs them, and where subprograms run.
  std::vector<std::uint32_t> trace;
  interp::Options o = opt;
  o.on_line = [&trace](std::uint32_t l) { trace.push_back(l); };
  const int errors = diags.errors();
  const interp::CallStructure calls = interp::call_structure(prog, o, diags);
  if (diags.errors() > errors) return {};
  if (calls.calls.empty()) return prog.bytes();
  const SourceText& src = prog.source();
  const std::string& bytes = prog.bytes();
  auto line_bytes = [&](std::uint32_t l) {
    return bytes.substr(src.line_begin(l), src.line_end_with_eol(l) - src.line_begin(l));
  };
  const std::string eol = bytes.find("\r\n") != std::string::npos ? "\r\n" : "\n";
  std::string out;
  Diagnostics quiet(nullptr, 0);
  gcode::Block b;
  std::uint32_t last_main = 0;
  for (std::uint32_t l : trace) {
    const bool in_sub = l < calls.sub_of.size() && calls.sub_of[l] != 0;
    if (!in_sub) last_main = l;
    prog.lex(l, b, quiet);
    const int code = flow_code(b);
    if (!code) {
      out += line_bytes(l);
      if (out.back() != '\n') out += eol;  // a last line without a line end, run inside
      continue;
    }
    if (b.block_delete) {
      // Whether it runs is the operator's switch; inline it would run always.
      diags.report(Severity::error, src, l, 1,
                   std::string(code == 980 ? "M98" : "M99") + " in a block-delete '/' block cannot be written inline");
      return {};
    }
    std::string words;
    for (const gcode::Word& w : b.words) {
      const bool ok = w.letter == 'N' || w.letter == 'P' || w.letter == 'L' || (w.letter == 'M' && w.code10() == code);
      if (!ok) {
        diags.report(Severity::error, src, l, w.begin - b.begin + 1,
                     std::string(code == 980 ? "M98" : "M99") +
                         " block with other words: it cannot be written inline (put them in a block of their own)");
        return {};
      }
      if (w.letter != 'N') words += (words.empty() ? "" : " ") + bytes.substr(w.begin, w.end - w.begin);
    }
    if (code == 980) {
      std::uint32_t o_line = 0;  // the subprogram this call runs: the line run next
      for (const auto& [sub, lines] : calls.calls)
        for (std::uint32_t c : lines)
          if (c == l) o_line = sub;
      // No subprogram behind the call: it repeats no time (L0).
      out += format_comment(words + " AT LINE " + std::to_string(l) + ": " +
                                (o_line ? calls.name_of(o_line, prog) + " WRITTEN INLINE BY DEFLEX" : "RUNS NO TIME"),
                            opt.dialect) +
             eol;
    } else if (!in_sub) {
      out += line_bytes(l);  // M99 in the main program: it ends there
    }
  }
  // The lines after the main program's last line run: the subprograms'
  // definitions and the tape end, as they are.
  if (last_main && last_main < prog.last_line()) out += bytes.substr(src.line_end_with_eol(last_main));
  return out;
}

}  // namespace deflex::writer
