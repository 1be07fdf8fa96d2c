// earl-m2t user file: pf manip/a.motor1/re.driveMotor/pf
// The pick-and-place sample's user code (samples/pick_and_place/user). gen never overwrites
// it; if the pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include "PickAndPlace/manip_a/motorK_re/data.hpp"
#include "pick_and_place_sample.hpp"

namespace PickAndPlace::manip_a::motorK_re {

/// A simulated joint motor and its encoder (all six motorK/re run this class): the winding
/// current drives the first-order motor of pick_and_place::MotorModel for one cycle; the
/// position is kept in position/m and read back by the encoder.
class driveMotor_pf final : public driveMotor_pf_base {
 public:
  using driveMotor_pf_base::driveMotor_pf_base;

  void execute() override {
    motor_.step(desiredCurrent_ib().current, position_mo());
    encoder_ob().position = position_mo();
  }

 private:
  ::pick_and_place::MotorModel motor_{};
};

}  // namespace PickAndPlace::manip_a::motorK_re
