// SPDX-License-Identifier: MIT
#include "core/physics/scene.hpp"
#include "core/physics/constraint_solver.hpp"
#include "core/physics/engine.hpp"
#include "core/physics/step.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <sstream>

#include "core/base/text.hpp"
#include "core/contract/json_io.hpp"
#include "core/contract/pallet_metrics.hpp"
#include "core/contract/pallet_type.hpp"
#include "core/inputs/validation.hpp"
#include "core/physics/quasi_static.hpp"
#include "core/physics/wrap.hpp"

namespace pb {

namespace {

// Shortest text that reads back as the same double.
std::string num(double v) {
  return Json(v).dump();
}

template <std::size_t N>
std::string nums(const std::array<double, N>& values) {
  std::string out;
  for (std::size_t i = 0; i < N; ++i) out += (i ? " " : "") + num(values[i]);
  return out;
}

// An item's box in world-aligned terms at rest (the pallet frame is the world at t = 0).
struct Box {
  double x0, x1, y0, y1, z0, z1;
  bool axis_aligned;  // yaw is a multiple of 90 degrees
};

Box item_box(const Item& item) {
  const double yaw = item.orientation_deg * std::numbers::pi / 180.0;
  const double c = std::abs(std::cos(yaw)), s = std::abs(std::sin(yaw));
  const double hx = 0.5 * (c * item.dims_m[0] + s * item.dims_m[1]);
  const double hy = 0.5 * (s * item.dims_m[0] + c * item.dims_m[1]);
  const double rem = std::fmod(std::abs(item.orientation_deg), 90.0);
  return {item.position[0] - hx,          item.position[0] + hx, item.position[1] - hy,
          item.position[1] + hy,          item.position[2],      item.position[2] + item.dims_m[2],
          rem < 1e-9 || 90.0 - rem < 1e-9};
}

double interval_gap(double a0, double a1, double b0, double b1) {
  return std::max(b0 - a1, a0 - b1);  // negative when the intervals overlap
}

// Surfaces within 1 mm touch (validation's tolerance, round-off included).
constexpr double kTouch = kSupportTolerance_m;

// Per item, how far to pull in each world-aligned face (-x, +x, -y, +y) to leave `gap` between
// neighbouring cartons.
std::vector<std::array<double, 4>> face_shrink(const std::vector<Box>& boxes, double gap) {
  std::vector<std::array<double, 4>> shrink(boxes.size(), {0, 0, 0, 0});
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    for (std::size_t j = i + 1; j < boxes.size(); ++j) {
      const Box& a = boxes[i];
      const Box& b = boxes[j];
      if (!a.axis_aligned || !b.axis_aligned) continue;
      if (interval_gap(a.z0, a.z1, b.z0, b.z1) > -kTouch) continue;  // not side by side
      const double gx = interval_gap(a.x0, a.x1, b.x0, b.x1);
      const double gy = interval_gap(a.y0, a.y1, b.y0, b.y1);
      if (gy < -kTouch && gx >= -kTouch && gx < gap) {  // facing along X
        const double pull = 0.5 * (gap - std::max(gx, 0.0));
        const bool a_first = a.x1 <= b.x0 + kTouch;
        shrink[i][a_first ? 1 : 0] = std::max(shrink[i][a_first ? 1 : 0], pull);
        shrink[j][a_first ? 0 : 1] = std::max(shrink[j][a_first ? 0 : 1], pull);
      } else if (gx < -kTouch && gy >= -kTouch && gy < gap) {  // facing along Y
        const double pull = 0.5 * (gap - std::max(gy, 0.0));
        const bool a_first = a.y1 <= b.y0 + kTouch;
        shrink[i][a_first ? 3 : 2] = std::max(shrink[i][a_first ? 3 : 2], pull);
        shrink[j][a_first ? 2 : 3] = std::max(shrink[j][a_first ? 2 : 3], pull);
      }
    }
  }
  return shrink;
}

bool can_touch(const Box& a, const Box& b, double reach) {
  return interval_gap(a.z0, a.z1, b.z0, b.z1) <= kTouch &&
         interval_gap(a.x0, a.x1, b.x0, b.x1) < reach &&
         interval_gap(a.y0, a.y1, b.y0, b.y1) < reach;
}

const char* integrator_name(Integrator i) {
  switch (i) {
    case Integrator::euler:
      return "Euler";
    case Integrator::implicit:
      return "implicit";
    case Integrator::rk4:
      return "RK4";
  }
  return "Euler";
}
// The scene's flags to step(), as MJCF custom numerics of value 1.
std::string custom_numerics(const SceneOptions& o) {
  std::string flags;
  for (const auto& [on, name] : {std::pair{o.solver_kinetic_friction, kSolverKineticFriction},
                                 std::pair{o.solver == Solver::pcg, kPreconditionedCg}}) {
    if (on) flags += "    <numeric name=\"" + std::string(name) + "\" data=\"1\"/>\n";
  }
  return flags.empty() ? flags : "  <custom>\n" + flags + "  </custom>\n";
}
const char* solver_name(Solver s) {
  switch (s) {
    case Solver::newton:
      return "Newton";
    case Solver::pgs:
      return "PGS";
    case Solver::cg:
    case Solver::pcg:  // MuJoCo's CG in the model; step() solves it with ours (kPreconditionedCg)
      return "CG";
  }
  return "Newton";
}

// Contact pairs: belt/pallet, pallet/item for items on the deck, item/item where they can touch.
// `stacked`: one rests on the other (contacts at rest); otherwise side by side, apart at rest.
struct Pair {
  std::string a, b;
  const FrictionValue* mu;
  bool stacked;
};

// Everything the MJCF is written from: the collision boxes, what is merged, the pairs, the welds
// and the buffers.
struct ScenePlan {
  std::vector<Box> boxes;
  std::vector<std::array<double, 4>> shrink;
  bool merged = false;
  Clustering rigid;
  std::vector<Pair> pairs;
  int welds = 0;
  BufferSizes sizes;
};

ScenePlan plan_scene(const PalletConfig& config, const ContactFriction& friction,
                     const SceneOptions& o) {
  ScenePlan p;
  const std::size_t n = config.items.size();
  const double deck = config.base_dims_m[2];
  p.boxes.reserve(n);
  for (const auto& item : config.items) p.boxes.push_back(item_box(item));
  p.shrink = face_shrink(p.boxes, o.lateral_gap_m);
  const WrapStiffness wrap = o.wrap_welds ? wrap_stiffness(config.wrap) : WrapStiffness{};
  // The reduced model: the wrap holds every item to the pallet; nothing but the pallet touches
  // the belt.
  p.merged = o.merge_wrapped && wrap.stiffness_n_per_m > 0.0 && n > 0;
  // What each item is rigidly part of: the reduced model merges every item into the pallet; the
  // clustered one those it names (unwrapped loads only: a wrap's welds hold the items otherwise).
  p.rigid.carrier.assign(n, p.merged ? kOnPallet : kFreeItem);
  if (!p.merged && o.rigid_carrier.size() == n && wrap.stiffness_n_per_m <= 0.0) {
    p.rigid.carrier = o.rigid_carrier;
  }
  p.pairs.push_back({"belt", "pallet", &friction.belt_pallet, true});  // kBeltPalletPair
  for (std::size_t i = 0; i < n; ++i) {
    if (std::abs(p.boxes[i].z0 - deck) <= kTouch && p.rigid.root(int(i)) != kOnPallet) {
      p.pairs.push_back({"pallet", "item_" + std::to_string(i), &friction.item_pallet, true});
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      const Box& a = p.boxes[i];
      const Box& b = p.boxes[j];
      if (p.rigid.root(int(i)) != p.rigid.root(int(j)) && can_touch(a, b, o.neighbour_distance_m)) {
        // Stacked: one on the other, footprints overlapping (diagonal neighbours across layers
        // touch at most along an edge).
        const bool stacked = interval_gap(a.z0, a.z1, b.z0, b.z1) >= -kTouch &&
                             interval_gap(a.x0, a.x1, b.x0, b.x1) < -kTouch &&
                             interval_gap(a.y0, a.y1, b.y0, b.y1) < -kTouch;
        p.pairs.push_back({"item_" + std::to_string(i), "item_" + std::to_string(j),
                           &friction.item_item, stacked});
      }
    }
  }
  p.welds = wrap.stiffness_n_per_m > 0.0 && !p.merged ? static_cast<int>(n) : 0;
  // Buffers from what the scene uses (MuJoCo 2.2 preallocates them, and its mjData holds an
  // njmax x njmax matrix, so generous sizes cost quadratically: in the buffer MuJoCo counts in an
  // int, though make_data keeps it from being resident): a resting face pair makes 4
  // contacts (8 at most, box-box), so a stacked pair is given 6; a side pair is apart at rest and
  // touches only as a load comes apart, so 1 each; a pyramidal condim-3 contact makes 4 rows
  // (elliptic 3), a weld 6. `buffer_scale` grows them after an overflow (Analyzer); an overflow
  // is still caught and reported, never a verdict. The stack holds the solver's work arrays:
  // Newton's Hessian takes three nv x nv arrays of it (engine_solver.c, CGallocate), which a wide
  // single layer outgrows first (120 cartons of 10 cm on the deck: nv 728, "Stack overflow").
  const std::size_t stacked = static_cast<std::size_t>(
      std::count_if(p.pairs.begin(), p.pairs.end(), [](const Pair& q) { return q.stacked; }));
  const double want = o.buffer_scale * double(6 * stacked + (p.pairs.size() - stacked) + 8 +
                                              (o.aftermath ? 4 * n : 0));
  p.sizes.nconmax = o.nconmax > 0 ? o.nconmax : static_cast<int>(std::ceil(want));
  const int rows = o.cone == Cone::pyramidal ? 4 : 3;  // a condim-3 contact's constraint rows
  p.sizes.njmax = o.njmax > 0 ? o.njmax : rows * p.sizes.nconmax + 6 * p.welds;
  const auto free =
      static_cast<double>(std::count(p.rigid.carrier.begin(), p.rigid.carrier.end(), kFreeItem));
  const double nv = 2 + 6 + 6 * free;  // the belt's two slides, the pallet's and items' free joints
  p.sizes.nv = static_cast<int>(nv);
  p.sizes.nstack =
      o.nstack > 0 ? o.nstack : 400000 + 200 * p.sizes.njmax + static_cast<int>(3 * nv * nv);
  p.sizes.dual_solver = o.solver == Solver::pgs;
  return p;
}

}  // namespace

