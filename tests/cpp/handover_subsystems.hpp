// The subsystems of the hand-over system of test_switch.cpp and test_switch_protocol.cpp:
// task/a.cs, the coordinator (states withA and withB naming the configurations useA and useB),
// sends numbered commands to manipA/a.cs or manipB/a.cs (the same class) over queued variable
// links and gets their status back over latest-value variable links. A manipulator receives
// one command per iteration in idle (quiescent); every fourth command sends it to work for a
// few iterations, in which it receives nothing, so commands wait in its queue; leaving() ends
// work early.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

#include "earl/earl.hpp"
#include "earl/switch.hpp"

namespace handover {

constexpr std::size_t kQueue = 128;
constexpr std::uint64_t kMaxSeq = 1u << 16;
constexpr std::uint64_t kWork = 2;  // iterations in work

struct Command {
  std::uint64_t seq = 0;
};
struct Status {
  std::uint64_t seq = 0;
  char who = '-';
};

using CommandLink = earl::VariableLink<earl::QueueChannel<Command, kQueue>>;
using StatusLink = earl::VariableLink<earl::Channel<Status>>;

struct Settings {
  std::uint64_t switches = 20;
  std::uint64_t per = 50;
  std::int64_t timeoutNs = 50'000'000;
};
inline Settings settings;

// ---------------------------------------------------------------- task/a.cs: the coordinator

class Task final : public earl::SwitchedSubsystem<Task> {
 public:
  Task() noexcept : earl::SwitchedSubsystem<Task>("task/a.cs", tables()) {}

  earl::OutputPort<Command, 2> command;
  earl::SwitchedInputPort<Status, 2> status;
  std::array<std::uint8_t, kMaxSeq> sentIn{};  // configuration (1 useA, 2 useB) each seq was sent in
  std::uint64_t seq = 0;
  std::uint64_t statuses = 0;
  std::atomic<bool> done{false};

  std::uint64_t total() const noexcept { return (settings.switches + 1) * settings.per; }

  void supervise() noexcept {
    fresh_ = seq < total();
    if (!fresh_) {
      done.store(true, std::memory_order_release);
      return;
    }
    command.msg().seq = ++seq;
    sentIn[seq] = static_cast<std::uint8_t>(currentState() + 1);
  }
  void send() noexcept {
    if (fresh_) command.send();
  }
  void receive() noexcept {
    if (status.receive()) ++statuses;
  }
  bool handOver() const noexcept { return iteration() >= settings.per && seq < total(); }
  bool never() const noexcept { return false; }
  bool always() const noexcept { return true; }
  void resetData(bool) noexcept {}
  void settleData() noexcept { status.settle(); }

  static const earl::FsmTables<Task>& tables() noexcept {
    static const earl::Action<Task> stage[] = {&Task::supervise};
    static const earl::StageDef<Task> stages[] = {{stage, 1}};
    static const earl::BehaviourDef<Task> behaviours[] = {
        {"supervise/bb", stages, 1, &Task::send, &Task::receive, &Task::handOver, &Task::never},
    };
    static const earl::StateDef states[] = {{"withA", 0}, {"withB", 0}};
    static const earl::TransitionDef<Task> transitions[] = {
        {"withA,withB/t", 0, 1, 0, &Task::always},
        {"withB,withA/t", 1, 0, 0, &Task::always},
    };
    static const earl::FsmTables<Task> t{states, 2, behaviours, 1, transitions, 2, 0, nullptr};
    return t;
  }

 private:
  bool fresh_ = false;
};

// ---------------------------------------------------------------- manipX/a.cs

class Manip final : public earl::SwitchedSubsystem<Manip> {
 public:
  Manip(const char* name, char who, const std::atomic<bool>& other, std::atomic<bool>& inside) noexcept
      : earl::SwitchedSubsystem<Manip>(name, tables(), kQuiescent), who_(who), other_(other), inside_(inside) {}

  earl::SwitchedInputPort<Command, 1, kQueue> command;
  earl::OutputPort<Status, 1> status;
  std::array<std::uint16_t, kMaxSeq> got{};  // times a pf ran on each seq (received for it)
  std::uint64_t received = 0, outOfOrder = 0, overlaps = 0, stale = 0, restarts = 0;
  std::uint64_t workIterations = 0;  // memory: kept by resume, reset by restart

  void report() noexcept {
    inside_.store(true, std::memory_order_seq_cst);
    if (pending_) {  // the command the last iteration received: this pf runs on it
      pending_ = false;
      const std::uint64_t s = command.msg().seq;
      if (s < kMaxSeq) ++got[s];
      if (s <= last_) ++outOfOrder;
      last_ = s;
      ++received;
    }
    if (other_.load(std::memory_order_seq_cst)) ++overlaps;  // both manipulators inside an iteration
    status.msg().who = who_;
    status.msg().seq = last_;
  }
  void work() noexcept {
    report();
    ++workIterations;
  }
  void send() noexcept { status.send(); }
  void receiveCommand() noexcept {
    if (command.receive()) pending_ = true;
    inside_.store(false, std::memory_order_seq_cst);
  }
  void receiveNothing() noexcept { inside_.store(false, std::memory_order_seq_cst); }
  bool toWork() const noexcept { return command.newData() && command.msg().seq % 4 == 0; }
  bool worked() const noexcept { return iteration() >= kWork || leaving(); }
  bool never() const noexcept { return false; }
  bool always() const noexcept { return true; }
  void settleData() noexcept { command.settle(); }
  void resetData(bool restart) noexcept {
    command.reset(restart);
    pending_ = false;  // dropped: the switch that stopped the agent counted it undelivered
    if (restart) {
      status.msg() = Status{};
      workIterations = 0;
      ++restarts;
    }
  }

  static const earl::FsmTables<Manip>& tables() noexcept {
    static const earl::Action<Manip> idleStage[] = {&Manip::report};
    static const earl::Action<Manip> workStage[] = {&Manip::work};
    static const earl::StageDef<Manip> idleStages[] = {{idleStage, 1}};
    static const earl::StageDef<Manip> workStages[] = {{workStage, 1}};
    static const earl::BehaviourDef<Manip> behaviours[] = {
        {"idle/bb", idleStages, 1, &Manip::send, &Manip::receiveCommand, &Manip::toWork, &Manip::never},
        {"work/bb", workStages, 1, &Manip::send, &Manip::receiveNothing, &Manip::worked, &Manip::never},
    };
    static const earl::StateDef states[] = {{"idle", 0}, {"work", 1}};
    static const earl::TransitionDef<Manip> transitions[] = {
        {"idle,work/t", 0, 1, 0, &Manip::always},
        {"work,idle/t", 1, 0, 0, &Manip::always},
    };
    static const earl::FsmTables<Manip> t{states, 2, behaviours, 2, transitions, 2, 0, nullptr};
    return t;
  }

 private:
  static constexpr bool kQuiescent[] = {true, false};
  char who_;
  const std::atomic<bool>& other_;
  std::atomic<bool>& inside_;
  std::uint64_t last_ = 0;
  bool pending_ = false;  // the last receiveCommand() took a command, for the next iteration's pf
};

}  // namespace handover
