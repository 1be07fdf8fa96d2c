// Variable structure in the earl C++ runtime (transforms/cpp/runtime/earl/switch.hpp), on a
// hand-written system in the shape the generator emits: task/a.cs (the coordinator, states
// withA and withB naming the configurations useA and useB) sends numbered commands to
// manipA/a.cs or manipB/a.cs (the same subsystem class) over queued variable links, and gets
// their status back over latest-value variable links. A manipulator receives one command per
// iteration in idle (quiescent); every fourth command sends it to work for a few iterations,
// in which it receives nothing, so commands wait in its queue; leaving() ends work early.
// manipA/a restarts when it joins, manipB/a resumes.
//
//   test_switch --cycles N [options]   deterministic (simulated clock), prints the trace
//   test_switch --threaded [options]   one thread per subsystem, prints only the summary
//   options: --switches S  --per P (commands per configuration)  --timeout-ms T  --quiet
//
// The last line is the summary the test reads: every command is checked to have been
// received exactly once, in order, by the manipulator of the configuration it was sent in.
// Built and run by tests/test_switch_runtime.py.
#include <array>
#include <atomic>
#include <chrono>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <thread>

#include "earl/earl.hpp"
#include "earl/switch.hpp"
#include "handover_subsystems.hpp"

namespace {

std::atomic<std::uint64_t> allocations{0};

}  // namespace

