// Agreement between two depth images of the same camera, e.g. the tracker's
// render of the robot against MuJoCo's.
#pragma once

#include <string>

#include "arttrack/tracker/camera.h"

namespace arttrack::sim {

struct DepthAgreement {
  long pixels_a = 0;          // pixels with a return in image a
  long pixels_b = 0;          // ... in image b
  long pixels_both = 0;       // ... in both
  long within_tolerance = 0;  // of pixels_both, |a - b| <= tolerance
  double tolerance_m = 0;
  double max_abs_difference_m = 0;  // over pixels_both
  // within_tolerance / pixels_both (1 if none).
  double fraction_within() const;
  // Silhouette intersection over union: both / (a + b - both) (1 if both empty).
  double silhouette_iou() const;
  // One line for logs, e.g. "both 10234 px, 99.8% within 2.0 mm, IoU 0.991".
  std::string summary() const;
};

// Compares a and b (same size; 0 or non-finite = no return).
DepthAgreement compare_depth(const DepthImage& a, const DepthImage& b, double tolerance_m);

}  // namespace arttrack::sim
