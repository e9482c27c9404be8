// consumer PROGRAM: the number of motions of a program (the built-in Fanuc
// dialect, no machine), through the installed library's reader and interpreter.
#include <cstdio>
#include <iostream>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/gcode/program.hpp"
#include "deflex/interp/interpreter.hpp"
#include "deflex/profile/profile.hpp"

namespace {
struct Count : deflex::interp::MotionSink {
  unsigned long long n = 0;
  void motion(const deflex::interp::Motion&) override { ++n; }
};
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: consumer PROGRAM\n";
    return 2;
  }
  try {
    const deflex::gcode::Program prog(deflex::gcode::read_source(argv[1]));
    deflex::interp::Options opt;
    opt.dialect = deflex::profile::load_dialect("fanuc");
    deflex::Diagnostics diags(&std::cerr);
    Count count;
    deflex::interp::interpret(prog, opt, diags, count);
    if (diags.errors()) return 1;
    std::cout << count.n << "\n";
    return 0;
  } catch (const deflex::Error& e) {
    std::cerr << "consumer: " << e.what() << "\n";
    return 1;
  }
}
