// earl runtime: the schedule of a deterministic run (--schedule SEED). Header-only, C++17.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>

#include "earl/component.hpp"

namespace earl {

/// The order in which the subsystems of a deterministic run step, drawn from a seed: seed 0 is
/// model order with every subsystem in every cycle (the default run); any other seed draws, in
/// each cycle, a new order and leaves each subsystem out of the cycle once in four, as if it were
/// a period late. The same seed gives the same run, so an interleaving one seed finds can be run
/// again; no two seeds promise different ones. Nothing here allocates.
class Schedule {
 public:
  explicit Schedule(std::uint64_t seed) noexcept : seed_(seed), state_(seed * 0x9E3779B97F4A7C15ULL | 1U) {}

  bool drawn() const noexcept { return seed_ != 0; }

  /// One cycle at ``now``: each subsystem the schedule keeps in the cycle steps when ready.
  template <std::size_t N>
  void step(std::array<Component*, N>& order, Component::Clock::time_point now) noexcept {
    for (std::size_t i = N; i > 1; --i) std::swap(order[i - 1], order[next() % i]);
    for (Component* c : order) {
      if (next() % 4 != 0 && c->ready(now)) c->updateHook();
    }
  }

 private:
  std::uint64_t next() noexcept {  // xorshift64*
    state_ ^= state_ >> 12;
    state_ ^= state_ << 25;
    state_ ^= state_ >> 27;
    return state_ * 0x2545F4914F6CDD1DULL;
  }

  std::uint64_t seed_;
  std::uint64_t state_;
};

}  // namespace earl
