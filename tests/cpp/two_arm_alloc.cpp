// Heap allocations per cycle of the generated two-arm system (samples/two_arm), switches
// included, counted by bench/cpp/count_new.cpp. Built and run by tests/test_two_arm_runs.py;
// prints one JSON object (after the lines the sample's user code prints).
//
//   two_arm_alloc [--cycles N] [--threaded SECONDS]
//
// 1. deterministic: one system, constructed and stepped once (start-up, not counted), then
//    --cycles cycles on the simulated clock (default 6000: every hand-over of the sample), counted;
// 2. threaded: a second system, one thread per subsystem; thread creation is not counted,
//    --threaded seconds of running (default 0.5) are.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>

#include "count_new.hpp"
#include "earl/earl.hpp"
#include "TwoArm/system.hpp"

namespace {

::TwoArm::System& deterministic() {
  static ::TwoArm::System system;
  return system;
}

::TwoArm::System& threaded() {
  static ::TwoArm::System system;
  return system;
}

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t cycles = 6000;
  double seconds = 0.5;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--cycles") == 0 && i + 1 < argc) {
      cycles = std::strtoull(argv[++i], nullptr, 10);
    } else if (std::strcmp(argv[i], "--threaded") == 0 && i + 1 < argc) {
      seconds = std::strtod(argv[++i], nullptr);
    } else {
      std::fprintf(stderr, "usage: %s [--cycles N] [--threaded SECONDS]\n", argv[0]);
      return 2;
    }
  }
  ::TwoArm::System& system = deterministic();
  ::TwoArm::System& other = threaded();
  const std::chrono::nanoseconds period = std::chrono::milliseconds(1);
  for (earl::Component* c : system.components()) c->setPeriod(period);
  system.switcher().countCycles(true);
  system.step(earl::Component::Clock::time_point{});
  count_new::start();
  for (std::uint64_t cycle = 1; cycle < cycles; ++cycle) {
    system.step(earl::Component::Clock::time_point(period * static_cast<std::int64_t>(cycle)));
  }
  count_new::stop();
  const std::uint64_t deterministicAllocations = count_new::allocations();
  const std::uint64_t deterministicSwitches = system.switcher().switches();

  for (earl::Component* c : other.components()) c->setPeriod(period);
  earl::ThreadedRunner<::TwoArm::System::kComponents> runner(other.components());
  const std::uint64_t beforeStart = count_new::allAllocations();
  runner.start();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const std::uint64_t startAllocations = count_new::allAllocations() - beforeStart;
  const std::uint64_t before = count_new::allocations();
  count_new::start();
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  count_new::stop();
  const std::uint64_t threadedAllocations = count_new::allocations() - before;
  const std::uint64_t threadedSwitches = other.switcher().switches();
  runner.stop();

  std::printf(
      "{\"cycles\": %llu, \"allocations\": %llu, \"switches\": %llu, \"threaded_start_allocations\": %llu, "
      "\"threaded_allocations\": %llu, \"threaded_switches\": %llu}\n",
      static_cast<unsigned long long>(cycles), static_cast<unsigned long long>(deterministicAllocations),
      static_cast<unsigned long long>(deterministicSwitches), static_cast<unsigned long long>(startAllocations),
      static_cast<unsigned long long>(threadedAllocations), static_cast<unsigned long long>(threadedSwitches));
  return 0;
}
