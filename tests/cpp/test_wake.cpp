// Test of the threaded runner's wake-ups (transforms/cpp/runtime/earl/runner.hpp, wake.hpp):
//   * an event-driven subsystem wakes on a write into its obligatory input, well within its
//     timeout (no iteration runs on a timeout while values come), and never runs an
//     iteration without its obligatory input outside a timeout;
//   * a subsystem whose obligatory input never comes runs at its timeout;
//   * stop() returns promptly although every thread sleeps without a near deadline, and
//     every thread is asleep (not polling) before it;
//   * a value delivered into an input that is not obligatory in the state does not wake the
//     waiting thread (its context switches stay flat), a value into the obligatory one does;
//     the same reader told that every input wakes it is woken by each (the control).
// Built and run by tests/test_wake_runtime.py; prints "ok" and exits 0.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <array>
#include <dirent.h>
#include <sys/syscall.h>
#include <unistd.h>
#include <string>
#include <thread>

#include "earl/earl.hpp"

namespace {

int failures = 0;

void expect(bool ok, const char* what, int line) {
  if (!ok) {
    std::printf("FAIL line %d: %s\n", line, what);
    ++failures;
  }
}
#define EXPECT(x) expect((x), #x, __LINE__)

using Clock = earl::Component::Clock;

/// One state activated by the obligatory input ``in`` (timeout in ns; -1: none).
template <std::int64_t TimeoutNs>
class Reader final : public earl::Subsystem<Reader<TimeoutNs>> {
  using Base = earl::Subsystem<Reader<TimeoutNs>>;

 public:
  Reader() noexcept : Base("reader", tables()) { in.setWake(this->wake()); }
  earl::InputPort<std::int64_t> in;
  std::atomic<std::uint64_t> withData{0};
  std::atomic<std::uint64_t> woken_before_data{0};  // ran without the input and not on a timeout

  void updateHook() noexcept override {
    if (in.ready()) {
      withData.fetch_add(1);
    } else if (this->steps() > 0 && this->timeouts() == lastTimeouts_) {
      woken_before_data.fetch_add(1);
    }
    lastTimeouts_ = this->timeouts();
    Base::updateHook();
  }

  void send() noexcept {}
  void receive() noexcept { in.receive(); }
  bool obligatory() const noexcept { return in.ready(); }
  bool never() const noexcept { return false; }

  static const earl::FsmTables<Reader>& tables() noexcept {
    static const earl::BehaviourDef<Reader> behaviours[] = {
        {"a/bb", nullptr, 0, &Reader::send, &Reader::receive, &Reader::never, &Reader::never},
    };
    static const earl::StateDef states[] = {{"A", 0}};
    static const earl::ActivationDef<Reader> activations[] = {{&Reader::obligatory, 0, TimeoutNs, TimeoutNs}};
    static const earl::FsmTables<Reader> t{states, 1, behaviours, 1, nullptr, 0, 0, activations};
    return t;
  }

 private:
  std::uint64_t lastTimeouts_ = 0;
};

/// One state activated by ``in`` alone; ``side`` is read when it has a value. ``WakeInputs``:
/// the state's wake mask (bit 0 ``in``, bit 1 ``side``).
template <std::uint64_t WakeInputs>
class TwoInputs final : public earl::Subsystem<TwoInputs<WakeInputs>> {
  using Base = earl::Subsystem<TwoInputs<WakeInputs>>;

 public:
  TwoInputs() noexcept : Base("two inputs", tables()) {
    in.setWake(this->wake(), earl::Wake::inputBit(0));
    side.setWake(this->wake(), earl::Wake::inputBit(1));
  }
  earl::InputPort<std::int64_t> in;
  earl::InputPort<std::int64_t> side;

  void send() noexcept {}
  void receive() noexcept {
    in.receive();
    side.receive();
  }
  bool obligatory() const noexcept { return in.ready(); }
  bool never() const noexcept { return false; }

