// The feed limit on a program whose cutting blocks carry their own F word
// (the side-wall sample): the F words are rewritten to the planned feeds and
// the safety check accepts them. (A compensation that kept the lowered feed
// in the motions it wrote down left the writer nothing to change, and the
// safety check rightly refused the output.)
#include <doctest/doctest.h>

#include <cstdlib>
#include <regex>
#include <sstream>

#include "support.hpp"

using namespace deflex;

TEST_SUITE("job") {
  TEST_CASE("a feed limit rewrites an F word of the block itself, with and without compensation") {
    for (const double gain : {0.0, 1.0}) {
      CAPTURE(gain);
      job::Settings s;
      s.program = "samples/programs/side_wall.nc";
      s.stock = "box:0,-40,-30,100,0,0";
      s.material.material = "Al6082-T4";
      s.feed_limit_N = 300;
      s.gain = gain;
      test::Streams streams;
      job::Io& io = streams.io;
      job::Run run = job::open(s, job::Purpose::compensate, io);
      const job::CompensateResult r = job::compensate(run, streams.out, io);
      CAPTURE(streams.err.str());
      CHECK(r.result.feed_lowered_lines == std::vector<std::uint32_t>{16, 20});
      CHECK(streams.err.str().find("feed lowered on 2 blocks to keep the peak force under 300 N and the spindle's power and torque "
                                  "within its S1 rating (lines 16, 20)") !=
            std::string::npos);
      // The two wall passes: programmed F2546.4, written lower (0.1 mm/min steps, down).
      const std::string text = streams.out.str();
      std::smatch m;
      REQUIRE(std::regex_search(text, m, std::regex("N22 X[^\\n]* F([0-9.]+)")));
      const double f = std::atof(m[1].str().c_str());
      CHECK(f < 2546.4);
      CHECK(f > 100);
      // Nothing but coordinates and F changed: the block before them stays.
      CHECK(text.find("N20 G01 Z-12. F1000.") != std::string::npos);
      CHECK(r.summary["feed_lowered_blocks"] == 2);
      CHECK(r.time_compensated.program.total_s > r.time_as_written.program.total_s);  // slower where lowered
    }
  }
}
