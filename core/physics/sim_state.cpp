// SPDX-License-Identifier: MIT
#include "core/physics/sim_state.hpp"

#include <algorithm>

namespace pb {

bool SimState::operator==(const SimState& other) const {
  for (const StateArray& a : kStateArrays) {
    if (this->*a.state != other.*a.state) return false;
  }
  for (std::size_t w = 0; w < warning.size(); ++w) {
    if (warning[w].lastinfo != other.warning[w].lastinfo ||
        warning[w].number != other.warning[w].number) {
      return false;
    }
  }
  return time == other.time;
}

SimState capture_state(const mjModel& m, const mjData& d) {
  SimState s;
  s.time = d.time;
  for (const StateArray& a : kStateArrays) {
    const mjtNum* first = d.*a.data;
    (s.*a.state).assign(first, first + a.width(m));
  }
  std::copy_n(d.warning, mjNWARNING, s.warning.begin());
  return s;
}

void restore_state(const SimState& s, mjData& d) {
  d.time = s.time;
  for (const StateArray& a : kStateArrays) {
    std::copy((s.*a.state).begin(), (s.*a.state).end(), d.*a.data);
  }
  std::copy(s.warning.begin(), s.warning.end(), d.warning);
}

}  // namespace pb
