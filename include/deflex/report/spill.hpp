// Records of fixed size kept on disk, not in memory: what a report needs of
// every CL point after the run (percentiles, the page's grid and plots) for a
// program of any length. The file is unlinked at once (it vanishes with the
// process, whatever happens) and lives in the report folder when there is
// one: /tmp may be a RAM disk, and the report's points.csv is larger anyway.
#pragma once
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

namespace deflex::report {

class SpillBytes {
 public:
  SpillBytes(const std::string& dir, std::size_t record_bytes);  // dir "": the temporary folder
  ~SpillBytes();
  SpillBytes(const SpillBytes&) = delete;
  SpillBytes& operator=(const SpillBytes&) = delete;
  void append(const void* record);
  std::size_t size() const { return count_; }
  // Each record in order, in chunks (the file is read from the start each call).
  void each(const std::function<void(const void* record)>& f);

 private:
  std::FILE* f_ = nullptr;
  std::size_t bytes_, count_ = 0;
  std::string dir_;
};

template <class T>
class Spill {
  static_assert(std::is_trivially_copyable_v<T>);

 public:
  explicit Spill(const std::string& dir = "") : b_(dir, sizeof(T)) {}
  void push_back(const T& r) { b_.append(&r); }
  std::size_t size() const { return b_.size(); }
  template <class F>
  void each(F f) {
    b_.each([&](const void* p) {
      T r;
      std::memcpy(&r, p, sizeof(T));
      f(r);
    });
  }

 private:
  SpillBytes b_;
};

// The k-th smallest (from 0) of the n values a pass over `each` yields (each
// call must yield the same values), in memory bounded by 2^20 values: a
// histogram narrows the range holding the rank pass by pass, and only the
// values in the last range are sorted. `lo`, `hi`: bounds of all the values.
double kth_value(const std::function<void(const std::function<void(double)>&)>& each, std::size_t n, std::size_t k,
                 double lo, double hi);

}  // namespace deflex::report
