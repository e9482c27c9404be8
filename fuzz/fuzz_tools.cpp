// Tool library YAML, and the beam model of every tool it accepts (a tool that
// passes the reader must not crash or hang the stiffness model).
#include "deflex/stiffness/beam.hpp"
#include "deflex/stiffness/tool.hpp"
#include "fuzz_support.hpp"

using namespace deflex;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  return fuzz::guarded([&] {
    const stiffness::ToolLibrary lib = stiffness::parse_tool_library(text, "fuzz.yaml");
    for (const auto& entry : lib.tools) stiffness::beam_compliance(entry.second, {}, true);
  });
}
