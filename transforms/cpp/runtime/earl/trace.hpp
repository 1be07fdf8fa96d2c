// earl runtime: an observer printing state changes, queue overflows and failing pf, one line each, to stdout.
// Part of earl-m2t's C++ target; header-only, C++17.
#pragma once

#include <cinttypes>
#include <cstdint>
#include <cstdio>

#include "earl/component.hpp"

namespace earl {

class PrintObserver final : public Observer {
 public:
  void stateChanged(const Component& component, const char* from, const char* to, const char* via,
                    std::uint64_t step) noexcept override {
    if (from == nullptr) {
      std::printf("step %" PRIu64 " %s: start in %s\n", step, component.name(), to);
    } else {
      std::printf("step %" PRIu64 " %s: %s -> %s (%s)\n", step, component.name(), from, to, via);
    }
  }
  void overflowed(const Component& component, const char* buffer, std::uint64_t lost,
                  std::uint64_t step) noexcept override {
    std::printf("step %" PRIu64 " %s: %s overflowed, %" PRIu64 " value(s) lost\n", step, component.name(), buffer,
                lost);
  }
  void pfFailed(const Component& component, const char* pf, const char* reason,
                std::uint64_t step) noexcept override {
    std::printf("step %" PRIu64 " %s: %s failed: %s\n", step, component.name(), pf, reason);
  }
  void nonFinite(const Component& component, const char* pf, const char* buffer,
                 std::uint64_t step) noexcept override {
    std::printf("step %" PRIu64 " %s: %s wrote a non-finite number into %s (sent)\n", step, component.name(), pf,
                buffer);
  }
};

}  // namespace earl
