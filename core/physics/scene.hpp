// SPDX-License-Identifier: MIT
// PalletConfig -> MJCF text -> compiled MuJoCo model, modelling no more than the scene needs:
// boxes on free joints, a velocity-driven belt (X, and Y for curves), explicit contact pairs only
// between surfaces that can touch (each with its own friction from the temperature model), a
// lateral gap between neighbouring cartons, wrap as welds of a physical stiffness, and buffers
// sized from the scene.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/base/diagnostic.hpp"
#include "core/contract/pallet_config.hpp"
#include "core/inputs/friction.hpp"
#include "core/physics/clustering.hpp"
#include "core/physics/engine.hpp"

namespace pb {

enum class Integrator { euler, implicit, rk4 };
/// pcg: conjugate gradient preconditioned with the constraints' Hessian, our own
/// (constraint_solver.hpp), where pb::step runs the step (the Euler integrator) and the model has
/// kPreconditionedCgMinDofs; MuJoCo's CG elsewhere. The others are MuJoCo's.
enum class Solver { newton, pgs, cg, pcg };
enum class Cone { pyramidal, elliptic };

/// Numerical settings of a scene. Defaults are the shipped configuration (see core/README.md for
/// the measurements behind each).
struct SceneOptions {
  double timestep_s = 0.002;
  Integrator integrator = Integrator::euler;  ///< implicit adds false creep with a velocity belt
  /// Conjugate gradient: in the elliptic cone a third of an interlocked load's contacts sit in the
  /// cone's middle zone under a push, where MuJoCo's Newton updates its Hessian per contact every
  /// iteration (core/README.md "The solver is conjugate gradient"). Ours, preconditioned with the
  /// constraints' Hessian (constraint_solver.hpp): MuJoCo's CG preconditions with the mass matrix
  /// alone and takes 50-240 iterations a step on a large brick (core/README.md "The constraint
  /// solve is preconditioned").
  Solver solver = Solver::pcg;
  /// Coulomb's circular cone. MuJoCo's pyramid (n +- mu t_i) turns a loaded contact's creep into
  /// normal motion: a load held near its onset chatters (core/README.md "The friction cone is
  /// Coulomb's circle").
  Cone cone = Cone::elliptic;
  double impratio = 1.0;
  /// A cap, not a count: MuJoCo's CG converges in 10-60 iterations a step, up to about 230 on a
  /// large brick's hardest; ours in 2-8, up to about 25 with a few factorizations.
  int iterations = 1000;
  /// MuJoCo's: the solve stops once an iteration improves its cost, or the cost's gradient is,
  /// below this (scaled by the model's mean inertia and degrees of freedom). Looser halves CG's
  /// iterations on large interlocked loads with the same agreement, but rocks a tower's top carton
  /// that a converged solve holds still (core/README.md "The solver is conjugate gradient").
  double tolerance = 1e-8;
  /// Contact softness. A stiff impedance keeps tip thresholds within a fraction of a percent of
  /// closed form (the soft default tips 2-3 % early: the rear edge sinks in).
  std::array<double, 2> contact_solref{0.02, 1.0};
  std::array<double, 5> contact_solimp{0.99, 0.999, 0.001, 0.5, 2.0};
  /// How a contact pair that has broken loose slides (step.hpp). false (the default): Coulomb's
  /// kinetic friction mu_d N acts on its contacts explicitly and the solve sees them frictionless.
  /// true: MuJoCo's own friction cone at mu_d, whose soft sliding contacts push the surfaces
  /// apart: a pallet sliding on its belt hops (its normal force swings from 0 to 3-8 times its
  /// weight) and shakes its load loose (core/README.md "Sliding is Coulomb's"). For studies.
  bool solver_kinetic_friction = false;
  /// Belt: a heavy body on slide joints driven by velocity actuators with kv = ratio * M / dt.
  /// Explicit (Euler) integration of kv is stable for ratio < 2; 1 is deadbeat tracking.
  double belt_mass_kg = 2000.0;
  double belt_kv_ratio = 1.0;
  /// Neighbouring cartons closer than this are pulled apart to this gap (each face by half of
  /// what is missing): touching faces cost 2-3x and add nothing.
  double lateral_gap_m = 0.0015;
  /// Items whose boxes come within this distance horizontally (with touching or overlapping
  /// heights) get a contact pair; farther ones cannot touch before a detector fires.
  double neighbour_distance_m = 0.05;
  bool wrap_welds = true;  ///< false: ignore wrap (for studies)
  /// false: simulate a load validate()'s standing rule refuses (to measure the rule against the
  /// simulation: `study standing`). Every other rule still applies.
  bool require_standing = true;
  /// The reduced model (Fidelity::reduced): items a wrap holds are merged into the pallet body
  /// (each stays a body without a joint, fixed where it rests, so MuJoCo composes the exact mass,
  /// centre of mass and inertia, and every item pose is still computed); the belt/pallet contact
  /// is the only contact. No effect on an unwrapped pallet or with wrap_welds off.
  bool merge_wrapped = false;
  /// The clustered model (Fidelity::clustered, clustering.hpp): per item, what it is merged into
  /// rigidly (kOnPallet, another item's index) or kFreeItem; contacts inside one rigid body are
  /// dropped. Empty: every item free (or merged by merge_wrapped). Ignored unless its size is the
  /// number of items, and for a wrapped load (its welds decide).
  std::vector<int> rigid_carrier;
  /// The wreck after a failure (Analyzer::solve's replay): besides the pairs, whatever touches
  /// collides (every geom gets contype = conaffinity = 1 and the friction of its kind: item/item
  /// for items, item/pallet for the pallet, belt/pallet for the belt; MuJoCo takes the larger of
  /// two), so falling cartons land on the deck, each other and the belt; buffers get 4 contacts
  /// more per item. Until something touches that no pair covers, the contacts and so the motion
  /// are the same as without it (MuJoCo merges predefined pairs in their order and skips their
  /// geoms among the dynamic ones).
  bool aftermath = false;
  /// Buffer sizes; <= 0 means sized from the scene (times buffer_scale, which the Analyzer doubles
  /// after an overflow).
  double buffer_scale = 1.0;
  int nconmax = 0;
  int njmax = 0;
  int nstack = 0;

