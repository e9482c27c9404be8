// deflex's STL reader (src/stock/stl.cpp): binary and ASCII give the same
// triangles; malformed files are an I/O error, never a read past a buffer.
#include <doctest/doctest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <unistd.h>
#include <string>

#include "../support.hpp"
#include "deflex/stock/build.hpp"

using namespace deflex;

namespace {
const char* kTetAscii =
    "solid tet\n"
    " facet normal 0 0 -1\n  outer loop\n   vertex 0 0 0\n   vertex 10 0 0\n   vertex 0 10 0\n  endloop\n endfacet\n"
    " facet normal 0 -1 0\n  outer loop\n   vertex 0 0 0\n   vertex 10 0 0\n   vertex 0 0 5\n  endloop\n endfacet\n"
    "endsolid tet\n";

std::string binary_of(const float (*tris)[9], std::uint32_t n) {
  std::string b(80, '\0');
  b.append(reinterpret_cast<const char*>(&n), 4);
  for (std::uint32_t k = 0; k < n; ++k) {
    const float normal[3] = {0, 0, 0};
    b.append(reinterpret_cast<const char*>(normal), 12);
    b.append(reinterpret_cast<const char*>(tris[k]), 36);
    b.append(2, '\0');
  }
  return b;
}

// A file of this process in the temporary directory.
std::string tmp(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("deflex-" + std::to_string(::getpid()) + "-" + name)).string();
}
std::string temp(const std::string& name, const std::string& bytes) {
  test::write_file(tmp(name), bytes);
  return tmp(name);
}
}  // namespace

TEST_SUITE("stock") {

TEST_CASE("STL reader: ASCII and binary give the same triangles") {
  const float tris[2][9] = {{0, 0, 0, 10, 0, 0, 0, 10, 0}, {0, 0, 0, 10, 0, 0, 0, 0, 5}};
  const auto a = stock::read_stl(temp("build-stl-a.stl", kTetAscii));
  const auto b = stock::read_stl(temp("build-stl-b.stl", binary_of(tris, 2)));
  REQUIRE(a.size() == 2);
  REQUIRE(b.size() == 2);
  for (int k = 0; k < 2; ++k) CHECK(a[k].p == b[k].p);
  CHECK(a[1].p[2][2] == 5.0);
  std::remove(tmp("build-stl-a.stl").c_str());
  std::remove(tmp("build-stl-b.stl").c_str());
}

TEST_CASE("STL reader: malformed files are I/O errors (fuzz finding: OCCT read past its line buffer)") {
  const std::string bad[] = {
      test::read_file("tests/stock/data/fuzz_ascii_overread.stl"),  // libFuzzer's crash input
      "solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n endloop\n endfacet\n",
      "solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 nan\n vertex 1 0 0\n vertex 0 1 0\n endloop\n endfacet\n",
      "solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n vertex 0 1",
      "not an stl",
      ""};
  for (const std::string& text : bad) {
    try {
      stock::read_stl(temp("build-stl-bad.stl", text));
      FAIL("no error for: " << text.substr(0, 60));
    } catch (const Error& e) {
      CHECK(e.kind() == ErrorKind::io);
      CHECK(std::string(e.what()).find("cannot read as STL") != std::string::npos);
    }
  }
  // A binary file whose count disagrees with its size is not binary, and not ASCII.
  const float one[1][9] = {{0, 0, 0, 1, 0, 0, 0, 1, 0}};
  std::string b = binary_of(one, 1);
  b.pop_back();
  CHECK_THROWS_AS(stock::read_stl(temp("build-stl-bad.stl", b)), Error);
  std::remove(tmp("build-stl-bad.stl").c_str());
}

TEST_CASE("STL reader: triangles without area are dropped") {
  const float tris[2][9] = {{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 0, 0, 0, 0, 0, 1, 0}};
  CHECK(stock::read_stl(temp("build-stl-d.stl", binary_of(tris, 2))).size() == 1);
  std::remove(tmp("build-stl-d.stl").c_str());
}

TEST_CASE("Z-map of an STL 1e36 mm long and 1e-12 mm wide: a config error (fuzz finding: UB converting the cell count)") {
  const auto tris = stock::read_stl("tests/stock/data/fuzz_thin_huge.stl");
  REQUIRE(!tris.empty());
  try {
    stock::zmap_from_triangles(tris, 0.5);
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(e.kind() == ErrorKind::config);
  }
  CHECK(stock::grid_covering(0, 0, 1, 1e-12, 0.05).ny == 1);
  CHECK_THROWS_AS(stock::grid_covering(0, 0, 1e36, 1e-12, 0.05), Error);
}

}  // TEST_SUITE
