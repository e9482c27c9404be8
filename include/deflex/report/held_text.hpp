// Text kept back until it is known whether it goes out at all. `deflex path`
// prints nothing of a program with an error, and it learns of the error in
// the same pass that makes the text: the text waits here, in memory up to a
// bound and past it in an unlinked temporary file (as report::SpillBytes), so
// memory does not grow with the program.
#pragma once
#include <cstddef>
#include <iosfwd>
#include <string>
#include <vector>

namespace deflex::report {

// Text held in memory before the rest goes to disk, bytes: the path of the
// 1M-block raster (35 MB) stays in memory, where writing it out costs no
// second copy through the kernel.
inline constexpr std::size_t kHeldMemoryBytes = std::size_t{64} << 20;

class HeldText {
 public:
  explicit HeldText(std::size_t memory_bytes = kHeldMemoryBytes) : memory_bytes_(memory_bytes) {}
  ~HeldText();
  HeldText(const HeldText&) = delete;
  HeldText& operator=(const HeldText&) = delete;
  // Appends `chunk`, taking its storage (it is left empty): no copy while in memory.
  void take(std::string&& chunk);
  // Everything taken, in order, to `o`; then nothing is held. Throws Error(io)
  // when the temporary file cannot be read back.
  void write_to(std::ostream& o);
  std::size_t size() const { return memory_ + spilled_; }
  std::size_t spilled() const { return spilled_; }  // of size(), on disk

 private:
  void spill(const std::string& chunk);
  std::size_t memory_bytes_;
  std::vector<std::string> chunks_;  // in memory, before what is on disk
  std::size_t memory_ = 0, spilled_ = 0;
  int fd_ = -1;
};

}  // namespace deflex::report