double BufferSizes::buffer_bytes() const {
  // MuJoCo 2.2.2's mjData buffer (mjxmacro.h): per njmax^2 efc_AR and its column indices (8 + 4
  // bytes), per njmax x nv the Jacobian and its transpose with theirs (2 x (8 + 4)), and what is
  // linear in nconmax and njmax.
  const double nj = njmax;
  return 12.0 * nj * nj + 24.0 * nj * double(nv) + 600.0 * nconmax + 200.0 * nj;
}

double BufferSizes::data_bytes() const {
  // The buffer and the stack, less what make_data shares of the dual solvers' matrix (engine.hpp;
  // it keeps one 2 MB block of it). `bench scale`'s 96-carton brick (njmax 4,188, nv 584): 77 MB.
  const double nj = njmax;
  const double matrix = 12.0 * nj * nj;
  const double shared = dual_solver ? 0.0 : std::max(0.0, matrix - double(kSharedSpanBytes));
  return buffer_bytes() - shared + 8.0 * double(nstack);
}

SceneOptions with_mujoco_solver(SceneOptions o) {
  o.cone = Cone::pyramidal;
  o.solver = Solver::newton;
  o.iterations = 100;
  o.tolerance = 1e-8;
  return o;
}

BufferSizes scene_buffer_sizes(const PalletConfig& config, const SceneOptions& options) {
  const ContactFriction none{};
  return plan_scene(config, none, options).sizes;
}

