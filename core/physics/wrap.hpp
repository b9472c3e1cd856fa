// SPDX-License-Identifier: MIT
// Wrap as physics: a spring-damper per item between the item and the pallet base, with a
// physical stiffness per wrap type, mapped onto a MuJoCo weld with the direct solref form.
#pragma once

#include <array>

#include "core/base/enums.hpp"

namespace pb {

/// What one item feels from the wrap, per item, as a linear spring and damper.
struct WrapStiffness {
  double stiffness_n_per_m = 0.0;  ///< 0: no wrap, no weld
  double damping_ratio = 0.0;      ///< of the item-on-pallet oscillator
};

/// Assumed stiffnesses (not measurements; calibrate on a line): shrink 3,000 N/m (a heat-shrunk
/// hood: a thin film, tight but stretchy), stretch 8,000 N/m (several turns of pre-stretched
/// film), banded 30,000 N/m (PET or steel straps, nearly rigid). A 10 kg carton at 3 m/s^2 then
/// deflects 10 / 3.8 / 1 mm. Damping ratio 0.5 for every wrap (film and board are lossy).
/// The reference declared 200 / 800 / 5000 N/m but never applied them; per carton those would
/// let a 10 kg carton under stretch wrap move 3.8 cm at 3 m/s^2, far softer than wrapped loads
/// behave.
WrapStiffness wrap_stiffness(WrapType wrap);

/// MuJoCo weld parameters that realise a spring K [N/m] and damper C [N s/m] between bodies of
/// masses m1 and m2 (MUJOCO_2_2_NOTES.md section 1): with a constant impedance d,
/// K_eff = K' / ((1 - d) * (1/m1 + 1/m2)), so K' = K (1 - d) / m_red and C' = C (1 - d) / m_red,
/// written as solref = (-K', -C') and solimp = (d, d, 0.001, 0.5, 2). A small d keeps the
/// transient frequency at sqrt(K / m_red) as well.
struct WeldParams {
  std::array<double, 2> solref{};
  std::array<double, 5> solimp{};
};
WeldParams weld_params(const WrapStiffness& wrap, double mass1_kg, double mass2_kg,
                       double impedance = 0.3);

}  // namespace pb