  static const earl::FsmTables<TwoInputs>& tables() noexcept {
    static const earl::BehaviourDef<TwoInputs> behaviours[] = {
        {"a/bb", nullptr, 0, &TwoInputs::send, &TwoInputs::receive, &TwoInputs::never, &TwoInputs::never},
    };
    static const earl::StateDef states[] = {{"A", 0}};
    static const earl::ActivationDef<TwoInputs> activations[] = {{&TwoInputs::obligatory, 0, -1, -1, WakeInputs}};
    static const earl::FsmTables<TwoInputs> t{states, 1, behaviours, 1, nullptr, 0, 0, activations};
    return t;
  }
};

/// A periodic component that counts its iterations.
class Ticker final : public earl::Component {
 public:
  Ticker() noexcept : earl::Component("ticker") {}
  void updateHook() noexcept override { ticks.fetch_add(1); }
  std::atomic<std::uint64_t> ticks{0};
};

void wakes_on_data() {
  constexpr std::uint64_t kWrites = 300;
  Reader<500'000'000> reader;  // timeout 500 ms: values come every 2 ms
  earl::Channel<std::int64_t> link;
  reader.in.connect(link);
  std::array<earl::Component*, 1> components{&reader};
  earl::ThreadedRunner<1> runner(components);
  EXPECT(runner.start());
  std::this_thread::sleep_for(std::chrono::milliseconds(20));  // the first iteration has run
  const std::uint64_t first = reader.steps();
  for (std::uint64_t i = 0; i < kWrites; ++i) {
    link.write(static_cast<std::int64_t>(i));
    // the next value only once this one was taken: each write needs a wake-up of its own
    const Clock::time_point limit = Clock::now() + std::chrono::milliseconds(400);
    while (link.fresh() && Clock::now() < limit) std::this_thread::sleep_for(std::chrono::microseconds(200));
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  runner.stop();
  EXPECT(first == 1);
  EXPECT(reader.withData.load() == kWrites);
  EXPECT(reader.in.received() == kWrites);
  EXPECT(reader.timeouts() == 0);  // every value woke it before its timeout
  EXPECT(reader.woken_before_data.load() == 0);
  EXPECT(reader.steps() == kWrites + 1);
  if (reader.steps() != kWrites + 1 || reader.timeouts() != 0) {
    std::printf("steps %llu, timeouts %llu, with data %llu\n", static_cast<unsigned long long>(reader.steps()),
                static_cast<unsigned long long>(reader.timeouts()),
                static_cast<unsigned long long>(reader.withData.load()));
  }
}

void runs_at_its_timeout() {
  Reader<20'000'000> reader;  // nothing ever comes: an iteration every 20 ms
  std::array<earl::Component*, 1> components{&reader};
  earl::ThreadedRunner<1> runner(components);
  const Clock::time_point start = Clock::now();
  EXPECT(runner.start());
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  runner.stop();
  const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
  const auto timeouts = static_cast<double>(reader.timeouts());
  // never sooner than the timeout (at most elapsed / 20 ms), and not lost either (loose
  // lower bound: the machine may be loaded)
  EXPECT(timeouts <= elapsed / 0.020 + 1.0);
  EXPECT(timeouts >= 5.0);
  EXPECT(reader.steps() == reader.timeouts() + 1);
  EXPECT(reader.woken_before_data.load() == 0);
}

/// The state letter of every thread of this process but the calling one.
std::string otherThreadStates() {
  std::string states;
  const long self = static_cast<long>(syscall(SYS_gettid));
  DIR* dir = opendir("/proc/self/task");
  if (dir == nullptr) return "?";
  while (dirent* entry = readdir(dir)) {
    if (entry->d_name[0] == '.') continue;
    if (std::strtol(entry->d_name, nullptr, 10) == self) continue;
    char path[300];
    std::snprintf(path, sizeof path, "/proc/self/task/%s/stat", entry->d_name);
    FILE* f = std::fopen(path, "r");
    if (f == nullptr) continue;
    char line[512] = {};
    const bool read = std::fgets(line, sizeof line, f) != nullptr;
    std::fclose(f);
    const char* paren = read ? std::strrchr(line, ')') : nullptr;
    if (paren != nullptr && paren[1] == ' ') states += paren[2];
  }
  closedir(dir);
  return states;
}

void stop_is_prompt_and_threads_sleep() {
  Reader<-1> waiting;  // no timeout: sleeps until a value or stop()
  Ticker slow;
  slow.setPeriod(std::chrono::seconds(30));  // sleeps 30 s between iterations
  std::array<earl::Component*, 2> components{&waiting, &slow};
  earl::ThreadedRunner<2> runner(components);
  EXPECT(runner.start());
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const std::string states = otherThreadStates();
  EXPECT(states == "SS");  // both asleep, neither running nor runnable
  if (states != "SS") std::printf("thread states: %s\n", states.c_str());
  const std::uint32_t before = waiting.wake().sequence();
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT(waiting.wake().sequence() == before);
  EXPECT(waiting.steps() == 1 && slow.ticks.load() == 1);
  const Clock::time_point stopping = Clock::now();
  runner.stop();
  const double took = std::chrono::duration<double>(Clock::now() - stopping).count();
  EXPECT(took < 5.0);  // not the 30 s period nor forever
}

/// Voluntary context switches of the one thread of this process other than the caller.
long otherThreadSwitches() {
  const long self = static_cast<long>(syscall(SYS_gettid));
  long found = -1;
  DIR* dir = opendir("/proc/self/task");
  if (dir == nullptr) return -1;
  while (dirent* entry = readdir(dir)) {
    if (entry->d_name[0] == '.' || std::strtol(entry->d_name, nullptr, 10) == self) continue;
    char path[300];
    std::snprintf(path, sizeof path, "/proc/self/task/%s/status", entry->d_name);
    FILE* f = std::fopen(path, "r");
    if (f == nullptr) continue;
    char line[256];
    while (std::fgets(line, sizeof line, f) != nullptr) {
      if (std::strncmp(line, "voluntary_ctxt_switches:", 24) == 0) found = std::strtol(line + 24, nullptr, 10);
    }
    std::fclose(f);
  }
  closedir(dir);
  return found;
}

/// Writes ``count`` values into ``side`` 1 ms apart while the reader waits for ``in``: how
/// many times the reader's thread was switched out meanwhile (each wake-up is one).
long switchesWhileSideValuesCome(earl::Channel<std::int64_t>& side, int count) {
  const long before = otherThreadSwitches();
  for (int i = 0; i < count; ++i) {
    side.write(i);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return otherThreadSwitches() - before;
}

void wakes_only_on_obligatory_inputs() {
  constexpr int kSideValues = 200;
  TwoInputs<0x1u> reader;  // woken by ``in`` only
  earl::Channel<std::int64_t> in, side;
  reader.in.connect(in);
  reader.side.connect(side);
  std::array<earl::Component*, 1> components{&reader};
  earl::ThreadedRunner<1> runner(components);
  EXPECT(runner.start());
  std::this_thread::sleep_for(std::chrono::milliseconds(20));  // the first iteration has run
  const long quiet = switchesWhileSideValuesCome(side, kSideValues);
  EXPECT(quiet >= 0 && quiet < kSideValues / 10);
  EXPECT(reader.steps() == 1);
  in.write(7);  // the obligatory input: one iteration, which also reads the side value
  const Clock::time_point limit = Clock::now() + std::chrono::seconds(2);
  while (reader.steps() < 2 && Clock::now() < limit) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT(reader.steps() == 2);
  EXPECT(reader.side.received() == 1);
  runner.stop();

  TwoInputs<earl::Wake::kAnyInput> control;  // every delivery wakes it (and it sleeps again)
  earl::Channel<std::int64_t> in2, side2;
  control.in.connect(in2);
  control.side.connect(side2);
  std::array<earl::Component*, 1> controls{&control};
  earl::ThreadedRunner<1> controlRunner(controls);
  EXPECT(controlRunner.start());
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const long woken = switchesWhileSideValuesCome(side2, kSideValues);
  EXPECT(woken >= kSideValues / 2);
  EXPECT(control.steps() == 1);
  controlRunner.stop();
  if (quiet >= kSideValues / 10 || woken < kSideValues / 2) {
    std::printf("context switches while %d side values came: %ld (obligatory only), %ld (every input)\n",
                kSideValues, quiet, woken);
  }
}

}  // namespace

int main() {
  wakes_on_data();
  runs_at_its_timeout();
  stop_is_prompt_and_threads_sleep();
  wakes_only_on_obligatory_inputs();
  if (failures != 0) return EXIT_FAILURE;
  std::printf("ok\n");
  return EXIT_SUCCESS;
}