std::string build_mjcf(const PalletConfig& config, const ContactFriction& friction,
                       const SceneOptions& o) {
  const std::size_t n = config.items.size();
  const Vec3& base = config.base_dims_m;
  const double deck = base[2];
  const ScenePlan plan = plan_scene(config, friction, o);
  const auto& shrink = plan.shrink;
  const bool merged = plan.merged;
  const Clustering& rigid = plan.rigid;
  const auto& pairs = plan.pairs;
  const int welds = plan.welds;
  const int nconmax = plan.sizes.nconmax, njmax = plan.sizes.njmax, nstack = plan.sizes.nstack;

  // The friction of a geom's dynamic contacts (the aftermath only; pairs carry their own).
  auto geom_friction = [&](const FrictionValue& mu) {
    return o.aftermath ? " friction=\"" + num(mu.mu_s) + " 0.005 0.0001\"" : std::string();
  };
  std::ostringstream x;
  x << "<mujoco model=\""
    << "pallet"
    << "\">\n"
    << "  <!-- PalletBallet scene: " << n << " items, wrap " << to_string(config.wrap) << ", "
    << pairs.size() << " contact pairs, " << welds << " welds"
    << (merged ? ", items merged into the pallet body (reduced model)" : "")
    << (!merged && rigid.free_count() < int(n)
            ? ", " + std::to_string(int(n) - rigid.free_count()) +
                  " items merged into what carries them (clustered model)"
            : std::string())
    << " -->\n"
    << "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
    << "  <option timestep=\"" << num(o.timestep_s) << "\" integrator=\""
    << integrator_name(o.integrator) << "\" solver=\"" << solver_name(o.solver) << "\" cone=\""
    << (o.cone == Cone::pyramidal ? "pyramidal" : "elliptic")
    << "\" jacobian=\"sparse\" impratio=\"" << num(o.impratio) << "\" iterations=\"" << o.iterations
    << "\" tolerance=\"" << num(o.tolerance) << "\"/>\n"
    << "  <size nconmax=\"" << nconmax << "\" njmax=\"" << njmax << "\" nstack=\"" << nstack
    << "\" nuserdata=\"" << kFrictionStateSlots * plan.pairs.size() + kDemandFieldSlots << "\"/>\n"
    << custom_numerics(o)
    << (o.aftermath ? "  <default><geom contype=\"1\" conaffinity=\"1\" condim=\"3\" solref=\"" +
                          nums(o.contact_solref) + "\" solimp=\"" + nums(o.contact_solimp) +
                          "\"/></default>\n"
                    : std::string("  <default><geom contype=\"0\" conaffinity=\"0\" "
                                  "condim=\"3\"/></default>\n"))
    << "  <worldbody>\n";
  // The belt: its top face at z = 0, wide enough that the pallet never runs off it.
  const double belt_h = 0.05;
  x << "    <body name=\"belt\" pos=\"0 0 " << num(-belt_h) << "\">\n"
    << "      <joint name=\"belt_x\" type=\"slide\" axis=\"1 0 0\"/>\n"
    << "      <joint name=\"belt_y\" type=\"slide\" axis=\"0 1 0\"/>\n"
    << "      <inertial pos=\"0 0 0\" mass=\"" << num(o.belt_mass_kg)
    << "\" diaginertia=\"1 1 1\"/>\n"
    << "      <geom name=\"belt\" type=\"box\" size=\"" << num(base[0] + 1.0) << " "
    << num(base[1] + 1.0) << " " << num(belt_h) << "\"" << geom_friction(friction.belt_pallet)
    << "/>\n"
    << "    </body>\n";
  {
    const double m = config.base_mass_kg;
    const Vec3 h{base[0] / 2, base[1] / 2, base[2] / 2};
    x << "    <body name=\"pallet\" pos=\"0 0 " << num(h[2]) << "\">\n"
      << "      <freejoint name=\"pallet_free\"/>\n"
      << "      <inertial pos=\"0 0 0\" mass=\"" << num(m) << "\" diaginertia=\""
      << num(m / 3 * (h[1] * h[1] + h[2] * h[2])) << " " << num(m / 3 * (h[0] * h[0] + h[2] * h[2]))
      << " " << num(m / 3 * (h[0] * h[0] + h[1] * h[1])) << "\"/>\n"
      << "      <geom name=\"pallet\" type=\"box\" size=\"" << num(h[0]) << " " << num(h[1]) << " "
      << num(h[2]) << "\"" << geom_friction(friction.item_pallet) << "/>\n";
  }
  // Merged items are bodies without a joint inside what carries them (the pallet's body or another
  // item's), placed in its frame; free items are top-level bodies with a free joint.
  struct Frame {
    double x, y, z, yaw;
  };
  auto centre = [&](std::size_t i) {
    const Item& item = config.items[i];
    return Frame{item.position[0], item.position[1], item.position[2] + item.dims_m[2] / 2,
                 item.orientation_deg * std::numbers::pi / 180.0};
  };
  std::function<void(std::size_t, const Frame&, int)> emit_item = [&](std::size_t i,
                                                                      const Frame& parent,
                                                                      int depth) {
    const Item& item = config.items[i];
    const double m = item.weight_kg;
    const Vec3& d = item.dims_m;
    const Frame c = centre(i);
    const double yaw = c.yaw - parent.yaw;
    const double cp = std::cos(parent.yaw), sp = std::sin(parent.yaw);
    const double dx = c.x - parent.x, dy = c.y - parent.y;
    const std::string indent(std::size_t(4 + 2 * depth), ' ');
    // The collision box: the item's box with faces pulled in where a neighbour is too close,
    // expressed in the item's own frame (yaw is a multiple of 90 degrees wherever it applies).
    const double own_c = std::cos(c.yaw), own_s = std::sin(c.yaw);
    const auto& s = shrink[i];
    const double wx = 0.5 * (s[0] - s[1]), wy = 0.5 * (s[2] - s[3]);  // world offset of the centre
    const double lx = own_c * wx + own_s * wy, ly = -own_s * wx + own_c * wy;  // in the item frame
    const double sx_world = 0.5 * (s[0] + s[1]), sy_world = 0.5 * (s[2] + s[3]);
    const bool swapped = std::abs(own_s) > std::abs(own_c);
    const double hx = d[0] / 2 - (swapped ? sy_world : sx_world);
    const double hy = d[1] / 2 - (swapped ? sx_world : sy_world);
    x << indent << "<body name=\"item_" << i << "\" pos=\"" << num(cp * dx + sp * dy) << " "
      << num(-sp * dx + cp * dy) << " " << num(c.z - parent.z) << "\" quat=\""
      << num(std::cos(yaw / 2)) << " 0 0 " << num(std::sin(yaw / 2)) << "\">\n";
    if (rigid.carrier[i] == kFreeItem)
      x << indent << "  <freejoint name=\"item_" << i << "_free\"/>\n";
    x << indent << "  <inertial pos=\"0 0 0\" mass=\"" << num(m) << "\" diaginertia=\""
      << num(m / 12 * (d[1] * d[1] + d[2] * d[2])) << " "
      << num(m / 12 * (d[0] * d[0] + d[2] * d[2])) << " "
      << num(m / 12 * (d[0] * d[0] + d[1] * d[1])) << "\"/>\n"
      << indent << "  <geom name=\"item_" << i << "\" type=\"box\" pos=\"" << num(lx) << " "
      << num(ly) << " 0\" size=\"" << num(hx) << " " << num(hy) << " " << num(d[2] / 2) << "\""
      << geom_friction(friction.item_item) << "/>\n";
    for (std::size_t j = 0; j < n; ++j) {
      if (rigid.carrier[j] == int(i)) emit_item(j, c, depth + 1);
    }
    x << indent << "</body>\n";
  };
  const Frame pallet_frame{0.0, 0.0, deck / 2, 0.0};
  for (std::size_t i = 0; i < n; ++i) {
    if (rigid.carrier[i] == kOnPallet) emit_item(i, pallet_frame, 1);
  }
  x << "    </body>\n";  // the pallet
  for (std::size_t i = 0; i < n; ++i) {
    if (rigid.carrier[i] == kFreeItem) emit_item(i, Frame{0.0, 0.0, 0.0, 0.0}, 0);
  }
  x << "  </worldbody>\n  <actuator>\n";
  const double kv = o.belt_kv_ratio * o.belt_mass_kg / o.timestep_s;
  x << "    <velocity name=\"belt_vx\" joint=\"belt_x\" kv=\"" << num(kv) << "\"/>\n"
    << "    <velocity name=\"belt_vy\" joint=\"belt_y\" kv=\"" << num(kv) << "\"/>\n"
    << "  </actuator>\n  <contact>\n";
  // MuJoCo's cone has one sliding coefficient; step() (step.hpp) makes it Coulomb's, static until
  // the pair breaks loose and kinetic while it slides. The pair's kinetic coefficient and its
  // index (+1) ride in the friction slots a condim-3 contact does not use (torsion, rolling), and
  // so reach every contact of the pair.
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const Pair& p = pairs[k];
    x << "    <pair geom1=\"" << p.a << "\" geom2=\"" << p.b << "\" condim=\"3\" friction=\""
      << num(p.mu->mu_s) << " " << num(p.mu->mu_s) << " " << num(std::min(p.mu->mu_d, p.mu->mu_s))
      << " 0.0001 " << k + 1 << "\" solref=\"" << nums(o.contact_solref) << "\" solimp=\""
      << nums(o.contact_solimp) << "\"/>\n";
  }
  x << "  </contact>\n";
  if (welds > 0) {
    x << "  <equality>\n";
    for (std::size_t i = 0; i < n; ++i) {
      const WeldParams w =
          weld_params(wrap_stiffness(config.wrap), config.items[i].weight_kg, config.base_mass_kg);
      x << "    <weld name=\"wrap_" << i << "\" body1=\"item_" << i
        << "\" body2=\"pallet\" solref=\"" << nums(w.solref) << "\" solimp=\"" << nums(w.solimp)
        << "\"/>\n";
    }
    x << "  </equality>\n";
  }
  x << "</mujoco>\n";
  return x.str();
}

