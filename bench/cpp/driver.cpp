// Per-cycle cost of the generated manip/a.cs (N = 6, the generated pf stubs) against the
// hand-written loop of baseline.cpp, measured in the same run. Built and run by
// bench/cpp_cycle.py; prints one JSON object per scenario.
//
//   driver [--cycles N] [--repeats R]
//
// Per scenario (bench.hpp) and repetition it times N cycles of each of
//   generated: source.feed(), then cs.updateHook() of the generated subsystem;
//   baseline:  source.feed(), then the hand-written loop's cycle();
//   source:    source.feed() alone (the part of both figures that is not the subsystem);
// interleaved, after one untimed warm-up round, and reports the best and the median
// repetition in ns per cycle. Built with -DBENCH_COUNT_NEW and count_new.cpp (as
// tests/test_cpp_allocations.py does), it also reports the operator new calls made during
// the timed repetitions ("allocations"; null otherwise).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "bench.hpp"
#ifdef BENCH_COUNT_NEW
#include "count_new.hpp"
#endif
#include "PickAndPlace/manip_a/cs/subsystem.hpp"

namespace {

using bench::Scenario;
using Cs = ::PickAndPlace::manip_a::cs::Subsystem;

/// manip/a.cs alone, its fourteen buffers linked to the driver's channels.
struct GeneratedFixture {
  explicit GeneratedFixture(Scenario s) noexcept : source(s) {
    auto& d = cs.data();
    d.manipulatorCommand_ib.connect(links.manipulatorCommand);
    d.manipulatorState_ob.connect(links.manipulatorState);
    for (std::size_t k = 0; k < bench::kJoints; ++k) {
      d.motorControllerStateK_ib[k].connect(links.motorControllerState[k]);
      d.motorControllerCommandK_ob[k].connect(links.motorControllerCommand[k]);
    }
    if (s == Scenario::switching) d.motionFinished_m = true;
    cs.startHook();
  }
  bench::Links links;
  bench::Source source;
  Cs cs{"manip/a.cs"};
  std::uint64_t cycle = 0;
};

struct SourceFixture {
  explicit SourceFixture(Scenario s) noexcept : source(s) {}
  bench::Links links;
  bench::Source source;
  std::uint64_t cycle = 0;
};

GeneratedFixture generatedHold(Scenario::hold), generatedSwitching(Scenario::switching);
SourceFixture sourceHold(Scenario::hold), sourceSwitching(Scenario::switching);

__attribute__((noinline)) double generatedRun(Scenario scenario, std::uint64_t cycles) {
  GeneratedFixture& f = scenario == Scenario::hold ? generatedHold : generatedSwitching;
  const double ns = bench::nsPerCycle(cycles, [&f](std::uint64_t i) {
    f.source.feed(f.links, f.cycle + i);
    f.cs.updateHook();
  });
  f.cycle += cycles;
  return ns;
}

__attribute__((noinline)) double sourceRun(Scenario scenario, std::uint64_t cycles) {
  SourceFixture& f = scenario == Scenario::hold ? sourceHold : sourceSwitching;
  const double ns = bench::nsPerCycle(cycles, [&f](std::uint64_t i) { f.source.feed(f.links, f.cycle + i); });
  f.cycle += cycles;
  return ns;
}

struct Stats {
  double best;
  double median;
};

Stats stats(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  const double median = n % 2 == 1 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2.0;
  return {values.front(), median};
}

int usage(const char* program) {
  std::fprintf(stderr, "usage: %s [--cycles N] [--repeats R]\n", program);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t cycles = 1000000;
  int repeats = 7;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--cycles") == 0 && i + 1 < argc) {
      cycles = std::strtoull(argv[++i], nullptr, 10);
    } else if (std::strcmp(argv[i], "--repeats") == 0 && i + 1 < argc) {
      repeats = std::atoi(argv[++i]);
    } else {
      return usage(argv[0]);
    }
  }
  if (cycles == 0 || repeats < 1) return usage(argv[0]);

  for (Scenario scenario : {Scenario::hold, Scenario::switching}) {
    generatedRun(scenario, cycles / 10 + 1);  // warm-up, untimed
    bench::baselineRun(scenario, cycles / 10 + 1);
    sourceRun(scenario, cycles / 10 + 1);
    std::vector<double> generated, baseline, source;
    generated.reserve(static_cast<std::size_t>(repeats));
    baseline.reserve(static_cast<std::size_t>(repeats));
    source.reserve(static_cast<std::size_t>(repeats));
#ifdef BENCH_COUNT_NEW
    const std::uint64_t before = count_new::allocations();
    count_new::start();
#endif
    for (int r = 0; r < repeats; ++r) {
      generated.push_back(generatedRun(scenario, cycles));
      baseline.push_back(bench::baselineRun(scenario, cycles));
      source.push_back(sourceRun(scenario, cycles));
    }
#ifdef BENCH_COUNT_NEW
    count_new::stop();
    char allocations[32];
    std::snprintf(allocations, sizeof allocations, "%llu",
                  static_cast<unsigned long long>(count_new::allocations() - before));
#else
    const char* allocations = "null";
#endif
    const Stats g = stats(generated), b = stats(baseline), s = stats(source);
    const GeneratedFixture& f = scenario == Scenario::hold ? generatedHold : generatedSwitching;
    const bench::Summary base = bench::baselineSummary(scenario);
    std::printf(
        "{\"scenario\": \"%s\", \"cycles\": %llu, \"repeats\": %d, "
        "\"generated\": {\"best\": %.3f, \"median\": %.3f, \"state\": \"%s\", \"iteration\": %llu}, "
        "\"baseline\": {\"best\": %.3f, \"median\": %.3f, \"state\": \"%s\", \"iteration\": %llu}, "
        "\"source\": {\"best\": %.3f, \"median\": %.3f}, \"allocations\": %s}\n",
        bench::name(scenario), static_cast<unsigned long long>(cycles), repeats, g.best, g.median,
        f.cs.currentStateName(), static_cast<unsigned long long>(f.cs.iteration()), b.best, b.median, base.state,
        static_cast<unsigned long long>(base.iteration), s.best, s.median, allocations);
  }
  return 0;
}
