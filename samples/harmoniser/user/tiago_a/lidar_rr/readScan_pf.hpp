// earl-m2t user file: pf tiago/a.lidar/rr.readScan/pf
// The harmoniser sample's user code (samples/harmoniser/user). gen never overwrites it; if the
// pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include <cstdint>

#include "Harmoniser/tiago_a/lidar_rr/data.hpp"
#include "harmoniser_sample.hpp"

namespace Harmoniser::tiago_a::lidar_rr {

/// The scripted lidar: one scan per iteration; the person stands, except in the scans
/// [kFallFrom, kFallUntil), where they lie on the floor.
class readScan_pf final : public readScan_pf_base {
 public:
  using readScan_pf_base::readScan_pf_base;

  void execute() override {
    const bool lying = scans_ >= harmoniser::kFallFrom && scans_ < harmoniser::kFallUntil;
    scan_ob().ranges[0] = lying ? harmoniser::kLying : harmoniser::kStanding;
    ++scans_;
  }

 private:
  std::int64_t scans_ = 0;
};

}  // namespace Harmoniser::tiago_a::lidar_rr
