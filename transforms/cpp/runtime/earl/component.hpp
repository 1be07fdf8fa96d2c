// earl runtime: the component base (an Orocos RTT TaskContext in miniature) and observers.
// Part of earl-m2t's C++ target; header-only, C++17.
#pragma once

#include <chrono>
#include <cstdint>

namespace earl {

class Component;

/// Told about every state a subsystem enters: the initial one (``from`` and ``via`` are
/// nullptr) and every transition taken, self-transitions included. For tracing and tests;
/// it runs in the subsystem's own thread.
class Observer {
 public:
  virtual ~Observer() = default;
  virtual void stateChanged(const Component& component, const char* from, const char* to,
                            const char* via, std::uint64_t step) noexcept = 0;
};

/// A periodic activity: startHook() once, updateHook() every period, stopHook() at the end.
class Component {
 public:
  explicit Component(const char* name) noexcept : name_(name) {}
  virtual ~Component() = default;
  Component(const Component&) = delete;
  Component& operator=(const Component&) = delete;

  const char* name() const noexcept { return name_; }
  virtual void startHook() noexcept {}
  virtual void updateHook() noexcept = 0;
  virtual void stopHook() noexcept {}

  std::chrono::nanoseconds period() const noexcept { return period_; }
  void setPeriod(std::chrono::nanoseconds period) noexcept { period_ = period; }
  void setObserver(Observer* observer) noexcept { observer_ = observer; }

 protected:
  Observer* observer() const noexcept { return observer_; }

 private:
  const char* name_;
  std::chrono::nanoseconds period_{std::chrono::milliseconds(1)};
  Observer* observer_ = nullptr;
};

}  // namespace earl
