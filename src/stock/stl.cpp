// Our own STL reader. OpenCASCADE 7.6's RWStl_Reader::ReadAscii reads past its
// line buffer on some malformed ASCII files (found by fuzz/fuzz_stl.cpp; case in
// tests/stock/test_stl.cpp); STL is simple enough to read here, strictly.
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/stock/build.hpp"

namespace deflex::stock {
namespace {

[[noreturn]] void bad(const std::string& path, const std::string& why) {
  throw Error(ErrorKind::io, path + ": cannot read as STL: " + why);
}

// A triangle whose corners are not all distinct has no area: dropped, as
// OpenCASCADE's node merging did.
void keep(const Triangle& t, std::vector<Triangle>& out) {
  if (t.p[0] != t.p[1] && t.p[1] != t.p[2] && t.p[0] != t.p[2]) out.push_back(t);
}

std::vector<Triangle> read_binary(const std::string& path, const std::string& bytes) {
  std::uint32_t n = 0;
  std::memcpy(&n, bytes.data() + 80, 4);  // little-endian, like every x86/ARM host deflex runs on
  std::vector<Triangle> out;
  out.reserve(n);
  for (std::uint32_t k = 0; k < n; ++k) {
    const char* rec = bytes.data() + 84 + 50 * static_cast<std::size_t>(k);
    float v[9];
    std::memcpy(v, rec + 12, sizeof v);  // after the normal
    Triangle t;
    for (int i = 0; i < 9; ++i) {
      if (!std::isfinite(v[i])) bad(path, "triangle " + std::to_string(k + 1) + " has a non-finite coordinate");
      t.p[i / 3][i % 3] = v[i];
    }
    keep(t, out);
  }
  return out;
}

bool same_word(const std::string& a, const char* b) {
  if (a.size() != std::strlen(b)) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) != b[i]) return false;
  return true;
}

// facet normal n n n / outer loop / vertex x y z (3x) / endloop / endfacet.
std::vector<Triangle> read_ascii(const std::string& path, const std::string& bytes) {
  std::istringstream in(bytes);
  std::vector<Triangle> out;
  Triangle t;
  int corners = -1;  // -1: outside a facet
  for (std::string w; in >> w;) {
    if (same_word(w, "facet")) {
      if (corners >= 0) bad(path, "'facet' inside a facet");
      corners = 0;
    } else if (same_word(w, "vertex")) {
      if (corners < 0 || corners == 3) bad(path, "'vertex' outside a facet or a fourth vertex");
      for (double& c : t.p[corners]) {
        std::string num;
        if (!(in >> num)) bad(path, "vertex with fewer than 3 numbers");
        char* end = nullptr;
        c = std::strtod(num.c_str(), &end);
        if (end != num.c_str() + num.size() || !std::isfinite(c)) bad(path, "bad number '" + num + "'");
      }
      ++corners;
    } else if (same_word(w, "endfacet")) {
      if (corners != 3) bad(path, "a facet without exactly 3 vertices");
      keep(t, out);
      corners = -1;
    }
  }
  if (corners >= 0) bad(path, "the file ends inside a facet");
  return out;
}

}  // namespace

std::vector<Triangle> read_stl(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw Error(ErrorKind::io, path + ": cannot open");
  const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  // Binary when the size matches the triangle count (many binary files also
  // begin with "solid"); otherwise ASCII, which must begin with "solid".
  if (bytes.size() >= 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, bytes.data() + 80, 4);
    if (bytes.size() == 84 + 50 * static_cast<std::uint64_t>(n)) return read_binary(path, bytes);
  }
  const std::size_t first = bytes.find_first_not_of(" \t\r\n");
  if (first == std::string::npos || bytes.compare(first, 5, "solid") != 0)
    bad(path, "neither binary (size 84 + 50 x count) nor ASCII ('solid' first)");
  return read_ascii(path, bytes);
}

}  // namespace deflex::stock
