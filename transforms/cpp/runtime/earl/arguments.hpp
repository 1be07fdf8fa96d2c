// earl runtime: the command-line values of the generated executables, read strictly: a
// value that is not what it says (a negative or fractional cycle count, a time that is not a
// finite number of seconds in range) is refused, never wrapped or clamped into another run.
// Part of earl-m2t's C++ target; header-only, C++17.
#pragma once

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "earl/component.hpp"
#include "earl/realtime.hpp"

namespace earl {

/// A whole number from 0 to ``limit``, decimal digits only.
inline bool parseWhole(const char* text, std::uint64_t limit, std::uint64_t& number) noexcept {
  if (text == nullptr || *text == '\0') return false;
  std::uint64_t value = 0;
  for (const char* c = text; *c != '\0'; ++c) {
    if (*c < '0' || *c > '9') return false;
    value = value * 10 + static_cast<std::uint64_t>(*c - '0');
    if (value > limit) return false;
  }
  number = value;
  return true;
}

/// Cycles of a deterministic run: a whole number from 0 to 10^12.
inline bool parseCycles(const char* text, std::uint64_t& cycles) noexcept {
  return parseWhole(text, 1'000'000'000'000ULL, cycles);
}

/// The seed of a deterministic run's schedule (earl/schedule.hpp): a whole number from 0 to 10^18.
inline bool parseSeed(const char* text, std::uint64_t& seed) noexcept {
  return parseWhole(text, 1'000'000'000'000'000'000ULL, seed);
}

/// Seconds of a threaded run: a finite number greater than 0 and at most 10^6 (eleven days).
inline bool parseSeconds(const char* text, double& seconds) noexcept {
  if (text == nullptr || *text == '\0') return false;
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(text, &end);
  if (end == text || *end != '\0' || errno != 0 || !std::isfinite(value) || value <= 0.0 || value > 1e6) return false;
  seconds = value;
  return true;
}

/// What a pf writing a non-finite number does: "error" or "report".
inline bool parseNonFinite(const char* text, NonFinite& policy) noexcept {
  if (text == nullptr) return false;
  if (std::strcmp(text, "error") == 0) {
    policy = NonFinite::error;
  } else if (std::strcmp(text, "report") == 0) {
    policy = NonFinite::report;
  } else {
    return false;
  }
  return true;
}

/// --threads: "period" (periodic subsystems of one period and the same settings share a
/// thread, the default) or "subsystem" (a thread each).
inline bool parseThreadPlan(const char* text, ThreadPlan& plan) noexcept {
  if (text == nullptr) return false;
  if (std::strcmp(text, "period") == 0) {
    plan = ThreadPlan::perPeriod;
  } else if (std::strcmp(text, "subsystem") == 0) {
    plan = ThreadPlan::perSubsystem;
  } else {
    return false;
  }
  return true;
}

}  // namespace earl
