// Shared by the fuzz targets: what counts as a finding, and temporary files for
// the readers that take a path.
#pragma once
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>
#include <string>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::fuzz {

// Runs one input. A deflex::Error is the reader's answer to bad input (a
// diagnostic and an exit code), so it passes; any other exception would reach
// the CLI as "internal error" (exit 70) and is a finding: abort so libFuzzer
// keeps the input.
template <class F>
int guarded(F&& f) {
  try {
    f();
  } catch (const Error&) {
  } catch (const std::bad_alloc&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz: exception that is not deflex::Error: %s\n", e.what());
    std::abort();
  }
  return 0;
}

// Writes the input to a file of this process (readers that only take a path).
inline std::string temp_file(const char* ext, const std::uint8_t* data, std::size_t size) {
  const std::string path = "/tmp/deflex-fuzz-" + std::to_string(getpid()) + ext;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
}

}  // namespace deflex::fuzz
