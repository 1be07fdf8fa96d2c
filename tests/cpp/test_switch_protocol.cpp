// The switch between nodes that share no memory (transforms/cpp/runtime/earl/switch_protocol.hpp),
// on the hand-over system of test_switch.cpp: each subsystem is a node with its own
// SwitchMember, task/a.cs's node also holds the SwitchCoordinator, and every value, command and
// acknowledgement goes through a Pipe (a single-producer single-consumer ring) standing in for a
// ROS topic or an RTT port connection: per-link order, no shared state.
//
//   test_switch_protocol --cycles N [options]   one thread steps the nodes in turn, prints the trace
//   test_switch_protocol --threaded [options]   one thread per node, prints only the summary
//   options: --switches S  --per P (commands per configuration)  --timeout-ms T  --quiet
//            --late-stop-ack L: manipA/a's node answers an unforced stop round only after L of
//            its loops (a node asleep until its next data), so that the coordinator forces the
//            stop after the other nodes acknowledged it; they must acknowledge the forced one
//            --slow-acks K: manipB/a's node answers every round only after K of its loops (a
//            slow transport, or a busy node), so that each round takes K loops more
//
// The last line is the summary tests/test_switch_runtime.py reads (the same checks as
// test_switch.cpp's), plus "dropped": values a Pipe could not take (the transport lost them).
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
#include "earl/switch_protocol.hpp"
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

constexpr std::size_t kLinks = 4;  // task/a,manipA/a  task/a,manipB/a  manipA/a,task/a  manipB/a,task/a
constexpr std::size_t kNodes = 3;  // manipA/a.cs, manipB/a.cs, task/a.cs
constexpr const char* kLinkNames[] = {"task/a,manipA/a", "task/a,manipB/a", "manipA/a,task/a", "manipB/a,task/a"};
constexpr const char* kNames[] = {"useA", "useB"};
constexpr bool kAgents[] = {true, false, false, true};
constexpr bool kLinkMask[] = {true, false, true, false, false, true, false, true};
constexpr std::int16_t kStateConfiguration[] = {0, 1};
std::int64_t timeouts[] = {0, 0};
// the variable agent sending and receiving each link (-1: task/a, in every configuration)
constexpr std::int16_t kLinkSender[] = {-1, -1, 0, 1};
constexpr std::int16_t kLinkReceiver[] = {0, 1, -1, -1};
const earl::SwitchTables kTables{kNames, 2, kAgents, 2, kLinkMask, kLinks, timeouts, kLinkSender, kLinkReceiver};

using Command_ = earl::SwitchCommand<kLinks>;
using Ack = earl::SwitchAck<kLinks>;
using Member = earl::SwitchMember<kLinks>;
using Coordinator = earl::SwitchCoordinator<kLinks, kNodes>;

std::atomic<std::uint64_t> dropped{0};

/// One direction of one connection: single producer, single consumer, bounded, in order.
template <class T, std::size_t N = 1024>
class Pipe {
 public:
  void push(const T& value) noexcept {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) == N) {
      dropped.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    ring_[head % N] = value;
    head_.store(head + 1, std::memory_order_release);
  }
  bool pop(T& value) noexcept {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return false;
    value = ring_[tail % N];
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

 private:
  std::array<T, N> ring_{};
  std::atomic<std::size_t> head_{0};
  std::atomic<std::size_t> tail_{0};
};

struct Net {
  Pipe<Command> toA, toB;  // values of links 0 and 1
  Pipe<Status> fromA, fromB;  // values of links 2 and 3
  std::array<Pipe<Command_>, kNodes> commands;  // coordinator -> node
  std::array<Pipe<Ack>, kNodes> acks;  // node -> coordinator
};

struct System {
  Net net;
  std::atomic<bool> insideA{false}, insideB{false};
  Task task;
  Manip manipA{"manipA/a.cs", 'A', insideB, insideA};
  Manip manipB{"manipB/a.cs", 'B', insideA, insideB};
  Member memberA{kTables, 0, 0, true, "manipA/a", earl::Reactivation::restart};
  Member memberB{kTables, 1, 1, true, "manipB/a", earl::Reactivation::resume};
  Member memberTask{kTables, 2, -1, true, "task/a", earl::Reactivation::restart};
  Coordinator coordinator{kTables, kLinkNames};
  // the receiving ends: task/a's command output and the manipulators' status outputs are not
  // connected; their node loops publish what they send
  CommandLink inA, inB;
  StatusLink statusA, statusB;
  std::uint64_t sentCommand = 0, sentA = 0, sentB = 0;
  std::uint64_t lateStopAck = 0, heldStopA = 0;  // --late-stop-ack
  std::uint64_t slowAcks = 0, heldB = 0;  // --slow-acks
  Command_ lastCommandA{};

