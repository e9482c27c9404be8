// A program deflex generated, read back as any program is (src/job only).
#pragma once
#include <string>
#include <vector>

#include "deflex/interp/motion.hpp"
#include "deflex/job/setup.hpp"

namespace deflex::job {

// A self-check before anything is written: the program must interpret without
// a diagnostic and stay in the machine's travel; else Error(settings) saying
// `what` does not fit this machine, with the diagnostics.
std::vector<interp::Motion> read_back(const std::string& text, const std::string& name, const Setup& s,
                                      const std::string& what);

}  // namespace deflex::job
