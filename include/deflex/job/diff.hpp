// `deflex diff` as a call: two programs paired block by block by their
// structure (compensate/pairing.hpp), and whether they differ only in the
// coordinates of motion blocks, and by how much.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "deflex/job/io.hpp"
#include "deflex/job/settings.hpp"

namespace deflex::job {

struct DiffSettings {
  std::string a, b;     // the original and (e.g.) the compensated program; "-": the input stream
  ReadSettings read;
  // A block only in B within this of the next paired move is a split of it;
  // of two blocks alike but for their coordinates, the nearer pairs, mm.
  double pair_mm = 1.0;
};

struct DiffChange {      // a paired motion block that moved
  std::uint32_t line_a = 0, line_b = 0;
  double d_mm[3] = {0, 0, 0};  // B's end point less A's, work frame
  double distance_mm = 0;
  bool edited = false;   // false: the same text, moved by a modal axis word carried over
};

struct DiffSplit {       // a block only in B on the move of A's line after it
  std::uint32_t line_b = 0, line_a = 0;
  double distance_mm = 0;  // its end point's distance from that move
};

struct DiffResult {
  std::vector<DiffChange> changes;
  std::vector<DiffSplit> splits;
  std::vector<std::string> other;  // every change in more than coordinates, as FILE:LINE: text
  double max_mm = 0, mean_mm = 0;  // over the changes and splits / the changes
  std::size_t edited = 0;
  bool only_coordinates() const { return other.empty(); }
};

// Both programs read and interpreted (their diagnostics to io.err; an input
// Error when either has errors), then paired and compared.
DiffResult diff(const DiffSettings& s, Io& io);

}  // namespace deflex::job
