// earl-m2t user file: pf tiago/a.arm/re.driveArm/pf
// The harmoniser sample's user code (samples/harmoniser/user). gen never overwrites it; if the
// pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include "Harmoniser/tiago_a/arm_re/data.hpp"

namespace Harmoniser::tiago_a::arm_re {

/// The sample's simulated hardware reaches every setpoint at once and reports it.
class driveArm_pf final : public driveArm_pf_base {
 public:
  using driveArm_pf_base::driveArm_pf_base;

  void execute() override { feedback_ob() = drive_ib(); }
};

}  // namespace Harmoniser::tiago_a::arm_re
