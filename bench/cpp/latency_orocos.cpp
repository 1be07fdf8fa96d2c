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
// ready() every period (the generated master before). With -DEARL_OROCOS_ACTIVITY=1 the event
// port triggers RTT's plain non-periodic Activity (a semaphore post; it has no timeout, so it
// could not wake at a deadline: for comparison only). With -DEARL_OROCOS_WAKE=1 the activity is
// earl::rtt::WakeActivity (transforms/orocos/runtime/earl/rtt_wake_activity.hpp): its thread
// sleeps on an earl wake word (a futex) with the subsystem's next deadline, and a trigger is
// the word's notify. With -DEARL_OROCOS_WAKE=2 also the master's dataOnPortHook() (RTT runs it
// in the writer's thread) asks the activity for an update step at once (timeout()) instead of
// letting RTT queue the port and trigger a callback step that asks for it: one wake-up, one
// step. --idle S: nothing is written.
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
#ifndef EARL_OROCOS_ACTIVITY
#define EARL_OROCOS_ACTIVITY 0
#endif
#ifndef EARL_OROCOS_WAKE
#define EARL_OROCOS_WAKE 0
#endif
// the activity the master sets its next deadline on (none: polling, or the plain Activity)
#define EARL_OROCOS_FD (!EARL_OROCOS_POLL && !EARL_OROCOS_ACTIVITY && !EARL_OROCOS_WAKE)

#if EARL_OROCOS_WAKE
#include "earl/rtt_wake_activity.hpp"
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
#if EARL_OROCOS_FD
    wakeup_ = dynamic_cast<RTT::extras::FileDescriptorActivityInterface*>(getActivity());
    if (wakeup_ == nullptr) return false;
    wakeup_->setTimeout_us(1);  // the first iteration at once
#elif EARL_OROCOS_WAKE
    wakeup_ = dynamic_cast<earl::rtt::WakeActivity*>(getActivity());
    if (wakeup_ == nullptr) return false;
    wakeup_->wakeAt(earl::Component::Clock::now());  // the first iteration at once
#endif
    return true;
  }

#if EARL_OROCOS_WAKE == 2
  bool dataOnPortHook(RTT::base::PortInterface*) override {
    if (isRunning()) wakeup_->timeout();  // an update step, no port callback
    return false;
  }
#endif

  void updateHook() override {
    if (port_.read(sample_, false) == RTT::NewData) channel_.write(sample_);
    const earl::Component::Clock::time_point now = earl::Component::Clock::now();
    if (!subsystem_.ready(now)) {
#if EARL_OROCOS_WAKE
      bool onData = false;
      wakeup_->wakeAt(subsystem_.nextDeadline(now, onData));  // max(): only data
#elif EARL_OROCOS_FD
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
#if EARL_OROCOS_FD
    wakeup_->setTimeout_us(1);  // after this iteration, look again at once
#elif EARL_OROCOS_WAKE
    wakeup_->wakeAt(now);  // after this iteration, look again at once
#endif
    subsystem_.updateHook();
  }

 private:
  Reader& subsystem_;
  earl::Channel<std::int64_t> channel_;
  RTT::InputPort<std::int64_t> port_;
  std::int64_t sample_ = 0;
#if EARL_OROCOS_FD
  RTT::extras::FileDescriptorActivityInterface* wakeup_ = nullptr;
#elif EARL_OROCOS_WAKE
  earl::rtt::WakeActivity* wakeup_ = nullptr;
#endif
};

}  // namespace

int ORO_main(int argc, char** argv) {
  const latency::Options options = latency::parse(argc, argv);
  static Reader reader(static_cast<std::size_t>(options.samples));
  Master master(reader);
#if EARL_OROCOS_POLL
  master.setActivity(new RTT::Activity(ORO_SCHED_OTHER, RTT::os::LowestPriority, 0.0002));
#elif EARL_OROCOS_ACTIVITY
  master.setActivity(new RTT::Activity(ORO_SCHED_OTHER, RTT::os::LowestPriority));
#elif EARL_OROCOS_WAKE
  master.setActivity(new earl::rtt::WakeActivity(ORO_SCHED_OTHER, RTT::os::LowestPriority, 0, "reader"));
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
  const char* variant = EARL_OROCOS_POLL       ? "orocos polling 0.2 ms"
                        : EARL_OROCOS_ACTIVITY ? "orocos plain Activity"
                        : EARL_OROCOS_WAKE == 2 ? "orocos master (generated)"
                        : EARL_OROCOS_WAKE     ? "orocos wake act., no hook"
                                               : "orocos fd activity (before)";
  latency::report(variant, reader.samples, reader.empty, "iterations_without_data");
  return 0;
}
