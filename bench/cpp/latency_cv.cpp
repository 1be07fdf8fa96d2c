// bench/latency.py's baseline: the same hand-off written by hand with a mutex and a
// std::condition_variable. The reader thread waits on the condition variable; the writer
// (the main thread) stores the current time under the mutex and notifies; the reader records
// the time since, as soon as it holds the lock again.
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "latency.hpp"

int main(int argc, char** argv) {
  const latency::Options options = latency::parse(argc, argv);
  std::mutex mutex;
  std::condition_variable changed;
  bool waiting = false;
  bool stop = false;
  std::int64_t written = 0;
  std::uint64_t taken = 0;
  std::vector<std::int64_t> samples;
  samples.reserve(static_cast<std::size_t>(options.samples));
  std::thread reader([&] {
    std::unique_lock<std::mutex> lock(mutex);
    for (;;) {
      changed.wait(lock, [&] { return waiting || stop; });
      if (stop) return;
      samples.push_back(latency::nowNs() - written);
      waiting = false;
      ++taken;
    }
  });
  latency::Pauses pauses;
  for (long i = 0; i < options.samples; ++i) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      written = latency::nowNs();
      waiting = true;
    }
    changed.notify_one();
    for (;;) {
      std::this_thread::sleep_for(std::chrono::microseconds(20));
      std::lock_guard<std::mutex> lock(mutex);
      if (!waiting) break;
    }
    std::this_thread::sleep_for(pauses.next());
  }
  {
    std::lock_guard<std::mutex> lock(mutex);
    stop = true;
  }
  changed.notify_one();
  reader.join();
  latency::report("std::condition_variable", samples, taken, "handoffs");
  return 0;
}
