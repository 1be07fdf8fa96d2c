// What bench/latency.py's programs share: the writer's hand-off schedule and the report.
// A writer hands one timestamp at a time to a reader thread, waits until the reader took it,
// then pauses a pseudo-random 100..400 us; the reader records, at the start of the iteration
// the value woke, how long ago it was written. The report is one JSON line.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace latency {

using Clock = std::chrono::steady_clock;

inline std::int64_t nowNs() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

/// The pause after a hand-off: 100..400 us from a fixed linear congruential sequence, so that
/// every program sees the same schedule and no write falls on a polling tick on purpose.
class Pauses {
 public:
  std::chrono::microseconds next() noexcept {
    state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return std::chrono::microseconds(100 + static_cast<int>((state_ >> 33) % 301));
  }

 private:
  std::uint64_t state_ = 42;
};

struct Options {
  long samples = 10000;
  double idle = 0.0;  // > 0: no writer, only the reader waiting for this many seconds
};

inline Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--samples") == 0) o.samples = std::atol(argv[i + 1]);
    if (std::strcmp(argv[i], "--idle") == 0) o.idle = std::atof(argv[i + 1]);
  }
  return o;
}

/// One JSON line: the percentiles of ``ns`` in microseconds. With LATENCY_RAW set, also every
/// sample, in nanoseconds, one a line, into that file (bench/latency.py merges rounds so).
inline void report(const char* variant, std::vector<std::int64_t>& ns, std::uint64_t extra, const char* extraName) {
  if (const char* raw = std::getenv("LATENCY_RAW")) {
    if (std::FILE* file = std::fopen(raw, "w")) {
      for (const std::int64_t v : ns) std::fprintf(file, "%lld\n", static_cast<long long>(v));
      std::fclose(file);
    }
  }
  std::sort(ns.begin(), ns.end());
  auto at = [&ns](double q) {
    const auto i = static_cast<std::size_t>(q * static_cast<double>(ns.size() - 1));
    return static_cast<double>(ns[i]) / 1e3;
  };
  std::printf("{\"variant\": \"%s\", \"samples\": %zu, \"p50_us\": %.2f, \"p99_us\": %.2f, \"max_us\": %.2f, "
              "\"%s\": %llu}\n",
              variant, ns.size(), at(0.5), at(0.99), static_cast<double>(ns.back()) / 1e3, extraName,
              static_cast<unsigned long long>(extra));
}

}  // namespace latency
