// Heap allocations per cycle after start-up of the generated pick-and-place system, counted
// by count_new.cpp. Built and run by tests/test_cpp_allocations.py; prints one JSON object.
//
//   alloc_main [--startup N] [--cycles N] [--threaded SECONDS] [--selftest]
//
// 1. start-up: the system object is constructed and wired, then stepped N times
//    (default 100), not counted as cycles (startup_allocations: every operator new so far);
// 2. deterministic: --cycles cycles of System::step() (default 10000), counted;
// 3. threaded: an earl::ThreadedRunner with one thread per subsystem (period 200 us) is
//    started, uncounted; then --threaded seconds of running (default 0.2) are counted, and
//    the threads are stopped and joined, uncounted.
// --selftest allocates once inside the counted deterministic phase, to show that the
// counter sees it.
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <thread>

#include "count_new.hpp"
#include "earl/earl.hpp"
#include "PickAndPlace/system.hpp"

namespace {

volatile char* sink = nullptr;

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t startup = 100;
  std::uint64_t cycles = 10000;
  double seconds = 0.2;
  bool selftest = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--startup") == 0 && i + 1 < argc) {
      startup = std::strtoull(argv[++i], nullptr, 10);
    } else if (std::strcmp(argv[i], "--cycles") == 0 && i + 1 < argc) {
      cycles = std::strtoull(argv[++i], nullptr, 10);
    } else if (std::strcmp(argv[i], "--threaded") == 0 && i + 1 < argc) {
      seconds = std::strtod(argv[++i], nullptr);
    } else if (std::strcmp(argv[i], "--selftest") == 0) {
      selftest = true;
    } else {
      std::fprintf(stderr, "usage: %s [--startup N] [--cycles N] [--threaded SECONDS] [--selftest]\n", argv[0]);
      return 2;
    }
  }

  static ::PickAndPlace::System system;
  for (std::uint64_t i = 0; i < startup; ++i) system.step();
  const std::uint64_t startupAllocations = count_new::allAllocations();

  count_new::start();
  for (std::uint64_t i = 0; i < cycles; ++i) system.step();
  if (selftest) {
    auto bytes = std::make_unique<char[]>(static_cast<std::size_t>(argc) * 64);
    sink = bytes.get();
    sink[0] = 1;
  }
  count_new::stop();
  const std::uint64_t deterministicAllocations = count_new::allocations();
  const std::uint64_t deterministicSteps = system.manip_a.cs.steps();

  std::uint64_t threadedStartAllocations = 0;
  std::uint64_t threadedAllocations = 0;
  std::uint64_t threadedSteps = 0;
  std::size_t threads = 0;
  if (seconds > 0.0) {
    for (earl::Component* c : system.components()) c->setPeriod(std::chrono::microseconds(200));
    earl::ThreadedRunner<::PickAndPlace::System::kComponents> runner(system.components());
    const std::uint64_t beforeStart = count_new::allAllocations();
    runner.start();
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // every thread is up
    threadedStartAllocations = count_new::allAllocations() - beforeStart;
    threads = runner.threads();
    const std::uint64_t before = count_new::allocations();
    const std::uint64_t stepsBefore = system.manip_a.cs.steps();
    count_new::start();
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    count_new::stop();
    threadedAllocations = count_new::allocations() - before;
    threadedSteps = system.manip_a.cs.steps() - stepsBefore;
    runner.stop();
  }

  std::printf(
      "{\"components\": %zu, \"startup_cycles\": %llu, \"startup_allocations\": %llu, "
      "\"cycles\": %llu, \"cs_steps\": %llu, \"allocations\": %llu, "
      "\"threaded_seconds\": %.3f, \"threads\": %zu, \"threaded_start_allocations\": %llu, "
      "\"threaded_cs_steps\": %llu, \"threaded_allocations\": %llu}\n",
      ::PickAndPlace::System::kComponents, static_cast<unsigned long long>(startup),
      static_cast<unsigned long long>(startupAllocations), static_cast<unsigned long long>(cycles),
      static_cast<unsigned long long>(deterministicSteps), static_cast<unsigned long long>(deterministicAllocations),
      seconds, threads, static_cast<unsigned long long>(threadedStartAllocations), static_cast<unsigned long long>(threadedSteps), static_cast<unsigned long long>(threadedAllocations));
  return 0;
}
