// Text held until it may go out (report/held_text.hpp): what comes out is
// what went in, in order, whether it stayed in memory or went partly to disk.
#include <doctest/doctest.h>

#include <sstream>
#include <string>

#include "deflex/report/held_text.hpp"
#include "deflex/report/text_out.hpp"

using namespace deflex;

TEST_SUITE("report") {
  TEST_CASE("held text: the bytes taken come out in order, from memory and from the spill file") {
    for (std::size_t memory_bytes : {std::size_t{0}, std::size_t{5000}, report::kHeldMemoryBytes}) {
      CAPTURE(memory_bytes);
      report::HeldText held(memory_bytes);
      std::string expected;
      for (int i = 0; i < 300; ++i) {
        std::string chunk(static_cast<std::size_t>(i * 7 % 97), static_cast<char>('a' + i % 26));
        chunk += std::to_string(i) + "\n";
        expected += chunk;
        held.take(std::move(chunk));
        CHECK(chunk.empty());
      }
      CHECK(held.size() == expected.size());
      CHECK((held.spilled() > 0) == (memory_bytes < expected.size()));
      std::ostringstream out;
      held.write_to(out);
      CHECK(out.str() == expected);
      CHECK(held.size() == 0);
    }
  }

  TEST_CASE("held text: TextOut into it gives what TextOut to a stream gives") {
    std::ostringstream direct, later;
    report::HeldText held(1000);  // most of it on disk
    {
      report::TextOut a(direct), b(held);
      for (int i = 0; i < 200000; ++i) {  // over 1 MiB: TextOut hands on several chunks
        for (report::TextOut* o : {&a, &b}) {
          o->integer(static_cast<unsigned long>(i));
          *o << ' ';
          o->fixed(i * -0.001234567, 6);
          *o << '\n';
        }
      }
    }
    CHECK(held.spilled() > 0);
    held.write_to(later);
    CHECK(later.str() == direct.str());
  }
}
