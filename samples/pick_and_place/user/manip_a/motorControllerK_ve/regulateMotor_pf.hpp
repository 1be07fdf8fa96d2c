// earl-m2t user file: pf manip/a.motorController1/ve.regulateMotor/pf
// The pick-and-place sample's user code (samples/pick_and_place/user). gen never overwrites
// it; if the pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include "PickAndPlace/manip_a/motorControllerK_ve/data.hpp"
#include "pick_and_place_sample.hpp"

namespace PickAndPlace::manip_a::motorControllerK_ve {

/// The drive of one joint (all six motorControllerK/ve run this class). MotorControllerCommand
/// carries a winding current, not a position, so the PI position regulator of eqs. 2–3 runs in
/// manip/a.cs.jointMove/pf (paper Table 7 and Fig. 13) and this controller is the current
/// stage: it passes the commanded current to its motor, limited to ±kMaxCurrent, and reports
/// the encoder position. An emergency stop command latches: from then on the current is
/// zero and every state it reports carries the stop. It integrates no position error, so
/// integralError/m stays 0.
class regulateMotor_pf final : public regulateMotor_pf_base {
 public:
  using regulateMotor_pf_base::regulateMotor_pf_base;

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

}  // namespace PickAndPlace::manip_a::motorControllerK_ve
