// earl-m2t user file: pf manipA/a.cs.outputState/pf
// The two-arm sample's user code (samples/two_arm/user). gen never overwrites it; if the pf
// disappears from the model, gen reports this file as orphaned.
#pragma once

#include "TwoArm/manipA_a/cs/data.hpp"

namespace TwoArm::manipA_a::cs {

/// Composes ManipulatorState: the seq of the last command taken, busy while moving.
class outputState_pf final : public outputState_pf_base {
 public:
  using outputState_pf_base::outputState_pf_base;

  void execute() override {
    manipulatorState_ob().lastSeq = lastSeq_mi();
    manipulatorState_ob().busy = !motionFinished_mi();
  }
};

}  // namespace TwoArm::manipA_a::cs
