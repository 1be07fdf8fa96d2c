// earl-m2t user file: pf task/a.cs.holdCommand/pf
// The two-arm sample's user code (samples/two_arm/user). gen never overwrites it; if the pf
// disappears from the model, gen reports this file as orphaned.
#pragma once

#include "TwoArm/task_a/cs/data.hpp"

namespace TwoArm::task_a::cs {

/// After the last hand-over: repeats the last command sent, its seq unchanged, so the arm in
/// use holds its setpoint (it takes no repeated seq as a new command).
class holdCommand_pf final : public holdCommand_pf_base {
 public:
  using holdCommand_pf_base::holdCommand_pf_base;

  void execute() override { manipulatorCommand_ob().seq = nextSeq_mi(); }
};

}  // namespace TwoArm::task_a::cs
