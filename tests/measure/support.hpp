// Checks of the located errors the measurement readers throw.
#pragma once
#include <doctest/doctest.h>

#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::test {

// The text of the Error `f` throws, which must be of kind `kind`; "" when it throws none.
template <class F>
std::string error_text(F&& f, ErrorKind kind = ErrorKind::input) {
  try {
    f();
  } catch (const Error& e) {
    CHECK(static_cast<int>(e.kind()) == static_cast<int>(kind));
    return e.what();
  }
  return "";
}

inline std::vector<std::string> lines_of(const std::string& s) {
  std::vector<std::string> out;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// A compiler-style error: "where: error: ..." holding `words`, then the source
// line, then a caret under column `col` (source lines without tabs).
inline void check_located(const std::string& what, const std::string& where, const std::string& words,
                          const std::string& source, std::uint32_t col) {
  CAPTURE(what);
  const std::vector<std::string> l = lines_of(what);
  REQUIRE(l.size() == 3);
  CHECK(l[0].rfind(where + ": error: ", 0) == 0);
  CHECK(l[0].find(words) != std::string::npos);
  CHECK(l[1] == "  " + source);
  CHECK(l[2] == "  " + std::string(col - 1, ' ') + "^");
}

}  // namespace deflex::test
