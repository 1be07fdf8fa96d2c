// earl-m2t user file: pf grip/a.cs.gripperControl/pf
// The pick-and-place sample's user code (samples/pick_and_place/user). gen never overwrites
// it; if the pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include <cmath>

#include "PickAndPlace/grip_a/cs/data.hpp"
#include "pick_and_place_sample.hpp"

namespace PickAndPlace::grip_a::cs {

/// The finger's PI position regulator (eqs. 2–3, the joints' gains) toward the commanded
/// finger position; an emergency stop is passed on with zero current. The status reports
/// the finger position, whether it is within kPositionTolerance of the command, and the
/// stop (commanded, or reported by the finger controller).
class gripperControl_pf final : public gripperControl_pf_base {
 public:
  using gripperControl_pf_base::gripperControl_pf_base;

  void execute() override {
    const auto& command = gripperCommand_ib();
    const auto& finger = fingerState_ib();
    const double current = regulator_.current(command.desiredFingerPos, finger.motorPos);
    fingerCommand_ob().emergencyStopCommand = command.emergencyStopCommand;
    fingerCommand_ob().desiredWindingCurrent = command.emergencyStopCommand ? 0.0 : current;
    auto& status = gripperStatus_ob();
    status.currentFingerPos = finger.motorPos;
    status.motionFinished =
        std::abs(command.desiredFingerPos - finger.motorPos) < ::pick_and_place::kPositionTolerance;
    status.emergencyStop = command.emergencyStopCommand || finger.emergencyStopCommand;
  }

 private:
  ::pick_and_place::PiRegulator regulator_{};
};

}  // namespace PickAndPlace::grip_a::cs
