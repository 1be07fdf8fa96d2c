// earl-m2t user file: pf tiago/a.base/ve.regulateBase/pf
// The harmoniser sample's user code (samples/harmoniser/user). gen never overwrites it; if the
// pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include "Harmoniser/tiago_a/base_ve/data.hpp"

namespace Harmoniser::tiago_a::base_ve {

/// The sample's controller passes the commanded setpoint on to the driver as it is.
class regulateBase_pf final : public regulateBase_pf_base {
 public:
  using regulateBase_pf_base::regulateBase_pf_base;

  void execute() override { drive_ob() = command_ib(); }
};

}  // namespace Harmoniser::tiago_a::base_ve