namespace {

RestBarriers rest_barriers(const Scene& scene) {
  const PalletConfig& config = scene.config;
  const mjModel* m = scene.model.get();
  RestBarriers b;
  const double total = total_mass_kg(config);
  // Friction dissipates at the kinetic coefficient once a slip slides (step.hpp).
  const FrictionValue& belt = scene.friction.belt_pallet;
  b.pallet_slip_force_n = total * std::min(belt.mu_s, belt.mu_d) * kGravity;
  const Vec3 com = composite_com_m(config);
  const double lever = std::min(config.base_dims_m[0] / 2 - std::abs(com[0]),
                                config.base_dims_m[1] / 2 - std::abs(com[1]));
  b.tilt_moment_nm = total * kGravity * std::max(0.0, lever);
  b.item_force_n = std::numeric_limits<double>::infinity();
  // A wrap only adds resistance (its welds store what they take and give back no more), so a free
  // item of a wrapped load is held at least by its own onsets: those of the load unwrapped.
  PalletConfig loose = config;
  loose.wrap = WrapType::none;
  const QuasiStaticBounds bounds = quasi_static_bounds(loose, scene.friction);
  for (const auto* list : {&bounds.along, &bounds.across}) {
    for (const QuasiStaticLimit& q : *list) {
      if (q.item < 0) continue;
      const int body = scene.layout.item_bodies[std::size_t(q.item)];
      if (m->body_jntnum[body] == 0) continue;  // merged: it moves only with what carries it
      b.item_force_n = std::min(
          b.item_force_n, config.items[std::size_t(q.item)].weight_kg * sliding_decel_mps2(q));
    }
  }
  return b;
}

}  // namespace

