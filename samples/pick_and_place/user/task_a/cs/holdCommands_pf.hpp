// earl-m2t user file: pf task/a.cs.holdCommands/pf
// The pick-and-place sample's user code (samples/pick_and_place/user). gen never overwrites
// it; if the pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include "PickAndPlace/task_a/cs/data.hpp"

namespace PickAndPlace::task_a::cs {

/// After an abort: keeps sending the last commands with the emergency stop set and no setpoint.
class holdCommands_pf final : public holdCommands_pf_base {
 public:
  using holdCommands_pf_base::holdCommands_pf_base;

  void execute() override {
    auto& command = manipulatorCommand_ob();
    command.jointPosSetpoint.clear();
    command.operationalPosSetpoint.clear();
    command.emergencyStopCommand = true;
    gripperCommand_ob().emergencyStopCommand = true;
  }
};

}  // namespace PickAndPlace::task_a::cs
