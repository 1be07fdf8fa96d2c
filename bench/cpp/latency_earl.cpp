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
#include "latency_reader.hpp"

using latency::Reader;

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
  latency::handOff(reader, options.samples, [&link](std::int64_t t) { link.write(t); });
  runner.stop();
  latency::report(EARL_WAKE_POLL ? "earl polling 100 us" : "earl wake word", reader.samples, reader.empty,
                  "iterations_without_data");
  return 0;
}
