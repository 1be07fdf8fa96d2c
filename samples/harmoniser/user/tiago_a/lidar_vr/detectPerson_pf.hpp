// earl-m2t user file: pf tiago/a.lidar/vr.detectPerson/pf
// The harmoniser sample's user code (samples/harmoniser/user). gen never overwrites it; if the
// pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include "Harmoniser/tiago_a/lidar_vr/data.hpp"
#include "harmoniser_sample.hpp"

namespace Harmoniser::tiago_a::lidar_vr {

/// The person has fallen when the highest point the lidar sees of them is low; before the
/// first scan (a height of 0) nothing is seen.
class detectPerson_pf final : public detectPerson_pf_base {
 public:
  using detectPerson_pf_base::detectPerson_pf_base;

  void execute() override {
    const double height = scan_ib().ranges[0];
    person_ob().fallen = height > 0.0 && height < harmoniser::kFallenBelow;
  }
};

}  // namespace Harmoniser::tiago_a::lidar_vr
