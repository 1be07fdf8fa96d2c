// earl runtime for Orocos RTT: the FSM and basic-behaviour loop of a master component.
// Part of earl-m2t's orocos target; header-only, C++17, no RTT header needed.
//
// The same loop as earl::Subsystem::updateHook() (earl/subsystem.hpp), over the same
// generated tables, except that each pf of a stage is run by a callback: the master
// component runs it as a separate component (a TaskContext with a slave activity).
//   tf.execute()          stages in order, the pf of a stage in model order (runFunction)
//   tf.pf.ob.send()       the output buffers the tf's pf write
//   iterationNumber += 1
//   tf.pf.ib.receive()    the input buffers the tf's pf (and the state's conditions) read
//   if ec() || tc():      cfs := selectState()  (stays in cfs when no transition holds)
#pragma once

#include <cstdint>

#include "earl/component.hpp"
#include "earl/subsystem.hpp"

namespace earl {
namespace rtt {

template <class Sub>
class FsmRunner {
 public:
  explicit FsmRunner(const FsmTables<Sub>& tables) noexcept : tables_(tables), current_(tables.initial) {}

  /// fsm.run(): cfs := ifs. The observer (may be nullptr) sees the initial entry.
  void start(const Component& component, Observer* observer) noexcept {
    current_ = tables_.initial;
    iteration_ = 0;
    steps_ = 0;
    started_ = true;
    if (observer != nullptr) observer->stateChanged(component, nullptr, tables_.states[current_].name, nullptr, 0);
  }

  /// One iteration of the current behaviour; runFunction(Action<Sub>) runs one pf.
  template <class RunFunction>
  void step(Sub& sub, RunFunction&& runFunction, Observer* observer) noexcept {
    if (!started_) start(sub, observer);
    const BehaviourDef<Sub>& behaviour = tables_.behaviours[tables_.states[current_].behaviour];
    for (std::size_t s = 0; s < behaviour.stageCount; ++s) {
      const StageDef<Sub>& stage = behaviour.stages[s];
      for (std::size_t f = 0; f < stage.count; ++f) runFunction(stage.functions[f]);
    }
    (sub.*behaviour.send)();
    ++iteration_;
    (sub.*behaviour.receive)();
    ++steps_;
    if ((sub.*behaviour.error)() || (sub.*behaviour.terminal)()) {
      const TransitionDef<Sub>* next = selectTransition(sub, tables_.transitions, tables_.transitionCount, current_);
      if (next != nullptr) {
        const char* from = tables_.states[current_].name;
        current_ = next->target;
        if (observer != nullptr) observer->stateChanged(sub, from, tables_.states[current_].name, next->name, steps_);
      }
      iteration_ = 0;
    }
  }

  StateId currentState() const noexcept { return current_; }
  const char* currentStateName() const noexcept { return tables_.states[current_].name; }
  std::uint64_t iteration() const noexcept { return iteration_; }
  std::uint64_t steps() const noexcept { return steps_; }

 private:
  const FsmTables<Sub>& tables_;
  StateId current_;
  std::uint64_t iteration_ = 0;
  std::uint64_t steps_ = 0;
  bool started_ = false;
};

}  // namespace rtt
}  // namespace earl
