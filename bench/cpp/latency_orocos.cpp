// bench/latency.py, the Orocos deployment: the reader is an RTT TaskContext doing what the
// generated master of an event-driven subsystem does (transforms/orocos/templates/
// components.cpp.j2): its input port copies each new value into the earl subsystem's channel,
// asks the subsystem's ready(), and steps it; the subsystem is latency_earl.cpp's (one state,
// its obligatory input ``in``, no timeout). The writer (the main thread) writes the current time
// into an RTT output port connected to the reader's input (a data connection, as
// deploy/system.ops makes them); the subsystem's updateHook() records the time since.
//
// Built as is, the reader's port is an event port and its activity a FileDescriptorActivity
// whose timeout is the subsystem's next deadline (the generated master now); with
// -DEARL_OROCOS_POLL=1 the port is a plain one and the activity periodic at 0.2 ms, looking at
// ready() every period (the generated master before). --idle S: nothing is written.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>
#include <vector>

#include <rtt/Activity.hpp>
#include <rtt/ConnPolicy.hpp>
#include <rtt/InputPort.hpp>
#include <rtt/OutputPort.hpp>
#include <rtt/TaskContext.hpp>
#include <rtt/extras/FileDescriptorActivity.hpp>
#include <rtt/os/main.h>

#include "earl/earl.hpp"
#include "latency.hpp"
#include "latency_reader.hpp"

#ifndef EARL_OROCOS_POLL
#define EARL_OROCOS_POLL 0
#endif

namespace {

using latency::Reader;

/// The master: the RTT side of the generated one, around the subsystem.
class Master final : public RTT::TaskContext {
 public:
  explicit Master(Reader& subsystem) : RTT::TaskContext("reader"), subsystem_(subsystem) {
    subsystem_.in.connect(channel_);
#if EARL_OROCOS_POLL
    ports()->addPort("in", port_);
#else
    ports()->addEventPort("in", port_);
#endif
  }

  bool startHook() override {
    subsystem_.startHook();
#if !EARL_OROCOS_POLL
    wakeup_ = dynamic_cast<RTT::extras::FileDescriptorActivityInterface*>(getActivity());
    if (wakeup_ == nullptr) return false;
    wakeup_->setTimeout_us(1);  // the first iteration at once
#endif
    return true;
  }

  void updateHook() override {
    if (port_.read(sample_, false) == RTT::NewData) channel_.write(sample_);
    const earl::Component::Clock::time_point now = earl::Component::Clock::now();
    if (!subsystem_.ready(now)) {
#if !EARL_OROCOS_POLL
      bool onData = false;
      const earl::Component::Clock::time_point deadline = subsystem_.nextDeadline(now, onData);
      if (deadline == earl::Component::Clock::time_point::max()) {
        wakeup_->setTimeout_us(0);  // no timeout: only data
      } else {
        const auto us = std::chrono::duration_cast<std::chrono::microseconds>(deadline - now).count() + 1;
        wakeup_->setTimeout_us(static_cast<int>(us < 1 ? 1 : us));
      }
#endif
      return;
    }
#if !EARL_OROCOS_POLL
    wakeup_->setTimeout_us(1);  // after this iteration, look again at once
#endif
    subsystem_.updateHook();
  }

 private:
  Reader& subsystem_;
  earl::Channel<std::int64_t> channel_;
  RTT::InputPort<std::int64_t> port_;
  std::int64_t sample_ = 0;
#if !EARL_OROCOS_POLL
  RTT::extras::FileDescriptorActivityInterface* wakeup_ = nullptr;
#endif
};

}  // namespace

int ORO_main(int argc, char** argv) {
  const latency::Options options = latency::parse(argc, argv);
  static Reader reader(static_cast<std::size_t>(options.samples));
  Master master(reader);
#if EARL_OROCOS_POLL
  master.setActivity(new RTT::Activity(ORO_SCHED_OTHER, RTT::os::LowestPriority, 0.0002));
#else
  master.setActivity(new RTT::extras::FileDescriptorActivity(ORO_SCHED_OTHER, RTT::os::LowestPriority));
#endif
  RTT::OutputPort<std::int64_t> out("out");
  if (!out.connectTo(master.ports()->getPort("in"), RTT::ConnPolicy::data())) return 3;
  if (!master.configure() || !master.start()) return 3;
  if (options.idle > 0.0) {
    std::this_thread::sleep_for(std::chrono::duration<double>(options.idle));
    master.stop();
    std::printf("{\"idle_s\": %.3f, \"iterations\": %llu}\n", options.idle,
                static_cast<unsigned long long>(reader.steps()));
    return 0;
  }
  latency::handOff(reader, options.samples, [&out](std::int64_t t) { out.write(t); });
  master.stop();
  latency::report(EARL_OROCOS_POLL ? "orocos polling 0.2 ms" : "orocos event port", reader.samples, reader.empty,
                  "iterations_without_data");
  return 0;
}
