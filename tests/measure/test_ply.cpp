// measure::parse_ply: point clouds in PLY, ascii and binary.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "deflex/measure/samples.hpp"
#include "support.hpp"

using namespace deflex;
using deflex::test::check_located;
using deflex::test::error_text;

namespace {

std::string ply_error(const std::string& bytes) {
  return error_text([&] { measure::parse_ply(bytes, "c.ply"); });
}

// Bytes of a value in the given order.
template <class T>
std::string bytes_of(T v, bool big) {
  std::string b(sizeof v, '\0');
  std::memcpy(b.data(), &v, sizeof v);
  if (big != (std::endian::native == std::endian::big)) std::reverse(b.begin(), b.end());
  return b;
}

// A face element before the vertices (its list read past), vertices of three
// types and a list property of their own.
const char* kBinaryHeader =
    "element face 1\nproperty list uchar int vertex_indices\n"
    "element vertex 2\nproperty double x\nproperty short y\nproperty float z\nproperty list int uchar extra\nend_header\n";

std::string binary_ply(bool big, float z1 = 0.0f) {
  std::string b = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") + " 1.0\n" + kBinaryHeader;
  b += bytes_of<std::uint8_t>(3, big) + bytes_of<std::int32_t>(0, big) + bytes_of<std::int32_t>(1, big) + bytes_of<std::int32_t>(1, big);
  b += bytes_of(1.5, big) + bytes_of<std::int16_t>(-2, big) + bytes_of(3.25f, big) + bytes_of<std::int32_t>(2, big) + "\x01\x02";
  b += bytes_of(-1.0, big) + bytes_of<std::int16_t>(7, big) + bytes_of(z1, big) + bytes_of<std::int32_t>(0, big);
  return b;
}

const std::string kAscii =
    "ply\r\nformat ascii 1.0\r\ncomment scanned\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\n"
    "property float z\r\nproperty uchar red\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
    "0 0 0 255\r\n1.5 0 -0.25 0\r\n0 1 1e-3 7\r\n3 0 1 2\r\n";

}  // namespace

TEST_SUITE("measure") {

TEST_CASE("PLY ascii: the vertices' x y z, other properties and the faces' lists read past") {
  const auto s = measure::parse_ply(kAscii, "c.ply");
  REQUIRE(s.size() == 3);
  CHECK(s[1].p_mm == Eigen::Vector3d(1.5, 0, -0.25));
  CHECK(s[2].p_mm == Eigen::Vector3d(0, 1, 1e-3));
  CHECK(s[2].line == 14);
  CHECK(s[2].id == -1);
}

TEST_CASE("PLY binary, both byte orders: mixed types, a face element first, lists skipped") {
  for (bool big : {false, true}) {
    CAPTURE(big);
    const auto s = measure::parse_ply(binary_ply(big), "c.ply");
    REQUIRE(s.size() == 2);
    CHECK(s[0].p_mm == Eigen::Vector3d(1.5, -2, 3.25));
    CHECK(s[1].p_mm == Eigen::Vector3d(-1, 7, 0));
    CHECK(s[0].line == 0);
  }
}

TEST_CASE("PLY binary: a truncated file, a header lying about the count, NaN name element and byte") {
  const std::string b = binary_ply(false);
  const std::size_t data = b.find("end_header\n") + 11;
  const std::size_t v1 = data + 13 + 8 + 2 + 4 + 4 + 2;  // the second vertex's first byte
  CHECK(ply_error(b.substr(0, b.size() - 6)) ==
        "c.ply: error: vertex 1 at byte " + std::to_string(v1) + ": the file ends inside its z (the header says 'element vertex 2')");
  std::string more = b;
  more.replace(more.find("vertex 2"), 8, "vertex 3");
  CHECK(ply_error(more) == "c.ply: error: vertex 2 at byte " + std::to_string(b.size()) +
                               ": the file ends inside its x (the header says 'element vertex 3')");
  std::string fewer = b;
  fewer.replace(fewer.find("vertex 2"), 8, "vertex 1");
  CHECK(ply_error(fewer) == "c.ply: error: 18 bytes after the last element at byte " + std::to_string(v1) +
                                ": the header's element counts do not match the data");
  CHECK(ply_error(binary_ply(false, std::numeric_limits<float>::quiet_NaN())) ==
        "c.ply: error: vertex 1 at byte " + std::to_string(v1) + ": z is not a finite number");
}

TEST_CASE("PLY ascii: a header lying about the count, NaN, a missing value, junk: located errors") {
  std::string more = kAscii;
  more.replace(more.find("vertex 3"), 8, "vertex 5");
  // The face's line is read as vertex 3; then the file ends.
  check_located(ply_error(more), "c.ply:15:1", "the file ends before vertex 4 (the header says 'element vertex 5')",
                "3 0 1 2", 1);
  std::string fewer = kAscii;
  fewer.replace(fewer.find("vertex 3"), 8, "vertex 2");
  // The third vertex's line is read as the face: a list of 0, then three values too many.
  check_located(ply_error(fewer), "c.ply:14:3", "face 0: more values than its properties", "0 1 1e-3 7", 3);
  std::string face_less = kAscii;
  face_less.replace(face_less.find("element face 1"), 14, "element face 0");
  check_located(ply_error(face_less), "c.ply:15:1", "data after the last element", "3 0 1 2", 1);
  std::string nan = kAscii;
  nan.replace(nan.find("1.5 0 -0.25"), 11, "1.5 nan -0.25");
  check_located(ply_error(nan), "c.ply:13:5", "vertex 1: y: 'nan' is not a finite number", "1.5 nan -0.25 0", 5);
  std::string missing = kAscii;
  missing.replace(missing.find("1.5 0 -0.25 0"), 13, "1.5 0 -0.25");
  check_located(ply_error(missing), "c.ply:13:12", "vertex 1: no value for red", "1.5 0 -0.25", 12);
  std::string junk = kAscii;
  junk.replace(junk.find("3 0 1 2"), 7, "3 0 1 2 9");
  check_located(ply_error(junk), "c.ply:15:9", "face 0: more values than its properties", "3 0 1 2 9", 9);
}

TEST_CASE("PLY: an empty file, another file, a header without x y z or end_header") {
  check_located(ply_error(""), "c.ply:1:1", "the file is empty", "", 1);
  check_located(ply_error("solid x\n"), "c.ply:1:1", "not a PLY file", "solid x", 1);
  check_located(ply_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n"),
                "c.ply:6:1", "the vertex element has no number property z", "end_header", 1);
  check_located(ply_error("ply\nformat ascii 1.0\nelement vertex 1\n"), "c.ply:3:1", "no end_header line", "element vertex 1", 1);
  check_located(ply_error("ply\nformat ascii 1.0\nelement vertex -1\nend_header\n"), "c.ply:3:16", "the count '-1' is not a whole number",
                "element vertex -1", 16);
  check_located(ply_error("ply\nformat ascii 1.0\nelement vertex 1\nproperty list float int x\nend_header\n"), "c.ply:4:15",
                "a list's count type must be a PLY integer type", "property list float int x", 15);
}

}  // TEST_SUITE
