// The probe logs of the two controls deflex's probe program runs on.
//
// LinuxCNC: the comment (PROBEOPEN file) opens the log, (PROBECLOSE) closes it
// (LinuxCNC docs/src/gcode/overview.adoc, "Probe Logging"). After each straight
// probe the interpreter reads the probed position (rs274ngc interp_internal.cc,
// set_probe_data) and emccanon.cc GET_EXTERNAL_PROBE_POSITION writes it with
// fprintf "%f %f %f %f %f %f %f %f %f\n": X Y Z A B C U V W, six decimals,
// one space between. The position is unoffset_and_unrotate_pos's: tool offset,
// G5x offset, XY rotation and G92 offset removed, so in the work coordinate
// system in effect; then to_prog: the program's units. It is written only when
// it differs from the last one written, so two probes tripping at exactly the
// same place give one line; a G38.3 that does not trip logs its programmed
// end point (docs/src/gcode/g-code.adoc, G38.x). Both show up when the log is
// joined with the probe program. The controlled point "should be at the
// center of the probe ball" (ibid.): the log gives the ball's centre.
//
// Fanuc DPRNT: characters are written as given, '*' as a space; #var[ab]
// prints the value with a integer and b decimal places, a decimal point when
// b > 0, a minus sign for a negative value, and pads the integer part with
// leading spaces (Haas 96-8000 Rev AC, "Formatted Output", which follows
// Fanuc's macro B). On Fanuc controls parameter 6001#1 (PRT) chooses whether
// leading zeros print as spaces or not at all (as we read Fanuc's Custom
// Macro chapter; the manual's text was not at hand), and a control may print
// the zeros. So a number may carry blanks before and after its sign, and
// leading zeros: all are read, nothing else is.
// POPEN and PCLOS write '%' lines around the output.
#include <algorithm>
#include <map>

#include "deflex/measure/samples.hpp"
#include "deflex/measure/text.hpp"

namespace deflex::measure {
namespace {

using detail::fail;

constexpr char kAxes[] = "XYZABCUVW";

// One line of a DPRNT log, read left to right with the column of each error.
class DprntLine {
 public:
  DprntLine(const SourceText& src, std::uint32_t line) : src_(src), line_(line), t_(src.line_text(line)) {}
  Sample read();

 private:
  void blanks() {
    while (i_ < t_.size() && detail::is_blank(t_[i_])) ++i_;
  }
  std::uint32_t col() const { return static_cast<std::uint32_t>(i_ + 1); }
  std::string_view digits() {
    const std::size_t b = i_;
    while (i_ < t_.size() && t_[i_] >= '0' && t_[i_] <= '9') ++i_;
    return t_.substr(b, i_ - b);
  }
  [[noreturn]] void bad(const std::string& why) { fail(src_, line_, col(), why); }
  double coordinate(char axis);

  const SourceText& src_;
  std::uint32_t line_;
  std::string_view t_;
  std::size_t i_ = 0;
};

double DprntLine::coordinate(char axis) {
  blanks();
  if (i_ == t_.size()) bad(std::string(1, axis) + " coordinate missing (expected PT<id> X<x> Y<y> Z<z>)");
  if (t_[i_] != axis) bad(std::string("expected ") + axis + ", found " + detail::quoted(t_.substr(i_, 1)));
  ++i_;
  blanks();
  const std::uint32_t at = col();
  std::string n;  // sign and digits, the blanks of the print format left out
  if (i_ < t_.size() && (t_[i_] == '-' || t_[i_] == '+')) {
    if (t_[i_++] == '-') n += '-';
    blanks();
  }
  const std::string_view whole = digits();
  n += whole;
  std::string_view frac;
  if (i_ < t_.size() && t_[i_] == '.') {
    ++i_;
    frac = digits();
    n += '.';
    n += frac;
  }
  if (whole.empty() && frac.empty()) fail(src_, line_, at, std::string("no number after ") + axis);
  const auto v = detail::number(n);
  if (!v) fail(src_, line_, at, std::string(1, axis) + ": " + detail::not_a_number(n));
  return *v;
}

Sample DprntLine::read() {
  blanks();
  if (t_.substr(i_, 2) != "PT") bad("expected a line PT<id> X<x> Y<y> Z<z> (DPRNT of deflex's probe program)");
  i_ += 2;
  blanks();
  const std::uint32_t at = col();
  const auto id = detail::positive_int(digits());
  if (!id) fail(src_, line_, at, "expected the probe point's id (a whole number >= 1) after PT");
  Sample s;
  s.id = *id;
  s.line = line_;
  for (int a = 0; a < 3; ++a) s.p_mm[a] = coordinate(kAxes[a]);
  blanks();
  if (i_ != t_.size()) bad("unexpected " + detail::quoted(t_.substr(i_)) + " after the Z coordinate");
  return s;
}

}  // namespace

std::vector<Sample> read_linuxcnc_probe_log(const std::string& text, const std::string& file) {
  const SourceText src(file, text);
  std::vector<Sample> out;
  for (std::uint32_t l = 1; l <= src.line_count(); ++l) {
    const std::vector<detail::Field> w = detail::words(src.line_text(l));
    if (w.empty()) continue;
    if (w.size() != 9) {
      const std::uint32_t col = w.size() > 9 ? w[9].col : static_cast<std::uint32_t>(src.line_text(l).size() + 1);
      fail(src, l, col, "expected 9 numbers (X Y Z A B C U V W, as LinuxCNC's PROBEOPEN log writes), found " +
                            std::to_string(w.size()));
    }
    Sample s;
    s.line = l;
    for (int a = 0; a < 9; ++a) {
      const auto v = detail::number(w[a].text);
      if (!v) fail(src, l, w[a].col, std::string(1, kAxes[a]) + ": " + detail::not_a_number(w[a].text));
      if (a < 3) s.p_mm[a] = *v;
    }
    out.push_back(s);
  }
  if (out.empty())
    fail(src, std::max<std::uint32_t>(1, src.last_line()), 1,
         "no probe positions in the log (did a probe move trip between (PROBEOPEN) and (PROBECLOSE)?)");
  return out;
}

std::vector<Sample> read_dprnt(const std::string& text, const std::string& file) {
  const SourceText src(file, text);
  std::vector<Sample> out;
  std::map<int, std::uint32_t> id_line;
  for (std::uint32_t l = 1; l <= src.line_count(); ++l) {
    const std::string_view t = detail::trim(src.line_text(l));
    if (t.empty() || t == "%") continue;
    out.push_back(DprntLine(src, l).read());
    if (auto [it, fresh] = id_line.emplace(out.back().id, l); !fresh)
      fail(src, l, static_cast<std::uint32_t>(src.line_text(l).find("PT") + 1),
           "point PT" + std::to_string(it->first) + " printed twice (first on line " + std::to_string(it->second) + ")");
  }
  if (out.empty())
    fail(src, std::max<std::uint32_t>(1, src.last_line()), 1,
         "no probe points in the DPRNT output (expected lines PT<id> X<x> Y<y> Z<z>)");
  return out;
}

}  // namespace deflex::measure
