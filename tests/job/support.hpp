// Helpers of the job API's tests: string streams for a job::Io, a run
// opened and compensated or simulated in one call, and a program's motions
// as `deflex path` prints them.
#pragma once
#include <optional>
#include <sstream>
#include <string>

#include "../support.hpp"
#include "deflex/job/job.hpp"
#include "deflex/job/program.hpp"
#include "deflex/report/text_out.hpp"

namespace deflex::test {

// A job::Io on string streams; `stdin_text` is the program of "-".
struct Streams {
  std::istringstream in;
  std::ostringstream out, err;
  job::Io io{in, out, err};
  explicit Streams(const std::string& stdin_text = "") : in(stdin_text) {}
};

// What a run gave: its messages, the program it wrote (to the output stream),
// its result, or the Error that stopped it (kind and message).
template <class Result>
struct Outcome {
  std::string out, err;
  std::optional<Result> result;
  std::optional<ErrorKind> error;
  std::string what;
  bool ok() const { return result.has_value(); }
};

// Opens `s` for `purpose` and runs `go(run, streams)`, catching a deflex::Error.
template <class Go>
auto run_job(const job::Settings& s, job::Purpose purpose, Go go, const std::string& stdin_text = "") {
  Streams st(stdin_text);
  Outcome<decltype(go(std::declval<job::Run&>(), st))> o;
  try {
    job::Run run = job::open(s, purpose, st.io);
    o.result = go(run, st);
  } catch (const Error& e) {
    o.error = e.kind();
    o.what = e.what();
  }
  o.out = st.out.str();
  o.err = st.err.str();
  return o;
}

// job::compensate of `s`, its program to the output stream (or to Settings::output).
inline Outcome<job::CompensateResult> compensate_job(const job::Settings& s, const std::string& stdin_text = "") {
  return run_job(
      s, job::Purpose::compensate, [](job::Run& r, Streams& st) { return job::compensate(r, st.out, st.io); },
      stdin_text);
}

// job::simulate of `s`.
inline Outcome<job::SimulateResult> simulate_job(const job::Settings& s, const std::string& stdin_text = "") {
  return run_job(
      s, job::Purpose::simulate, [](job::Run& r, Streams& st) { return job::simulate(r, st.io); }, stdin_text);
}

// The stock of samples/programs/pocket_finish.nc beside its box: its two
// holes pre-drilled by a flat D20 (tests/data/pocket_predrill.nc). T5 drills
// them 12 mm deep with flutes of 10 mm: on the bare box its shank runs 2 mm
// into the bore, an error (compensate/collision.hpp).
inline std::vector<job::EarlierOp> pocket_predrilled() { return {{"tests/data/pocket_predrill.nc", ""}}; }

// The sample side wall with its first pass (line 16) replaced by `pass`.
inline std::string side_wall_with(const TempDir& dir, const std::string& name, const std::string& pass) {
  return edited_copy(dir, "samples/programs/side_wall.nc", name, "N22 X110. F2546.4\n", pass);
}

// Compensates `in` on the side wall's stock into the file `out`.
inline Outcome<job::CompensateResult> compensate_side_wall(const std::string& in, const std::string& out,
                                                      const std::string& report_dir = "") {
  job::Settings s;
  s.program = in;
  s.stock = "box:0,-40,-30,100,0,0";
  s.output = out;
  s.report_dir = report_dir;
  return compensate_job(s);
}

// A compensation's summary but for what names the program or its lines
// (the name and the warnings at their lines): two programs that compensate
// alike, one edited from the other, have the same.
inline std::string summary_but_lines(const job::CompensateResult& r) {
  report::Json js = r.summary;
  js.erase("file");
  js.erase("warnings");
  return report::document(js);
}

// `deflex path [--centre]` of a program file through job::path: one line per
// motion, KIND X Y Z (6 decimals), read with the config's machine and
// dialect (or `dialect`); the programmed contour's points under G41/G42
// unless `centre`. A program with an error fails the test.
inline std::string path_text(const std::string& file, bool centre = false, const std::string& dialect = "") {
  job::PathSettings ps;
  ps.program = file;
  ps.read.dialect = dialect;
  std::ostringstream text;
  struct Print : interp::MotionSink {
    report::TextOut* out;
    bool centre;
    void motion(const interp::Motion& m) override {
      if (!centre && m.corner) return;  // a corner piece has no programmed point
      *out << interp::to_string(m.kind);
      for (double v : centre || !m.comp ? m.end_mm : m.contour_end_mm) {
        *out << ' ';
        out->fixed(v, 6);
      }
      *out << '\n';
    }
  } print;
  Streams st;
  job::PathResult r;
  {
    report::TextOut out(text);
    print.out = &out;
    print.centre = centre;
    r = job::path(ps, print, st.io);
  }
  INFO(file << ": " << st.err.str());
  CHECK(r.errors == 0);
  CHECK(r.handed);
  return text.str();
}

}  // namespace deflex::test
