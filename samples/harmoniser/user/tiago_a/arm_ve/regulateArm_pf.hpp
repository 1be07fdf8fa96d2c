// earl-m2t user file: pf tiago/a.arm/ve.regulateArm/pf
// The harmoniser sample's user code (samples/harmoniser/user). gen never overwrites it; if the
// pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include "Harmoniser/tiago_a/arm_ve/data.hpp"

namespace Harmoniser::tiago_a::arm_ve {

/// The sample's controller passes the commanded setpoint on to the driver as it is.
class regulateArm_pf final : public regulateArm_pf_base {
 public:
  using regulateArm_pf_base::regulateArm_pf_base;

  void execute() override { drive_ob() = command_ib(); }
};

}  // namespace Harmoniser::tiago_a::arm_ve
