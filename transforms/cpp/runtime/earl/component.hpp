// earl runtime: the component base (an Orocos RTT TaskContext in miniature) and observers.
// Part of earl-m2t's C++ target; header-only, C++17.
#pragma once

#include <chrono>
#include <cstdint>

#include "earl/wake.hpp"

namespace earl {

class Component;

/// What a pf that writes a non-finite number (NaN, +-inf) into an output buffer does:
/// ``error``: the pf fails and the value is not sent; ``report``: the value is reported (once
/// per pf and buffer until it is finite again) and sent.
enum class NonFinite : std::uint8_t { error, report };

/// Told about every state a subsystem enters: the initial one (``from`` and ``via`` are
/// nullptr) and every transition taken, self-transitions included. For tracing and tests;
/// it runs in the subsystem's own thread.
class Observer {
 public:
  virtual ~Observer() = default;
  virtual void stateChanged(const Component& component, const char* from, const char* to,
                            const char* via, std::uint64_t step) noexcept = 0;
  /// A queued Input Buffer was full: ``lost`` values sent to it since the last report were
  /// dropped (reported at the receive() that found them).
  virtual void overflowed(const Component& component, const char* buffer, std::uint64_t lost,
                          std::uint64_t step) noexcept {
    (void)component, (void)buffer, (void)lost, (void)step;
  }
  /// The pf ``pf`` failed for ``reason`` (its first failure since the state was entered;
  /// behaviourOk() is false until the subsystem enters a state).
  virtual void pfFailed(const Component& component, const char* pf, const char* reason,
                        std::uint64_t step) noexcept {
    (void)component, (void)pf, (void)reason, (void)step;
  }
  /// Under NonFinite::report: the pf ``pf`` wrote a non-finite number into ``buffer``, sent
  /// (told once until the value it writes there is finite again).
  virtual void nonFinite(const Component& component, const char* pf, const char* buffer,
                         std::uint64_t step) noexcept {
    (void)component, (void)pf, (void)buffer, (void)step;
  }
};

/// A periodic activity: startHook() once, updateHook() every period, stopHook() at the end.
/// An event-driven one (eventDriven(): FABRIC's buffer groups) runs updateHook() whenever
/// ready() says so instead of every period.
class Component {
 public:
  using Clock = std::chrono::steady_clock;

  explicit Component(const char* name) noexcept : name_(name) {}
  virtual ~Component() = default;
  Component(const Component&) = delete;
  Component& operator=(const Component&) = delete;

  const char* name() const noexcept { return name_; }
  virtual void startHook() noexcept {}
  virtual void updateHook() noexcept = 0;
  virtual void stopHook() noexcept {}
  virtual bool eventDriven() const noexcept { return false; }
  /// Whether the next iteration may run at ``now``; true for a periodic component.
  virtual bool ready(Clock::time_point now) noexcept {
    (void)now;
    return true;
  }
  /// When ready() may next hold without a delivery into an input, asked after ready() said
  /// no: the runner sleeps until then or until a value comes (Clock::time_point::max(): no
  /// deadline, only a value or a wake-up). ``onData`` false: a value cannot make it ready
  /// before the deadline (its minimal period), so deliveries need not wake it.
  virtual Clock::time_point nextDeadline(Clock::time_point now, bool& onData) noexcept {
    onData = false;
    return now;
  }
  /// Asked after nextDeadline() said ``onData``: the inputs (Wake::inputBit() of each) whose
  /// delivery can make ready() hold; a delivery into another one need not wake the thread.
  virtual std::uint64_t wakeInputs() const noexcept { return Wake::kAnyInput; }
  /// The wake word the channels into this component's inputs signal (earl/wake.hpp).
  Wake& wake() noexcept { return wake_; }

  std::chrono::nanoseconds period() const noexcept { return period_; }
  void setPeriod(std::chrono::nanoseconds period) noexcept { period_ = period; }
  void setObserver(Observer* observer) noexcept { observer_ = observer; }
  NonFinite nonFinite() const noexcept { return nonFinite_; }
  void setNonFinite(NonFinite policy) noexcept { nonFinite_ = policy; }

 protected:
  Observer* observer() const noexcept { return observer_; }

 private:
  const char* name_;
  std::chrono::nanoseconds period_{std::chrono::milliseconds(1)};
  Observer* observer_ = nullptr;
  NonFinite nonFinite_ = NonFinite::error;
  Wake wake_;
};

}  // namespace earl