std::optional<std::string> numerical_limits_problem(const Scene& scene) {
  const SceneOptions& o = scene.options;
  if (o.timestep_s > 0.01) {
    return "a timestep of " + short_number(o.timestep_s * 1000.0) +
           " ms lets a resting load sink more than 1 cm in one step (contacts cannot hold it); "
           "use 10 ms or less";
  }
  // MuJoCo 2.2's implicit integrator damps the belt through kv but its contact solve sees the
  // undamped belt acceleration: the load creeps forward on the belt at about a * (kv dt / M) /
  // b_contact, stably and silently (MUJOCO_2_2_NOTES 3d). Checked correct at kv dt / M = 1; at 4
  // it slides a carton off where the converged reference slips the pallet.
  if (o.integrator == Integrator::implicit && o.belt_kv_ratio > 1.0) {
    return "the implicit integrator with a velocity-driven belt at kv dt / M = " +
           short_number(o.belt_kv_ratio) +
           " makes the load creep forward on the belt (a false slide no check can see); use "
           "Euler (kv dt / M below 2), or keep kv dt / M at 1 or less";
  }
  const mjModel* m = scene.model.get();
  for (int i = 0; i < m->neq; ++i) {
    const double k = -m->eq_solref[mjNREF * i];
    if (k > 0.0 && std::sqrt(k) * o.timestep_s >= 1.0) {
      return "wrap weld " + std::to_string(i) + " is too stiff for the timestep (sqrt(K') dt = " +
             fixed(std::sqrt(k) * o.timestep_s, 2) + " >= 1): it rings and diverges";
    }
  }
  return std::nullopt;
}

