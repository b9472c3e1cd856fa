// SPDX-License-Identifier: MIT
// The speed-accuracy chart of `palletballet-lab study speed-accuracy`, rendered to PNG with Qt
// Charts on Qt's offscreen platform. Plain C++ interface: the rest of the CLI stays Qt-free; this
// module is built (and linked) only when the UI is (PB_BUILD_UI).
#pragma once

#include <string>
#include <vector>

namespace pb::cli {

struct StudyChartPoint {
  std::string name;
  double median_ms = 0.0;        ///< x, log scale
  double within_one_step = 0.0;  ///< y, fraction
  double worst_error_steps = 0.0;
  bool pareto = false;
  bool is_default = false;
  bool is_reference_equivalent = false;
  bool is_reference = false;
};

/// Writes the chart as a PNG (width x height pixels). Returns an empty string on success, or what
/// went wrong. Sets QT_QPA_PLATFORM=offscreen when no platform is set.
std::string render_study_chart(const std::vector<StudyChartPoint>& points, const std::string& title,
                               const std::string& png_path, int width = 1200, int height = 800);

}  // namespace pb::cli
