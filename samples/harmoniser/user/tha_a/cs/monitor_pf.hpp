// earl-m2t user file: pf tha/a.cs.monitor/pf
// The harmoniser sample's user code (samples/harmoniser/user). gen never overwrites it; if the
// pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include "Harmoniser/tha_a/cs/data.hpp"

namespace Harmoniser::tha_a::cs {

/// Counts the falls: one more each time the alarm rises.
class monitor_pf final : public monitor_pf_base {
 public:
  using monitor_pf_base::monitor_pf_base;

  void execute() override {
    const bool fallen = fallAlarm_ib().fallen;
    if (fallen && !raised_) falls_mo() += 1;
    raised_ = fallen;
  }

 private:
  bool raised_ = false;
};

}  // namespace Harmoniser::tha_a::cs
