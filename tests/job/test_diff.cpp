// job::diff places an inserted split block where it belongs, among lines
// whose skeletons are all equal. What `deflex diff` prints of it is in
// tests/cli/test_corpus.cpp.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "deflex/job/diff.hpp"
#include "support.hpp"

using namespace deflex;

TEST_SUITE("job") {
  TEST_CASE("diff: an inserted split block in a program of skeleton-equal lines is placed where it belongs") {
    test::TempDir dir("diff");
    test::write_file(dir / "a.nc", test::kDiffSplitA);
    test::write_file(dir / "b.nc", test::kDiffSplitB);
    job::DiffSettings ds;
    ds.a = dir / "a.nc";
    ds.b = dir / "b.nc";
    ds.read.dialect = "fanuc";
    test::Streams st;
    const job::DiffResult r = job::diff(ds, st.io);
    CHECK(r.only_coordinates());
    REQUIRE(r.splits.size() == 1);
    CHECK(r.splits[0].line_b == 4);
    CHECK(r.splits[0].line_a == 4);
    CHECK(r.splits[0].distance_mm < 0.5e-6);
    const job::DiffChange* moved = nullptr;
    for (const job::DiffChange& c : r.changes)
      if (c.line_a == 4) moved = &c;
    REQUIRE(moved != nullptr);
    CHECK(moved->line_b == 5);
    CHECK(std::fabs(moved->d_mm[0]) < 0.5e-6);
    CHECK(std::fabs(moved->d_mm[1] - 0.01) < 0.5e-6);
    CHECK(std::fabs(moved->d_mm[2]) < 0.5e-6);
    CHECK(std::fabs(moved->distance_mm - 0.01) < 0.5e-6);
    CHECK(std::fabs(r.max_mm - 0.01) < 0.5e-6);
  }
}
