// earl-m2t user file: pf tiago/a.base/re.driveBase/pf
// The harmoniser sample's user code (samples/harmoniser/user). gen never overwrites it; if the
// pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include "Harmoniser/tiago_a/base_re/data.hpp"

namespace Harmoniser::tiago_a::base_re {

/// The sample's simulated hardware reaches every setpoint at once and reports it.
class driveBase_pf final : public driveBase_pf_base {
 public:
  using driveBase_pf_base::driveBase_pf_base;

  void execute() override { feedback_ob() = drive_ib(); }
};

}  // namespace Harmoniser::tiago_a::base_re