  System() noexcept {
    manipA.command.connect(inA);
    manipB.command.connect(inB);
    task.status.connect(statusA);
    task.status.connect(statusB);
    manipA.joinAgent(*memberA.slot(), true);
    manipB.joinAgent(*memberB.slot(), true);
    memberTask.sends(0);
    memberTask.sends(1);
    memberTask.receives(2, statusA);
    memberTask.receives(3, statusB);
    memberA.receives(0, inA);
    memberA.sends(2);
    memberB.receives(1, inB);
    memberB.sends(3);
    task.coordinate(coordinator, kStateConfiguration);
    coordinator.setTransport(&System::broadcast, this);
    const auto initial = static_cast<std::size_t>(kStateConfiguration[Task::tables().initial]);
    coordinator.start(initial);
    for (Member* m : {&memberA, &memberB, &memberTask}) m->start(initial);
  }

  static void broadcast(void* self, const Command_& command) noexcept {
    System& s = *static_cast<System*>(self);
    s.net.commands[0].push(command);
    s.net.commands[1].push(command);
    s.memberTask.command(command);  // the coordinator's own node
  }

  void nodeA(earl::Component::Clock::time_point now) noexcept {
    Command_ c;
    while (net.commands[0].pop(c)) {
      memberA.command(c);
      lastCommandA = c;
      heldStopA = 0;
    }
    Command value;
    while (net.toA.pop(value)) memberA.deliver(0, inA, value);
    Ack ack;
    const bool holds = lastCommandA.round == earl::SwitchRound::stop && !lastCommandA.forced && heldStopA++ < lateStopAck;
    if (!holds && memberA.boundary(ack)) net.acks[0].push(ack);
    if (manipA.ready(now)) manipA.updateHook();
    if (manipA.status.sent() != sentA) {
      sentA = manipA.status.sent();
      if (memberA.admit(2)) {
        net.fromA.push(manipA.status.msg());
        memberA.sent(2);
      }
    }
  }

  void nodeB(earl::Component::Clock::time_point now) noexcept {
    Command_ c;
    while (net.commands[1].pop(c)) {
      memberB.command(c);
      heldB = 0;
    }
    Command value;
    while (net.toB.pop(value)) memberB.deliver(1, inB, value);
    Ack ack;
    if (heldB++ >= slowAcks && memberB.boundary(ack)) net.acks[1].push(ack);
    if (manipB.ready(now)) manipB.updateHook();
    if (manipB.status.sent() != sentB) {
      sentB = manipB.status.sent();
      if (memberB.admit(3)) {
        net.fromB.push(manipB.status.msg());
        memberB.sent(3);
      }
    }
  }

  void nodeTask(earl::Component::Clock::time_point now) noexcept {
    Ack ack;
    for (std::size_t n = 0; n + 1 < kNodes; ++n) {
      while (net.acks[n].pop(ack)) coordinator.ack(ack);
    }
    Status status;
    while (net.fromA.pop(status)) memberTask.deliver(2, statusA, status);
    while (net.fromB.pop(status)) memberTask.deliver(3, statusB, status);
    if (memberTask.boundary(ack)) coordinator.ack(ack);
    if (task.ready(now)) task.updateHook();
    if (task.command.sent() != sentCommand) {
      sentCommand = task.command.sent();
      if (memberTask.admit(0)) {
        net.toA.push(task.command.msg());
        memberTask.sent(0);
      }
      if (memberTask.admit(1)) {
        net.toB.push(task.command.msg());
        memberTask.sent(1);
      }
    }
  }