void* operator new(std::size_t size) {
  allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace {

using namespace handover;

// ---------------------------------------------------------------- the system

constexpr const char* kNames[] = {"useA", "useB"};
// variable agents: manipA/a, manipB/a
constexpr bool kAgents[] = {true, false, false, true};
// variable links: task/a,manipA/a  task/a,manipB/a  manipA/a,task/a  manipB/a,task/a
constexpr bool kLinks[] = {true, false, true, false, false, true, false, true};
constexpr std::int16_t kStateConfiguration[] = {0, 1};  // withA: useA, withB: useB
std::int64_t timeouts[] = {0, 0};
// the variable agent sending and receiving each link (-1: task/a, in every configuration)
constexpr std::int16_t kLinkSender[] = {-1, -1, 0, 1};
constexpr std::int16_t kLinkReceiver[] = {0, 1, -1, -1};
const earl::SwitchTables kTables{kNames, 2, kAgents, 2, kLinks, 4, timeouts, kLinkSender, kLinkReceiver};

struct System {
  CommandLink toA, toB;
  StatusLink fromA, fromB;
  earl::AgentSlot slotA{"manipA/a", earl::Reactivation::restart};
  earl::AgentSlot slotB{"manipB/a", earl::Reactivation::resume};
  std::atomic<bool> insideA{false}, insideB{false};
  Task task;
  Manip manipA{"manipA/a.cs", 'A', insideB, insideA};
  Manip manipB{"manipB/a.cs", 'B', insideA, insideB};
  std::array<earl::AgentSlot*, 2> slots{&slotA, &slotB};
  std::array<earl::SwitchLink, 4> links{
      earl::switchLink("task/a,manipA/a", toA, &slotA), earl::switchLink("task/a,manipB/a", toB, &slotB),
      earl::switchLink("manipA/a,task/a", fromA, nullptr), earl::switchLink("manipB/a,task/a", fromB, nullptr)};
  earl::Switch sw{kTables, slots.data(), links.data()};

  System() noexcept {
    task.command.connect(toA);
    task.command.connect(toB);
    manipA.command.connect(toA);
    manipB.command.connect(toB);
    manipA.status.connect(fromA);
    manipB.status.connect(fromB);
    task.status.connect(fromA);
    task.status.connect(fromB);
    manipA.joinAgent(slotA, true);
    manipB.joinAgent(slotB, true);
    task.coordinate(sw, kStateConfiguration);
    sw.start(static_cast<std::size_t>(kStateConfiguration[Task::tables().initial]));
  }

  void step(earl::Component::Clock::time_point now) noexcept {
    if (task.ready(now)) task.updateHook();
    if (manipA.ready(now)) manipA.updateHook();
    if (manipB.ready(now)) manipB.updateHook();
  }
  std::array<earl::Component*, 3> components() noexcept { return {&task, &manipA, &manipB}; }
  void setObserver(earl::SwitchObserver* o) noexcept {
    task.setObserver(o);
    manipA.setObserver(o);
    manipB.setObserver(o);
    sw.setObserver(o);
  }
};

/// Counts switches, latencies and losses; passes every event on to ``next`` when there is one
/// (the threaded run prints nothing: printing takes the stdio lock).
class Tally final : public earl::SwitchObserver {
 public:
  explicit Tally(earl::SwitchObserver* next) noexcept : next_(next) {}
  void stateChanged(const earl::Component& c, const char* from, const char* to, const char* via,
                    std::uint64_t step) noexcept override {
    if (next_ != nullptr) next_->stateChanged(c, from, to, via, step);
  }
  void overflowed(const earl::Component& c, const char* buffer, std::uint64_t lost, std::uint64_t step) noexcept override {
    overflows += lost;
    if (next_ != nullptr) next_->overflowed(c, buffer, lost, step);
  }
  void switched(const char* from, const char* to, const earl::SwitchLatency& latency) noexcept override {
    if (latency.nanoseconds > maxNs) maxNs = latency.nanoseconds;
    if (latency.cycles > maxCycles) maxCycles = latency.cycles;
    if (latency.forced) ++forced;
    if (next_ != nullptr) next_->switched(from, to, latency);
  }
  void undelivered(const char* link, std::uint64_t count) noexcept override {
    undeliveredCount += count;
    if (next_ != nullptr) next_->undelivered(link, count);
  }
  std::atomic<std::uint64_t> overflows{0};
  std::int64_t maxNs = 0;
  std::uint64_t forced = 0;  // switches the observer was told were forced
  std::uint64_t maxCycles = 0, undeliveredCount = 0;

 private:
  earl::SwitchObserver* next_;
};

System& theSystem() {
  static System system;  // static: the whole system lives outside the stack
  return system;
}

int usage(const char* program) {
  std::fprintf(stderr,
               "usage: %s (--cycles N | --threaded) [--switches S] [--per P] [--timeout-ms T] [--quiet]\n",
               program);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t cycles = 0;
  bool threaded = false, quiet = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--cycles") == 0 && i + 1 < argc) {
      cycles = std::strtoull(argv[++i], nullptr, 10);
    } else if (std::strcmp(argv[i], "--threaded") == 0) {
      threaded = true;
    } else if (std::strcmp(argv[i], "--switches") == 0 && i + 1 < argc) {
      settings.switches = std::strtoull(argv[++i], nullptr, 10);
    } else if (std::strcmp(argv[i], "--per") == 0 && i + 1 < argc) {
      settings.per = std::strtoull(argv[++i], nullptr, 10);
    } else if (std::strcmp(argv[i], "--timeout-ms") == 0 && i + 1 < argc) {
      settings.timeoutNs = static_cast<std::int64_t>(std::strtod(argv[++i], nullptr) * 1e6);
    } else if (std::strcmp(argv[i], "--quiet") == 0) {
      quiet = true;
    } else {
      return usage(argv[0]);
    }
  }
  if ((cycles == 0) == !threaded || (settings.switches + 1) * settings.per >= kMaxSeq) return usage(argv[0]);
  timeouts[0] = timeouts[1] = settings.timeoutNs;

  System& system = theSystem();
  earl::SwitchPrintObserver trace;
  Tally tally(threaded || quiet ? nullptr : &trace);
  std::uint64_t counted = 0;
  if (threaded) {
    system.setObserver(&tally);
    system.task.setPeriod(std::chrono::microseconds(500));
    system.manipA.setPeriod(std::chrono::microseconds(250));
    system.manipB.setPeriod(std::chrono::microseconds(250));
    earl::ThreadedRunner<3> runner(system.components());
    runner.plan(earl::ThreadPlan::perSubsystem);  // the two arms in threads of their own: the most concurrency
    runner.start();
    const std::uint64_t before = allocations.load();
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!system.task.done.load(std::memory_order_acquire) && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the last manipulator empties its queue
    counted = allocations.load() - before;
    runner.stop();
  } else {
    system.sw.countCycles(true);
    system.setObserver(&tally);
    const std::chrono::nanoseconds period = std::chrono::milliseconds(1);
    for (earl::Component* c : system.components()) c->setPeriod(period);
    system.step(earl::Component::Clock::time_point{});
    const std::uint64_t before = allocations.load();
    for (std::uint64_t cycle = 1; cycle < cycles; ++cycle) {
      system.step(earl::Component::Clock::time_point(period * static_cast<std::int64_t>(cycle)));
    }
    counted = allocations.load() - before;
  }

  // every seq sent: received exactly once, by the manipulator of the configuration it was sent in
  const Task& task = system.task;
  std::uint64_t received = 0, duplicates = 0, lost = 0, misrouted = 0;
  for (std::uint64_t s = 1; s <= task.seq; ++s) {
    const unsigned a = system.manipA.got[s], b = system.manipB.got[s];
    received += a + b;
    if (a + b == 0) ++lost;
    if (a + b > 1) duplicates += a + b - 1;
    if ((a != 0 && task.sentIn[s] != 1) || (b != 0 && task.sentIn[s] != 2)) ++misrouted;
  }
  const std::uint64_t overflows = system.manipA.command.overflows() + system.manipB.command.overflows();
  const earl::Switch& sw = system.sw;
  std::printf(
      "summary sent %" PRIu64 " received %" PRIu64 " lost %" PRIu64 " duplicates %" PRIu64 " misrouted %" PRIu64
      " out_of_order %" PRIu64 " overlaps %" PRIu64 " undelivered %" PRIu64 " overflows %" PRIu64 " switches %" PRIu64
      " timeouts %" PRIu64 " forced %" PRIu64 " max_latency_ns %" PRId64 " max_latency_cycles %" PRIu64 " restarts_a %" PRIu64
      " restarts_b %" PRIu64 " statuses %s allocations %" PRIu64 "\n",
      task.seq, received, lost, duplicates, misrouted, system.manipA.outOfOrder + system.manipB.outOfOrder,
      system.manipA.overlaps + system.manipB.overlaps, sw.undelivered(), overflows, sw.switches(), sw.timeouts(), tally.forced,
      tally.maxNs, tally.maxCycles, system.manipA.restarts,
      system.manipB.restarts, task.statuses > 0 ? "yes" : "no", counted);
  return 0;
}
