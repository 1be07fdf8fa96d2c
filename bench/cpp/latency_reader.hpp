// What bench/latency.py's earl and Orocos programs share: the reader, an event-driven earl
// subsystem with one state whose obligatory input ``in`` has no timeout and no minimal period.
// Its updateHook() records, at its start, how long ago the value it takes was written.
#pragma once

#include <atomic>
#include <chrono>
#include <thread>
#include <cstdint>
#include <vector>

#include "earl/earl.hpp"
#include "latency.hpp"

namespace latency {

class Reader final : public earl::Subsystem<Reader> {
 public:
  explicit Reader(std::size_t capacity) : earl::Subsystem<Reader>("bench/reader", tables()) {
    in.setWake(wake(), earl::Wake::inputBit(0));
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

/// The writer's side of the bench: ``samples`` hand-offs, each ``write(now)`` into the reader's
/// input, then waiting until the reader took it and pausing (Pauses).
template <class Write>
void handOff(Reader& reader, long samples, Write&& write) {
  while (reader.taken.load() < 1) std::this_thread::sleep_for(std::chrono::milliseconds(1));  // first iteration
  Pauses pauses;
  for (long i = 0; i < samples; ++i) {
    const std::uint64_t before = reader.taken.load(std::memory_order_acquire);
    const std::int64_t t = nowNs();
    reader.written.store(t, std::memory_order_release);
    write(t);
    while (reader.taken.load(std::memory_order_acquire) == before) std::this_thread::sleep_for(std::chrono::microseconds(20));
    std::this_thread::sleep_for(pauses.next());
  }
}

}  // namespace latency
