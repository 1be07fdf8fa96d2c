// bench/latency.py, the earl runtime: an event-driven subsystem (one state, its obligatory
// input ``in`` fed by an earl::Channel, no timeout, no minimal period) run by
// earl::ThreadedRunner. The writer (the main thread) writes the current time into the channel;
// the subsystem's updateHook() records the time since, at its start. Built as is (the reader
// sleeps on its wake word) and with -DEARL_WAKE_POLL=1 (ready() looked at every 100 us).
// --idle S: nothing is written, the reader waits S seconds (the bench reads its CPU time).
#include <array>
#include <atomic>
#include <thread>
#include <vector>

#include "earl/earl.hpp"
#include "latency.hpp"

namespace {

class Reader final : public earl::Subsystem<Reader> {
 public:
  explicit Reader(std::size_t capacity) : earl::Subsystem<Reader>("bench/reader", tables()) {
    in.setWake(wake());
    samples.reserve(capacity);
  }
  earl::InputPort<std::int64_t> in;
  std::vector<std::int64_t> samples;  // reserved: no allocation in a cycle
  std::atomic<std::int64_t> written{0};
  std::atomic<std::uint64_t> taken{0};
  std::uint64_t empty = 0;  // iterations that found no value (there should be none)

  void updateHook() noexcept override {
    const std::int64_t start = latency::nowNs();
    if (in.ready()) {
      if (samples.size() < samples.capacity()) samples.push_back(start - written.load(std::memory_order_acquire));
    } else if (steps() > 0) {
      ++empty;
    }
    earl::Subsystem<Reader>::updateHook();
    taken.fetch_add(1, std::memory_order_release);
  }

  void send() noexcept {}
  void receive() noexcept { in.receive(); }
  bool obligatory() const noexcept { return in.ready(); }
  bool never() const noexcept { return false; }

  static const earl::FsmTables<Reader>& tables() noexcept {
    static const earl::BehaviourDef<Reader> behaviours[] = {
        {"wait/bb", nullptr, 0, &Reader::send, &Reader::receive, &Reader::never, &Reader::never},
    };
    static const earl::StateDef states[] = {{"wait", 0}};
    static const earl::ActivationDef<Reader> activations[] = {{&Reader::obligatory, 0, -1, -1}};
    static const earl::FsmTables<Reader> t{states, 1, behaviours, 1, nullptr, 0, 0, activations};
    return t;
  }
};

}  // namespace

int main(int argc, char** argv) {
  const latency::Options options = latency::parse(argc, argv);
  static Reader reader(static_cast<std::size_t>(options.samples));
  earl::Channel<std::int64_t> link;
  reader.in.connect(link);
  std::array<earl::Component*, 1> components{&reader};
  earl::ThreadedRunner<1> runner(components);
  if (!runner.start()) return 3;
  if (options.idle > 0.0) {
    std::this_thread::sleep_for(std::chrono::duration<double>(options.idle));
    runner.stop();
    std::printf("{\"idle_s\": %.3f, \"iterations\": %llu}\n", options.idle,
                static_cast<unsigned long long>(reader.steps()));
    return 0;
  }
  while (reader.taken.load() < 1) std::this_thread::sleep_for(std::chrono::milliseconds(1));  // first iteration
  latency::Pauses pauses;
  for (long i = 0; i < options.samples; ++i) {
    const std::uint64_t before = reader.taken.load(std::memory_order_acquire);
    const std::int64_t t = latency::nowNs();
    reader.written.store(t, std::memory_order_release);
    link.write(t);
    while (reader.taken.load(std::memory_order_acquire) == before) std::this_thread::sleep_for(std::chrono::microseconds(20));
    std::this_thread::sleep_for(pauses.next());
  }
  runner.stop();
  latency::report(EARL_WAKE_POLL ? "earl polling 100 us" : "earl wake word", reader.samples, reader.empty,
                  "iterations_without_data");
  return 0;
}
