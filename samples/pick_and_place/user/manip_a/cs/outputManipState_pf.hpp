// earl-m2t user file: pf manip/a.cs.outputManipState/pf
// The pick-and-place sample's user code (samples/pick_and_place/user). gen never overwrites
// it; if the pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include <cinttypes>
#include <cstdint>
#include <cstdio>

#include "PickAndPlace/manip_a/cs/data.hpp"
#include "pick_and_place_sample.hpp"

namespace PickAndPlace::manip_a::cs {

/// Composes ManipulatorState from the internal memory (paper Fig. 14a) and prints it:
///   step N manip/a.cs: q Q1 Q2 Q3 Q4 Q5 Q6 finished F estop E
/// N counts this subsystem's cycles before this one (the numbering of the state-change
/// lines), Q are the joint positions in rad, F and E are 0 or 1.
class outputManipState_pf final : public outputManipState_pf_base {
 public:
  using outputManipState_pf_base::outputManipState_pf_base;

  void execute() override {
    auto& state = manipulatorState_ob();
    state.currentJointPos = currentJointPos_mi();
    state.currentOperationalPos = currentOperationalPos_mi();
    state.motionFinished = motionFinished_mi();
    bool stop = false;
    for (std::size_t k = 0; k < emergencyStopCommandK_count; ++k) stop = stop || emergencyStopCommandK_mi(k);
    state.emergencyStop = stop;
    if (trace_) {
      const auto& q = state.currentJointPos.q;
      std::printf("step %" PRIu64 " manip/a.cs: q %.6f %.6f %.6f %.6f %.6f %.6f finished %d estop %d\n", step_, q[0],
                  q[1], q[2], q[3], q[4], q[5], state.motionFinished ? 1 : 0, stop ? 1 : 0);
    }
    ++step_;
  }

 private:
  const bool trace_ = ::pick_and_place::traceEnabled();
  std::uint64_t step_ = 0;  // stage 2 of every behaviour runs this pf: once per cycle
};

}  // namespace PickAndPlace::manip_a::cs