Diagnostics capacity_problems(const PalletConfig& config, const SceneOptions& options) {
  const BufferSizes sizes = scene_buffer_sizes(config, options);
  const double mb = 1024.0 * 1024.0;
  const std::string needs = "this load needs " + std::to_string(sizes.njmax) +
                            " constraint rows (" + std::to_string(config.items.size()) +
                            " items, " + std::to_string(sizes.nconmax) + " contacts): ";
  const std::string change = "; split the load into fewer, larger items, or analyse it wrapped";
  if (sizes.buffer_bytes() > kMaxBufferBytes) {
    return {{"/items",
             needs + "one simulation's buffer would be " + fixed(sizes.buffer_bytes() / mb, 0) +
                 " MB, above the " + fixed(kMaxBufferBytes / mb, 0) +
                 " MB MuJoCo 2.2 can allocate (it holds a rows x rows matrix per simulation and "
                 "counts its buffer in an int)" +
                 change,
             Severity::error}};
  }
  if (sizes.data_bytes() > kMaxSimulationBytes) {
    return {{"/items",
             needs + "one simulation would take " + fixed(sizes.data_bytes() / mb, 0) +
                 " MB of memory, above the engine's " + fixed(kMaxSimulationBytes / mb, 0) + " MB" +
                 change,
             Severity::error}};
  }
  return {};
}

