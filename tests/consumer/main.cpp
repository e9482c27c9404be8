// consumer PROGRAM STOCK PART OUT SUMMARY: compensates PROGRAM on STOCK with
// the part model PART through the installed library's job API, as
// `deflex compensate PROGRAM --stock STOCK --part PART -o OUT --report DIR`
// does, and writes the run's summary.json to SUMMARY. The consumer test
// (cmake/consumer_test.cmake) compares both files with the command line's.
#include <fstream>
#include <iostream>
#include <sstream>

#include "deflex/job/job.hpp"

int main(int argc, char** argv) {
  if (argc != 6) {
    std::cerr << "usage: consumer PROGRAM STOCK PART OUT SUMMARY\n";
    return 2;
  }
  try {
    deflex::job::Settings s;
    s.program = argv[1];
    s.stock = argv[2];
    s.part.part = argv[3];
    s.output = argv[4];
    std::istringstream in;
    deflex::job::Io io{in, std::cout, std::cerr};
    deflex::job::Run run = deflex::job::open(s, deflex::job::Purpose::compensate, io);
    const deflex::job::CompensateResult r = deflex::job::compensate(run, std::cout, io);
    std::ofstream(argv[5]) << deflex::report::document(r.summary);
    std::cout << r.result.compensated_points << " points compensated\n";
    return 0;
  } catch (const deflex::Error& e) {
    std::cerr << "consumer: " << e.what() << "\n";
    return 1;
  }
}
