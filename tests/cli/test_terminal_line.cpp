// The progress line on a terminal (src/cli/terminal_line.hpp): a message
// written while it is shown starts on a cleared row, never after its text.
#include <doctest/doctest.h>

#include <ostream>
#include <sstream>

#include "../../src/cli/terminal_line.hpp"

TEST_SUITE("cli") {
  TEST_CASE("a message while the progress line is shown clears the line first; none when it is not") {
    const std::string clear = "\r\033[K";
    std::stringbuf terminal;
    deflex::cli::TerminalLine line(&terminal);
    std::ostream err(&line);
    err << "a note\n";  // nothing shown: written as it is
    CHECK(terminal.str() == "a note\n");
    line.show("checking 40%");
    err << "p.nc:3:1: warning: w" << '\n';
    line.show("checking 80%");
    err.put('x');  // one character goes through overflow, not xsputn
    line.show("");  // nothing shown since the x: nothing to clear
    const std::string expected = "a note\n" + clear + "checking 40%" + clear + "p.nc:3:1: warning: w\n" + clear +
                                 "checking 80%" + clear + "x";
    CHECK(terminal.str() == expected);
    line.show("stock 0%");
    line.show("");  // the run's end: the line shown is cleared
    CHECK(terminal.str() == expected + clear + "stock 0%" + clear);
  }
}
