// Material library YAML, and writing each accepted entry back as YAML.
#include "deflex/force/material.hpp"
#include "fuzz_support.hpp"

using namespace deflex;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  return fuzz::guarded([&] {
    const force::MaterialLibrary lib = force::parse_material_library(text, "fuzz.yaml");
    for (const force::MaterialEntry& m : lib.entries) force::to_yaml(m);
  });
}