Result<Scene> build_scene(const PalletConfig& config, const SceneOptions& options,
                          const FrictionModel& friction_model) {
  ValidationLimits limits;
  limits.check_standing = options.require_standing;
  Diagnostics diags = validate(config, limits);
  if (has_errors(diags)) return Result<Scene>::failure(std::move(diags));
  auto friction = friction_model.for_pallet(config);
  if (!friction) return Result<Scene>::failure(std::move(friction.diagnostics));
  if (!(options.timestep_s > 0.0) || !(options.belt_mass_kg > 0.0)) {
    return Result<Scene>::failure("", "the timestep and the belt mass must be positive");
  }

  // A scene the engine cannot hold is refused before it is compiled, in words.
  if (Diagnostics too_large = capacity_problems(config, options); !too_large.empty()) {
    return Result<Scene>::failure(std::move(too_large));
  }
  Scene scene;
  scene.config = config;
  scene.options = options;
  scene.friction = *friction.value;
  scene.mjcf = build_mjcf(config, scene.friction, options);
  // MuJoCo's compiler makes an mjData of the model to set its constants (mj_setConst), outside
  // make_data, so with the scene's rows it would write the whole rows x rows matrix once: 272 MB
  // on a 96-carton brick, half its prepare in page faults. No array of mjModel depends on njmax
  // (mjxmacro.h), so the scene is compiled with one row (its other sizes as they are) and given
  // its rows after.
  const BufferSizes sizes = scene_buffer_sizes(config, options);
  SceneOptions one_row = options;
  one_row.njmax = 1;
  one_row.nstack = sizes.nstack;
  auto model = compile_mjcf(build_mjcf(config, scene.friction, one_row));
  if (!model) return Result<Scene>::failure(std::move(model.diagnostics));
  scene.model = std::move(*model.value);
  scene.model->njmax = sizes.njmax;

  const mjModel* m = scene.model.get();
  SceneLayout& l = scene.layout;
  auto body = [&](const std::string& name) { return mj_name2id(m, mjOBJ_BODY, name.c_str()); };
  auto joint = [&](const std::string& name) { return mj_name2id(m, mjOBJ_JOINT, name.c_str()); };
  l.belt_body = body("belt");
  l.pallet_body = body("pallet");
  const int bx = joint("belt_x"), by = joint("belt_y"), pf = joint("pallet_free");
  l.belt_x_qpos = m->jnt_qposadr[bx];
  l.belt_y_qpos = m->jnt_qposadr[by];
  l.belt_x_dof = m->jnt_dofadr[bx];
  l.belt_y_dof = m->jnt_dofadr[by];
  l.belt_x_act = mj_name2id(m, mjOBJ_ACTUATOR, "belt_vx");
  l.belt_y_act = mj_name2id(m, mjOBJ_ACTUATOR, "belt_vy");
  l.pallet_qpos = m->jnt_qposadr[pf];
  l.pallet_dof = m->jnt_dofadr[pf];
  // Belt x, belt y and the pallet are the only joints: the items are merged into the pallet.
  l.merged = !config.items.empty() && m->njnt == 3;
  for (std::size_t i = 0; i < config.items.size(); ++i) {
    const std::string name = "item_" + std::to_string(i);
    l.item_bodies.push_back(body(name));
    const int j = joint(name + "_free");
    if (j < 0) continue;  // merged into what carries it
    l.item_qpos.push_back(m->jnt_qposadr[j]);
    l.item_dofs.push_back(m->jnt_dofadr[j]);
  }
  l.free_items = static_cast<int>(l.item_dofs.size());
  l.contact_pairs = m->npair;
  l.welds = m->neq;
  scene.barriers = rest_barriers(scene);
  return Result<Scene>{std::move(scene), std::move(diags)};
}

}  // namespace pb
