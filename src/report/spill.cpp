// Records on disk (include/deflex/report/spill.hpp).
#include "deflex/report/spill.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::report {

SpillBytes::SpillBytes(const std::string& dir, std::size_t record_bytes) : bytes_(record_bytes), dir_(dir) {
  namespace fs = std::filesystem;
  std::string tmpl = ((dir.empty() ? fs::temp_directory_path() : fs::path(dir)) / ".deflex-spill-XXXXXX").string();
  std::vector<char> name(tmpl.begin(), tmpl.end());
  name.push_back('\0');
  const int fd = mkstemp(name.data());
  if (fd < 0) throw Error(ErrorKind::io, tmpl + ": error: cannot create a temporary file: " + std::strerror(errno));
  ::unlink(name.data());
  f_ = ::fdopen(fd, "w+b");
  if (!f_) {
    ::close(fd);
    throw Error(ErrorKind::io, tmpl + ": error: cannot open a temporary file");
  }
  std::setvbuf(f_, nullptr, _IOFBF, 1 << 20);
}

SpillBytes::~SpillBytes() {
  if (f_) std::fclose(f_);
}

void SpillBytes::append(const void* record) {
  if (std::fwrite(record, bytes_, 1, f_) != 1)
    throw Error(ErrorKind::io, (dir_.empty() ? std::string("temporary folder") : dir_) + ": error: write failed (disk full?)");
  ++count_;
}

void SpillBytes::each(const std::function<void(const void* record)>& f) {
  if (std::fflush(f_) != 0 || std::fseek(f_, 0, SEEK_SET) != 0)
    throw Error(ErrorKind::io, "error: cannot read back a temporary file");
  std::vector<char> buf(bytes_ * 16384);
  std::size_t left = count_;
  while (left) {
    const std::size_t want = std::min<std::size_t>(left, 16384);
    if (std::fread(buf.data(), bytes_, want, f_) != want) throw Error(ErrorKind::io, "error: cannot read back a temporary file");
    for (std::size_t i = 0; i < want; ++i) f(buf.data() + i * bytes_);
    left -= want;
  }
  std::fseek(f_, 0, SEEK_END);  // appending goes on at the end
}

double kth_value(const std::function<void(const std::function<void(double)>&)>& each, std::size_t n, std::size_t k,
                 double lo, double hi) {
  constexpr std::size_t kBins = 4096, kSort = std::size_t{1} << 20;
  // Invariant: the values in [lo, hi] are n, the wanted one the k-th of them.
  for (int level = 0;; ++level) {
    if (!(lo < hi)) return lo;
    if (n <= kSort || level >= 12) {
      std::vector<double> v;
      v.reserve(std::min(n, kSort));
      each([&](double x) {
        if (x >= lo && x <= hi) v.push_back(x);
      });
      std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
      return v[k];
    }
    // A histogram over [lo, hi]; a bin's values are those between its
    // smallest and largest (the binning is monotone), the next range.
    const double w = (hi - lo) / kBins;
    if (!(w > 0) || !std::isfinite(w)) level = 12;  // infinite or subnormal range: sort what is there
    if (level >= 12) continue;
    auto bin = [&](double x) { return std::min<std::size_t>(kBins - 1, static_cast<std::size_t>((x - lo) / w)); };
    std::vector<std::size_t> count(kBins, 0);
    std::vector<double> mn(kBins, HUGE_VAL), mx(kBins, -HUGE_VAL);
    each([&](double x) {
      if (!(x >= lo && x <= hi)) return;
      const std::size_t b = bin(x);
      ++count[b];
      mn[b] = std::min(mn[b], x);
      mx[b] = std::max(mx[b], x);
    });
    std::size_t b = 0;
    for (; b + 1 < kBins && k >= count[b]; ++b) k -= count[b];
    n = count[b];
    lo = mn[b];
    hi = mx[b];
  }
}

}  // namespace deflex::report
