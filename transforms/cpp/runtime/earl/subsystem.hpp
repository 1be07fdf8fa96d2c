// earl runtime: a subsystem's FSM and basic-behaviour loop (earl-metamodel.md section 2).
// Part of earl-m2t's C++ target; header-only, C++17.
//
// One updateHook() is one iteration of the current basic behaviour:
//   tf.execute()          stages in order, the pf of a stage in model order
//   tf.pf.ob.send()       the output buffers the tf's pf write
//   iterationNumber += 1
//   tf.pf.ib.receive()    the input buffers the tf's pf (and the state's conditions) read
//   if ec() || tc():      cfs := selectState()  (stays in cfs when no transition holds)
//
// Activation (FABRIC's buffer groups, earl-metamodel.md): a subsystem whose states have an
// ActivationDef is event-driven. Its next iteration is ready once minPeriod has passed since
// the previous one started and every obligatory input of the current state's group has a
// value waiting, or once the state's timeout (firstTimeout for the first iteration after
// entering the state, nextTimeout later) has passed since the wait began.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>

#include "earl/component.hpp"
#include "earl/health.hpp"

namespace earl {

using StateId = std::uint16_t;

template <class Self>
using Action = void (Self::*)() noexcept;
template <class Self>
using Guard = bool (Self::*)() const noexcept;

/// pf of one stage of a transition function, in model order.
template <class Self>
struct StageDef {
  const Action<Self>* functions;
  std::size_t count;
};

template <class Self>
struct BehaviourDef {
  const char* name;
  const StageDef<Self>* stages;  // stage 1 first
  std::size_t stageCount;
  Action<Self> send;     // tf.pf.ob.send()
  Action<Self> receive;  // tf.pf.ib.receive()
  Guard<Self> terminal;  // tc
  Guard<Self> error;     // ec
};

struct StateDef {
  const char* name;
  std::size_t behaviour;  // index into the behaviour table
};

/// When a subsystem runs an iteration in one state (FABRIC's buffer group of the state).
template <class Self>
struct ActivationDef {
  Guard<Self> obligatory;       // every obligatory input has a value waiting; nullptr: none
  std::int64_t minPeriodNs;     // < 0: the component's period
  std::int64_t firstTimeoutNs;  // < 0: no limit
  std::int64_t nextTimeoutNs;   // < 0: no limit
  std::uint64_t wakeInputs = Wake::kAnyInput;  // the obligatory inputs' bits (Wake::inputBit())
};

/// A transition; the table lists them in model order, which breaks priority ties.
template <class Self>
struct TransitionDef {
  const char* name;
  StateId source;
  StateId target;
  int priority;
  Guard<Self> condition;  // ic
};

template <class Self>
struct FsmTables {
  const StateDef* states;
  std::size_t stateCount;
  const BehaviourDef<Self>* behaviours;
  std::size_t behaviourCount;
  const TransitionDef<Self>* transitions;
  std::size_t transitionCount;
  StateId initial;
  const ActivationDef<Self>* activations;  // one per state; nullptr: periodic (EARL's default)
};

/// selectState(): among the transitions leaving ``current`` whose condition holds, the one
/// with the highest priority; ties go to the first in model order. nullptr when none holds.
template <class Self>
const TransitionDef<Self>* selectTransition(const Self& self, const TransitionDef<Self>* table,
                                            std::size_t count, StateId current) noexcept {
  const TransitionDef<Self>* best = nullptr;
  for (std::size_t i = 0; i < count; ++i) {
    const TransitionDef<Self>& t = table[i];
    if (t.source != current) continue;
    if (best != nullptr && t.priority <= best->priority) continue;
    if ((self.*t.condition)()) best = &t;
  }
  return best;
}

/// The base of every generated subsystem (CRTP): Self supplies the tables and the
/// member functions they point to.
template <class Self>
class Subsystem : public Component, public Health {
 public:
  Subsystem(const char* name, const FsmTables<Self>& tables) noexcept
      : Component(name), tables_(tables), current_(tables.initial) {}

  /// Enters the initial state (fsm.run(): cfs := ifs). Called by the first updateHook()
  /// when nobody called it before.
  void startHook() noexcept override {
    if (started_) return;
    started_ = true;
    enter(tables_.initial, nullptr);
  }

  bool eventDriven() const noexcept override { return tables_.activations != nullptr; }

  /// Whether the next iteration may run at ``now`` (see Activation above); the first call
  /// after an iteration starts the wait that the timeouts bound.
  bool ready(Clock::time_point now) noexcept override {
    if (tables_.activations == nullptr || !ran_) return take(now);
    const ActivationDef<Self>& a = tables_.activations[current_];
    if (!waiting_) {
      waiting_ = true;
      waitStart_ = now;
    }
    if (now < lastStart_ + activationGap(a)) return false;
    if (a.obligatory == nullptr) return take(now);
    const Self& self = static_cast<const Self&>(*this);
    if ((self.*a.obligatory)()) return take(now);
    const std::int64_t timeout = entered_ ? a.firstTimeoutNs : a.nextTimeoutNs;
    if (timeout >= 0 && now >= waitStart_ + std::chrono::nanoseconds(timeout)) {
      ++timeouts_;
      return take(now);
    }
    return false;
  }

  /// After ready() said no at ``now``: the end of the minimal period (no value can make it
  /// ready before), else the timeout of the wait (or none), waking on data meanwhile.
  Clock::time_point nextDeadline(Clock::time_point now, bool& onData) noexcept override {
    onData = false;
    if (tables_.activations == nullptr || !ran_) return now;
    const ActivationDef<Self>& a = tables_.activations[current_];
    const Clock::time_point earliest = lastStart_ + activationGap(a);
    if (now < earliest) return earliest;
    if (a.obligatory == nullptr) return now;
    onData = true;
    const std::int64_t timeout = entered_ ? a.firstTimeoutNs : a.nextTimeoutNs;
    return timeout >= 0 ? waitStart_ + std::chrono::nanoseconds(timeout) : Clock::time_point::max();
  }

