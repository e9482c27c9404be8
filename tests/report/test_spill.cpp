// Records kept on disk and the selection of a rank over them in bounded
// memory (report/spill.hpp), against std::nth_element over the same values.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "deflex/report/spill.hpp"
#include "deflex/report/stats.hpp"

using namespace deflex;

TEST_SUITE("report") {
  TEST_CASE("spill: records come back in order; kth_value equals nth_element, ties and narrow ranges included") {
    struct Rec {
      double a;
      float b;
      std::uint32_t c;
    };
    report::Spill<Rec> s;
    for (std::uint32_t i = 0; i < 40000; ++i) s.push_back({i * 0.5, static_cast<float>(i), i});
    std::uint32_t next = 0;
    bool ordered = true;
    s.each([&](const Rec& r) { ordered = ordered && r.c == next && r.a == next * 0.5 && r.b == static_cast<float>(next), ++next; });
    CHECK(ordered);
    CHECK(next == 40000);
    // 3 million values: more than the 2^20 sorted in memory, so the
    // histogram narrows; a third of them the same value, a cluster 1e-12 wide.
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<double> v(3000000);
    for (std::size_t i = 0; i < v.size(); ++i)
      v[i] = i % 3 == 0 ? 0.25 : i % 3 == 1 ? 0.5 + 1e-12 * u(rng) : std::pow(u(rng), 8);
    const double lo = *std::min_element(v.begin(), v.end()), hi = *std::max_element(v.begin(), v.end());
    auto each = [&](const std::function<void(double)>& f) {
      for (double x : v) f(x);
    };
    for (std::size_t k : {std::size_t{0}, std::size_t{1}, v.size() / 3, v.size() / 2, 2 * v.size() / 3 + 5,
                          v.size() * 99 / 100, v.size() - 1}) {
      CAPTURE(k);
      std::vector<double> w = v;
      std::nth_element(w.begin(), w.begin() + static_cast<std::ptrdiff_t>(k), w.end());
      CHECK(report::kth_value(each, v.size(), k, lo, hi) == w[k]);
    }
  }
}
