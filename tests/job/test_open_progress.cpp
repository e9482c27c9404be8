// job::open() under an observer: the stages it goes through with their
// fractions, and a cancellation while the program is being checked; a job
// with no program.
#include <doctest/doctest.h>

#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "support.hpp"

using namespace deflex;

namespace {

struct Stages : job::Observer {
  std::vector<std::pair<std::string, double>> seen;
  std::string cancel_in;  // cancel at the first step of this stage
  void progress(const std::string& stage, double f) override { seen.emplace_back(stage, f); }
  bool cancelled() override { return !cancel_in.empty() && !seen.empty() && seen.back().first == cancel_in; }
};

job::Settings wall() {
  job::Settings s;
  s.program = "tests/golden/wall.nc";
  s.stock = "box:0,0,-20,100,20,0";
  return s;
}

// The stages in the order first seen, each with its fractions.
std::vector<std::pair<std::string, std::vector<double>>> by_stage(const Stages& o) {
  std::vector<std::pair<std::string, std::vector<double>>> v;
  for (const auto& [stage, f] : o.seen) {
    if (v.empty() || v.back().first != stage) v.push_back({stage, {}});
    v.back().second.push_back(f);
  }
  return v;
}

}  // namespace

TEST_SUITE("job") {
  TEST_CASE("open() reports checking, then the stock; in pieces, checking by the bytes of its three passes") {
    for (const char* piece_lines : {"0", "4"}) {  // whole, then pieces of 4 lines
      CAPTURE(piece_lines);
      ::setenv("DEFLEX_CHUNK_LINES", piece_lines, 1);
      test::Streams streams;
      job::Io& io = streams.io;
      Stages o;
      const job::Run run = job::open(wall(), job::Purpose::compensate, io, &o);
      ::unsetenv("DEFLEX_CHUNK_LINES");
      CHECK((run.pieces != nullptr) == (std::string(piece_lines) != "0"));
      const auto stages = by_stage(o);
      REQUIRE(stages.size() == 2);
      CHECK(stages[0].first == "checking");
      CHECK(stages[1].first == "stock");
      for (const auto& one : stages) {
        CAPTURE(one.first);  // not a structured binding: CAPTURE's lambda takes it (clang 14)
        const std::vector<double>& f = one.second;
        CHECK(f.front() == 0.0);
        CHECK(f.back() == 1.0);
        for (std::size_t i = 1; i < f.size(); ++i) CHECK(f[i] >= f[i - 1]);
      }
      // In pieces: a step per piece and pass, the file's 3 passes ending at 1.
      if (run.pieces) CHECK(stages[0].second.size() > 6);
    }
  }

  TEST_CASE("an observer that cancels while the program is checked stops open() there") {
    test::Streams streams;
    job::Io& io = streams.io;
    Stages o;
    o.cancel_in = "checking";
    CHECK_THROWS_AS((void)job::open(wall(), job::Purpose::compensate, io, &o), job::Cancelled);
    for (const auto& [stage, f] : o.seen) CHECK(stage == "checking");  // the stock never built
  }

  TEST_CASE("a job with no program is a settings error that names the setting") {
    test::Streams streams;
    job::Io& io = streams.io;
    job::Settings s = wall();
    s.program.clear();
    try {
      (void)job::open(s, job::Purpose::simulate, io);
      FAIL("open() took a job without a program");
    } catch (const Error& e) {
      CHECK(e.kind() == ErrorKind::settings);
      CHECK(e.settings() == std::vector<std::string>{"program"});
    }
  }
}
