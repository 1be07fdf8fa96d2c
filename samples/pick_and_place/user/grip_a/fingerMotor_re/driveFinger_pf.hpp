// earl-m2t user file: pf grip/a.fingerMotor/re.driveFinger/pf
// The pick-and-place sample's user code (samples/pick_and_place/user). gen never overwrites
// it; if the pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include "PickAndPlace/grip_a/fingerMotor_re/data.hpp"
#include "pick_and_place_sample.hpp"

namespace PickAndPlace::grip_a::fingerMotor_re {

/// The simulated finger motor and its encoder: the same first-order motor as the joints.
class driveFinger_pf final : public driveFinger_pf_base {
 public:
  using driveFinger_pf_base::driveFinger_pf_base;

  void execute() override {
    motor_.step(desiredCurrent_ib().current, position_mo());
    encoder_ob().position = position_mo();
  }

 private:
  ::pick_and_place::MotorModel motor_{};
};

}  // namespace PickAndPlace::grip_a::fingerMotor_re
