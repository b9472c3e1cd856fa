// SPDX-License-Identifier: MIT
#include "core/physics/wrap.hpp"

#include <cmath>

namespace pb {

WrapStiffness wrap_stiffness(WrapType wrap) {
  switch (wrap) {
    case WrapType::none:
      return {0.0, 0.0};
    case WrapType::shrink:
      return {3000.0, 0.5};
    case WrapType::stretch:
      return {8000.0, 0.5};
    case WrapType::banded:
      return {30000.0, 0.5};
  }
  return {0.0, 0.0};
}

WeldParams weld_params(const WrapStiffness& wrap, double m1, double m2, double d) {
  const double m_red = 1.0 / (1.0 / m1 + 1.0 / m2);
  const double damping = 2.0 * wrap.damping_ratio * std::sqrt(wrap.stiffness_n_per_m * m_red);
  WeldParams p;
  p.solref = {-wrap.stiffness_n_per_m * (1.0 - d) / m_red, -damping * (1.0 - d) / m_red};
  p.solimp = {d, d, 0.001, 0.5, 2.0};
  return p;
}

}  // namespace pb
