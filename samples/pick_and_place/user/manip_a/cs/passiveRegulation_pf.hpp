// earl-m2t user file: pf manip/a.cs.passiveRegulation/pf
// The pick-and-place sample's user code (samples/pick_and_place/user). gen never overwrites
// it; if the pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include "PickAndPlace/manip_a/cs/data.hpp"

namespace PickAndPlace::manip_a::cs {

/// Winding currents that keep the manipulator still. The simulated joints carry no gravity
/// or other load and their motors have viscous friction, so a joint at rest stays at rest
/// with no current: the current needed is zero. (A real arm would send the current that
/// balances gravity at the measured joint positions, motorControllerStateK/ib.)
class passiveRegulation_pf final : public passiveRegulation_pf_base {
 public:
  using passiveRegulation_pf_base::passiveRegulation_pf_base;

  void execute() override {
    for (std::size_t k = 0; k < windingCurrentK_count; ++k) windingCurrentK_mo(k) = 0.0;
  }
};

}  // namespace PickAndPlace::manip_a::cs