  bool operator==(const SceneOptions&) const = default;
};

/// `o` with MuJoCo's own cone and solver (pyramid, Newton, 100 iterations, tolerance 1e-8): what
/// the reference system runs, and the model until session 28.
SceneOptions with_mujoco_solver(SceneOptions o);

/// MuJoCo 2.2's preallocated buffers of a scene.
struct BufferSizes {
  int nconmax = 0, njmax = 0, nstack = 0;
  int nv = 0;                ///< the model's degrees of freedom
  bool dual_solver = false;  ///< PGS: its njmax x njmax matrix is used, so it is resident
  /// The resident memory one mjData of them takes, bytes: the njmax x nv Jacobians and the stack
  /// dominate; the njmax x njmax matrix and its index only for a dual solver (make_data shares
  /// their pages otherwise).
  double data_bytes() const;
  /// The mjData buffer MuJoCo 2.2 allocates, bytes, matrix included: it counts it in an int.
  double buffer_bytes() const;
};

/// The most resident memory one simulation of a scene may take. The envelope's searches share
/// SearchConfig::axis_memory_bytes (640 MB), which must hold the whole model's own mjData and the
/// reduced ones beside it. `bench scale`'s 96-carton brick of dairy cases takes 77 MB.
inline constexpr double kMaxSimulationBytes = 512.0 * 1024 * 1024;
/// The largest mjData buffer MuJoCo 2.2 can make: it counts the buffer's bytes in an int, and the
/// njmax x njmax matrix (12 bytes an entry with its index) grows with the rows squared: about
/// 13,000 rows. 5 % below the int's range, the estimate's accuracy.
inline constexpr double kMaxBufferBytes = 0.95 * 2147483647.0;

/// The buffers build_mjcf sizes for a pallet (no friction or engine needed).
BufferSizes scene_buffer_sizes(const PalletConfig& config, const SceneOptions& options);
/// A scene of `config` with `options` that the engine cannot hold (its mjData above
/// kMaxSimulationBytes resident or kMaxBufferBytes allocated), in words that say what to change at
/// /items; empty when it fits. build_scene refuses such a scene before compiling it.
Diagnostics capacity_problems(const PalletConfig& config, const SceneOptions& options);

/// Where things are in the compiled model.
struct SceneLayout {
  int belt_body = -1;
  int pallet_body = -1;
  std::vector<int> item_bodies;
  int belt_x_qpos = -1, belt_y_qpos = -1;
  int belt_x_dof = -1, belt_y_dof = -1;
  int belt_x_act = -1, belt_y_act = -1;
  int pallet_qpos = -1;  ///< free joint: 7 qpos (pos, quat), 6 dofs from pallet_dof
  int pallet_dof = -1;
  /// The free items' joints, in item order (merged items have none).
  std::vector<int> item_qpos;
  std::vector<int> item_dofs;
  bool merged = false;  ///< every item is merged into the pallet body (the reduced model)
  int free_items = 0;   ///< items on their own free joint
  int contact_pairs = 0;
  int welds = 0;
};

/// The scene's first contact pair is the belt and the pallet (MuJoCo numbers pairs in the order
/// the MJCF lists them).
inline constexpr int kBeltPalletPair = 0;

/// What it takes to move the load away from rest, from the quasi-static onsets (quasi_static.hpp)
/// times the masses they hold: a slip dissipates m mu_d g per metre it slides (kinetic friction,
/// step.hpp; no more than its onset's mu_s g), a tip of onset g (b/2) / h lifts the centre of mass
/// by (b/2) / h per metre it moves sideways, m g of work each. So moving an item a distance s costs
/// at least m a s, a its slip's sliding deceleration or its tip's onset; tilting the whole load by
/// an angle theta about the pallet's bottom edge costs M g lever theta.
struct RestBarriers {
  /// The least m_i x a_i over the free items (slip on what carries it at mu_d g, tip of the
  /// sub-stack it carries over its bottom edge; a wrapped load's as if unwrapped: a wrap only adds
  /// resistance; infinite when no item is free), N.
  double item_force_n = 0.0;
  double pallet_slip_force_n = 0.0;  ///< M_total mu_d,belt g (kinetic: what a slide dissipates)
  double tilt_moment_nm = 0.0;       ///< M_total g (the centre of mass's distance to the edge)
};

struct Scene {
  PalletConfig config;
  SceneOptions options;
  ContactFriction friction;
  std::string mjcf;
  ModelPtr model;
  SceneLayout layout;
  RestBarriers barriers;
};

/// The MJCF text of a pallet on the belt (what `palletballet-cli mjcf` writes; MuJoCo's viewer
/// opens it). Pure text: no validation, no engine.
std::string build_mjcf(const PalletConfig& config, const ContactFriction& friction,
                       const SceneOptions& options);

/// Why these numerical settings cannot give a trustworthy answer for this scene, or nullopt: a wrap
/// weld whose
/// natural frequency is not resolved by the timestep (sqrt(K') dt >= 1) rings and diverges; above
/// 10 ms a resting load sinks more than the phantom-contact filter's 1 cm in one step and falls
/// through. A run of such a scene is `unstable` before it starts. (A belt drive integrated beyond
/// its stability limit, kv dt / M >= 2 with Euler, is caught while it runs: its error grows.)
std::optional<std::string> numerical_limits_problem(const Scene& scene);

/// Validates the pallet (errors make it fail; a pallet that cannot exist is not simulated), takes
/// friction from `friction_model`, writes and compiles the MJCF.
Result<Scene> build_scene(const PalletConfig& config, const SceneOptions& options = {},
                          const FrictionModel& friction_model = FrictionModel::builtin());

}  // namespace pb
