// The force module reads its libraries with the shared YAML helpers.
#pragma once
#include "deflex/profile/yaml.hpp"

namespace deflex::force {
namespace yaml = deflex::yaml;
}
