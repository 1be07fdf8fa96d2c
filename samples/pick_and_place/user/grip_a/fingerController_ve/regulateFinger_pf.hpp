// earl-m2t user file: pf grip/a.fingerController/ve.regulateFinger/pf
// The pick-and-place sample's user code (samples/pick_and_place/user). gen never overwrites
// it; if the pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include "PickAndPlace/grip_a/fingerController_ve/data.hpp"
#include "pick_and_place_sample.hpp"

namespace PickAndPlace::grip_a::fingerController_ve {

/// The finger drive, as manip/a's motor controllers: the finger's position regulator runs in
/// grip/a.cs.gripperControl/pf, which sends a winding current; this controller limits it,
/// latches an emergency stop (zero current from then on) and reports the encoder position.
class regulateFinger_pf final : public regulateFinger_pf_base {
 public:
  using regulateFinger_pf_base::regulateFinger_pf_base;

  void execute() override {
    const auto& command = motorControllerCommand_ib();
    desiredCurrent_ob().current = stage_.current(command.desiredWindingCurrent, command.emergencyStopCommand);
    motorControllerState_ob().motorPos = encoder_ib().position;
    motorControllerState_ob().emergencyStopCommand = stage_.stopped();
    integralError_mo() = 0.0;
  }

 private:
  ::pick_and_place::CurrentStage stage_;
};

}  // namespace PickAndPlace::grip_a::fingerController_ve