  /// While waiting in a state with obligatory inputs, only those can make it ready.
  std::uint64_t wakeInputs() const noexcept override {
    if (tables_.activations == nullptr || !ran_) return Wake::kAnyInput;
    return tables_.activations[current_].wakeInputs;
  }

  void updateHook() noexcept override {
    Self& self = static_cast<Self&>(*this);
    step([&self](Action<Self> function) noexcept { (self.*function)(); });
  }

  /// One iteration of the basic-behaviour loop, in which ``run(pf)`` runs each pf of each
  /// stage, the stages in order and the pf of a stage in model order. updateHook() calls the
  /// pf itself; the Orocos target's master component runs each as a component of its own.
  template <class RunFunction>
  void step(RunFunction&& run) noexcept {
    if (!started_) startHook();
    Self& self = static_cast<Self&>(*this);
    const BehaviourDef<Self>& behaviour = tables_.behaviours[tables_.states[current_].behaviour];
    for (std::size_t s = 0; s < behaviour.stageCount; ++s) {
      const StageDef<Self>& stage = behaviour.stages[s];
      for (std::size_t f = 0; f < stage.count; ++f) run(stage.functions[f]);
    }
    (self.*behaviour.send)();
    ++iteration_;
    entered_ = false;
    (self.*behaviour.receive)();
    ++steps_;
    const bool error = (self.*behaviour.error)();
    setInError(error);  // inError(): read by tc and the guards of this iteration, by ec in the next
    if (error || (self.*behaviour.terminal)()) {
      const TransitionDef<Self>* next =
          selectTransition(self, tables_.transitions, tables_.transitionCount, current_);
      if (next != nullptr) {
        enter(next->target, next);
      } else {
        iteration_ = 0;  // no transition holds: the same behaviour runs again
      }
    }
  }

  StateId currentState() const noexcept { return current_; }
  const char* currentStateName() const noexcept { return tables_.states[current_].name; }
  /// iterationNumber of the current behaviour (0 when it has just been entered).
  std::uint64_t iteration() const noexcept { return iteration_; }
  /// updateHook() calls so far.
  std::uint64_t steps() const noexcept { return steps_; }
  /// Iterations that ran because a timeout passed before the obligatory inputs came.
  std::uint64_t timeouts() const noexcept { return timeouts_; }
  const FsmTables<Self>& tables() const noexcept { return tables_; }

  /// The pf number ``pf`` (``name``) failed for ``reason``: behaviourOk() is false until the
  /// subsystem enters a state; the observer hears of the pf's first failure in the state.
  void pfFailed(std::size_t pf, const char* name, const char* reason) noexcept {
    if (!markFailed(pf)) return;
    if (Observer* o = observer()) o->pfFailed(*this, name, reason, steps_);
  }
  /// After the pf number ``pf`` ran: whether the value it wrote into ``buffer`` may be sent.
  /// ``finite``: every number in it is; ``reason``: the failure a non-finite one is under
  /// NonFinite::error (the value is held back); under report it is reported and sent,
  /// ``reported`` remembering that until the value is finite again.
  bool written(std::size_t pf, const char* name, const char* buffer, const char* reason, bool finite,
               bool& reported) noexcept {
    if (finite) {
      reported = false;
      return true;
    }
    if (nonFinite() == NonFinite::error) {
      pfFailed(pf, name, reason);
      return false;
    }
    if (!reported) {
      reported = true;
      if (Observer* o = observer()) o->nonFinite(*this, name, buffer, steps_);
    }
    return true;
  }

 protected:
  /// A queued input found full: tell the observer how many values were lost.
  void overflowed(const char* buffer, std::uint64_t lost) const noexcept {
    if (Observer* o = observer()) o->overflowed(*this, buffer, lost, steps_);
  }

 private:
  /// The least time between the starts of two iterations in a state (its minimal period).
  Clock::duration activationGap(const ActivationDef<Self>& a) const noexcept {
    return a.minPeriodNs >= 0 ? Clock::duration(std::chrono::nanoseconds(a.minPeriodNs))
           : a.obligatory != nullptr ? Clock::duration::zero()
                                     : Clock::duration(period());
  }

  bool take(Clock::time_point now) noexcept {
    ran_ = true;
    waiting_ = false;
    lastStart_ = now;
    return true;
  }

  void enter(StateId state, const TransitionDef<Self>* via) noexcept {
    const char* from = via != nullptr ? tables_.states[current_].name : nullptr;
    current_ = state;
    iteration_ = 0;
    entered_ = true;
    entered();  // every pf healthy again, inError() false
    if (Observer* o = observer()) {
      o->stateChanged(*this, from, tables_.states[state].name, via != nullptr ? via->name : nullptr, steps_);
    }
  }

  const FsmTables<Self>& tables_;
  StateId current_;
  std::uint64_t iteration_ = 0;
  std::uint64_t steps_ = 0;
  std::uint64_t timeouts_ = 0;
  bool started_ = false;
  bool entered_ = true;   // no iteration ran in the current state yet
  bool ran_ = false;      // ready() granted an iteration before
  bool waiting_ = false;  // waitStart_ holds when the wait for the next iteration began
  Clock::time_point lastStart_{};
  Clock::time_point waitStart_{};
};

}  // namespace earl
