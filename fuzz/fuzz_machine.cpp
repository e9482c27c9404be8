// Machine profile YAML: the profile reader and the stiffness section's reader.
#include "deflex/profile/profile.hpp"
#include "deflex/stiffness/machine.hpp"
#include "fuzz_support.hpp"

using namespace deflex;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::temp_file(".yaml", data, size);
  fuzz::guarded([&] { profile::load_machine(path); });
  return fuzz::guarded([&] { stiffness::load_machine_stiffness(path); });
}
