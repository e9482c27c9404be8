// --feed-limit through the command line on a program whose cutting blocks
// carry their own F word (the side-wall sample): the F words are rewritten to
// the planned feeds and the safety check accepts them. The compensation kept
// the lowered feed in the motions it wrote down, so the writer saw nothing to
// change and the safety check (rightly) refused the output.
#include <doctest/doctest.h>

#include <cstdlib>
#include <regex>

#include "../support.hpp"

using namespace deflex;

TEST_SUITE("cli") {
  TEST_CASE("--feed-limit rewrites an F word of the block itself, with and without compensation") {
    for (const char* gain : {"0", "1"}) {
      CAPTURE(gain);
      const auto r = test::run_cli({"compensate", "samples/programs/side_wall.nc", "--stock", "box:0,-40,-30,100,0,0",
                                    "--material", "Al6082-T4", "--feed-limit", "300", "--gain", gain});
      CAPTURE(r.err);
      REQUIRE(r.rc == 0);
      CHECK(r.err.find("feed lowered on 2 blocks to keep the peak force under 300 N (lines 16, 20)") != std::string::npos);
      // The two wall passes: programmed F2546.4, written lower (0.1 mm/min steps, down).
      std::smatch m;
      REQUIRE(std::regex_search(r.out, m, std::regex("N22 X[^\\n]* F([0-9.]+)")));
      const double f = std::atof(m[1].str().c_str());
      CHECK(f < 2546.4);
      CHECK(f > 100);
      // Nothing but coordinates and F changed: diff pairs every block.
      CHECK(r.out.find("N20 G01 Z-12. F1000.") != std::string::npos);
    }
  }
}
