// earl-m2t user file: pf manip/a.cs.emergencyStop/pf
// The pick-and-place sample's user code (samples/pick_and_place/user). gen never overwrites
// it; if the pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include "PickAndPlace/manip_a/cs/data.hpp"

namespace PickAndPlace::manip_a::cs {

/// Copies the emergency stop to every joint: set when the task commands it or when any motor
/// controller reports one. outputMotorCon/pf then sends the stop with zero current.
class emergencyStop_pf final : public emergencyStop_pf_base {
 public:
  using emergencyStop_pf_base::emergencyStop_pf_base;

  void execute() override {
    bool stop = manipulatorCommand_ib().emergencyStopCommand;
    for (std::size_t k = 0; k < motorControllerStateK_ib_count; ++k) {
      stop = stop || motorControllerStateK_ib(k).emergencyStopCommand;
    }
    for (std::size_t k = 0; k < emergencyStopCommandK_count; ++k) emergencyStopCommandK_mo(k) = stop;
  }
};

}  // namespace PickAndPlace::manip_a::cs
