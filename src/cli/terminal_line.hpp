// The progress line on a terminal, kept apart from the messages: standard
// error's buffer, wrapped so that a message written while the line is shown
// first clears it (the line is drawn again at the next step). Without it a
// warning found while the program is being checked would start on the
// progress line's row.
#pragma once
#include <streambuf>
#include <string>

namespace deflex::cli {

class TerminalLine : public std::streambuf {
 public:
  explicit TerminalLine(std::streambuf* terminal) : terminal_(terminal) {}
  // Draws `text` in place of the line shown; "" clears it.
  void show(const std::string& text);

 protected:
  int overflow(int c) override;
  std::streamsize xsputn(const char* s, std::streamsize n) override;
  int sync() override { return terminal_->pubsync(); }

 private:
  void clear();
  std::streambuf* terminal_;
  bool shown_ = false;
};

}  // namespace deflex::cli
