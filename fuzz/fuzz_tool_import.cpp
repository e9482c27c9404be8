// Tool libraries from other software: the same bytes as a Fusion 360 JSON
// library and as a LinuxCNC tool table; whatever either accepts must give YAML
// that deflex's own reader loads (the importer checks every value it writes).
#include "deflex/stiffness/tool.hpp"
#include "deflex/stiffness/tool_import.hpp"
#include "fuzz_support.hpp"

using namespace deflex;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  fuzz::guarded([&] {
    const stiffness::ImportedLibrary imp = stiffness::import_fusion_json(text, "fuzz.json");
    try {
      (void)stiffness::parse_tool_library(imp.yaml, "fuzz.json.yaml");
    } catch (const Error&) {
      std::abort();  // the importer wrote a library its own reader refuses
    }
  });
  fuzz::guarded([&] {
    const stiffness::ImportedLibrary imp = stiffness::import_linuxcnc_tbl(text, "fuzz.tbl");
    try {
      (void)stiffness::parse_tool_library(imp.yaml, "fuzz.tbl.yaml");
    } catch (const Error&) {
      std::abort();
    }
  });
  return 0;
}
