// earl-m2t user file: pf manip/a.cs.operationalMove/pf
// The pick-and-place sample's user code (samples/pick_and_place/user). gen never overwrites
// it; if the pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include "PickAndPlace/manip_a/cs/data.hpp"

namespace PickAndPlace::manip_a::cs {

/// A stub: the sample's task sends no operational-space setpoint. It holds the joints (zero
/// current, as passiveRegulation/pf) and reports the motion finished at once, so the FSM
/// goes back to idle. A full version interpolates the pose of operationalPosSetpoint and
/// maps it to joint positions by inverse kinematics, then regulates them as jointMove/pf.
class operationalMove_pf final : public operationalMove_pf_base {
 public:
  using operationalMove_pf_base::operationalMove_pf_base;

  void execute() override {
    for (std::size_t k = 0; k < windingCurrentK_count; ++k) windingCurrentK_mo(k) = 0.0;
    motionFinished_mo() = true;
  }
};

}  // namespace PickAndPlace::manip_a::cs
