// Machine profile YAML: the profile reader and the stiffness section's reader.
// The same bytes also go through the dialect and config readers, the other
// YAML files a user hands deflex (same YAML layer, same error paths).
#include "deflex/profile/profile.hpp"
#include "deflex/stiffness/machine.hpp"
#include "fuzz_support.hpp"

using namespace deflex;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::temp_file(".yaml", data, size);
  fuzz::guarded([&] { profile::load_machine(path); });
  fuzz::guarded([&] { profile::load_dialect(path); });
  fuzz::guarded([&] { profile::load_config(path); });
  return fuzz::guarded([&] { stiffness::load_machine_stiffness(path); });
}
