// PieceCutter (compensate/pieces.hpp): the pieces make the program, line for
// line and motion for motion, and each ends where nothing looks past it.
#include <doctest/doctest.h>

#include "../support.hpp"
#include "deflex/compensate/pieces.hpp"

using namespace deflex;

TEST_SUITE("compensate") {
  TEST_CASE("program pieces: the lines and motions of the whole, cut before a plain G0/G1 in the same frame") {
    const char* path = "samples/programs/freeform.nc";
    const std::string bytes = test::read_file(path);
    const test::Interpreted whole = test::interpret_text(bytes);
    REQUIRE(whole.motions.size() > 100);
    interp::Options o;
    o.dialect = profile::load_dialect("fanuc");
    // Read piece by piece as asked, and read ahead on a thread of its own.
    for (const bool ahead : {false, true})
    for (std::size_t per : {1u, 13u, 200u}) {
      CAPTURE(ahead);
      CAPTURE(per);
      compensate::PieceCutter cut(path, 17, o, per, {}, ahead);
      std::string joined;
      std::vector<interp::Motion> motions;
      std::uint32_t next = 1;
      int pieces = 0;
      while (auto p = cut.next()) {
        ++pieces;
        CHECK(p->first_line == next);
        CHECK(p->first_motion == motions.size());
        // Its own lines numbered from 1; the context around them numbered in the file.
        CHECK(p->own.line_count() == p->last_line - p->first_line + 1);
        CHECK(p->text.first_line() == (p->first_line > 200 ? p->first_line - 200 : 1));
        bool same = true;
        for (std::uint32_t l = p->first_line; l <= p->last_line; ++l)
          same = same && p->text.source().line_text(l) == p->own.source().line_text(l - p->first_line + 1);
        CHECK(same);
        joined += p->own.bytes();
        bool inside = true;
        for (const interp::Motion& m : p->motions) inside = inside && m.line >= p->first_line && m.line <= p->last_line;
        CHECK(inside);
        // Where it was cut: the next motion is a plain G0/G1, the first of its line, same frame.
        if (!p->motions.empty() && motions.size() + p->motions.size() < whole.motions.size()) {
          CHECK(p->motions.size() >= per);
          const interp::Motion& after = whole.motions[motions.size() + p->motions.size()];
          CHECK(after.plain);
          CHECK((after.kind == interp::MotionKind::linear || after.kind == interp::MotionKind::rapid));
          CHECK(after.line == p->last_line + 1);
          CHECK(after.work_offset_mm == p->motions.back().work_offset_mm);
        }
        motions.insert(motions.end(), p->motions.begin(), p->motions.end());
        next = p->last_line + 1;
      }
      CHECK(joined == bytes);
      CHECK(pieces > 1);
      REQUIRE(motions.size() == whole.motions.size());
      bool same = true;
      for (std::size_t i = 0; i < motions.size(); ++i)
        same = same && motions[i].line == whole.motions[i].line && motions[i].end_mm == whole.motions[i].end_mm;
      CHECK(same);
    }
  }
}