  void setObserver(earl::SwitchObserver* o) noexcept {
    task.setObserver(o);
    manipA.setObserver(o);
    manipB.setObserver(o);
    coordinator.setObserver(o);
  }
};

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
    if (next_ != nullptr) next_->undelivered(link, count);
  }
  std::atomic<std::uint64_t> overflows{0};
  std::int64_t maxNs = 0;
  std::uint64_t forced = 0;  // switches the observer was told were forced
  std::uint64_t maxCycles = 0;

 private:
  earl::SwitchObserver* next_;
};

System& theSystem() {
  static System system;
  return system;
}

/// A node's own thread: its loop every ``period``, sleeping between (no busy polling).
template <class Step>
void runNode(Step step, std::chrono::nanoseconds period, const std::atomic<bool>& stop) {
  auto next = std::chrono::steady_clock::now();
  while (!stop.load(std::memory_order_acquire)) {
    step(earl::Component::Clock::now());
    next += period;
    std::this_thread::sleep_until(next);
  }
}

int usage(const char* program) {
  std::fprintf(stderr,
               "usage: %s (--cycles N | --threaded) [--switches S] [--per P] [--timeout-ms T] [--late-stop-ack L]"
               " [--slow-acks K] [--quiet]\n",
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
    } else if (std::strcmp(argv[i], "--late-stop-ack") == 0 && i + 1 < argc) {
      theSystem().lateStopAck = std::strtoull(argv[++i], nullptr, 10);
    } else if (std::strcmp(argv[i], "--slow-acks") == 0 && i + 1 < argc) {
      theSystem().slowAcks = std::strtoull(argv[++i], nullptr, 10);
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
  system.setObserver(&tally);
  std::uint64_t counted = 0;
  if (threaded) {
    system.task.setPeriod(std::chrono::microseconds(500));
    system.manipA.setPeriod(std::chrono::microseconds(250));
    system.manipB.setPeriod(std::chrono::microseconds(250));
    std::atomic<bool> stop{false};
    system.task.startHook();
    system.manipA.startHook();
    system.manipB.startHook();
    std::thread a([&] { runNode([&](auto now) { system.nodeA(now); }, std::chrono::microseconds(250), stop); });
    std::thread b([&] { runNode([&](auto now) { system.nodeB(now); }, std::chrono::microseconds(250), stop); });
    std::thread t([&] { runNode([&](auto now) { system.nodeTask(now); }, std::chrono::microseconds(500), stop); });
    const std::uint64_t before = allocations.load();
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!system.task.done.load(std::memory_order_acquire) && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the last manipulator empties its queue
    counted = allocations.load() - before;
    stop.store(true, std::memory_order_release);
    a.join();
    b.join();
    t.join();
  } else {
    system.coordinator.countCycles(true);
    const std::chrono::nanoseconds period = std::chrono::milliseconds(1);
    for (earl::Component* c : std::array<earl::Component*, 3>{&system.task, &system.manipA, &system.manipB}) {
      c->setPeriod(period);
      c->startHook();
    }
    const std::uint64_t before = allocations.load();
    for (std::uint64_t cycle = 0; cycle < cycles; ++cycle) {
      const earl::Component::Clock::time_point now(period * static_cast<std::int64_t>(cycle));
      system.nodeTask(now);
      system.nodeA(now);
      system.nodeB(now);
    }
    counted = allocations.load() - before;
  }

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
  const Coordinator& sw = system.coordinator;
  std::printf(
      "summary sent %" PRIu64 " received %" PRIu64 " lost %" PRIu64 " duplicates %" PRIu64 " misrouted %" PRIu64
      " out_of_order %" PRIu64 " overlaps %" PRIu64 " undelivered %" PRIu64 " overflows %" PRIu64 " switches %" PRIu64
      " timeouts %" PRIu64 " forced %" PRIu64 " max_latency_ns %" PRId64 " max_latency_cycles %" PRIu64 " restarts_a %" PRIu64 " restarts_b %" PRIu64
      " statuses %s dropped %" PRIu64 " allocations %" PRIu64 "\n",
      task.seq, received, lost, duplicates, misrouted, system.manipA.outOfOrder + system.manipB.outOfOrder,
      system.manipA.overlaps + system.manipB.overlaps, sw.undelivered(), overflows, sw.switches(), sw.timeouts(), tally.forced,
      tally.maxNs, tally.maxCycles, system.manipA.restarts, system.manipB.restarts, task.statuses > 0 ? "yes" : "no",
      dropped.load(), counted);
  return 0;
}
