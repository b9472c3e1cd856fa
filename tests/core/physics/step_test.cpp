// SPDX-License-Identifier: MIT
// pb::step's Coulomb friction against closed-form mechanics: a carton (mu_s 0.4, mu_d 0.3 on the
// deck) holds below its static onset even where kinetic friction could not hold it, breaks loose
// above it and slides as kinetic friction says, then sticks again; below the onset the step is
// mj_step's, bit for bit. A pallet that slips on its belt slides as Coulomb says and carries its
// carton without shaking it loose.
#include "core/physics/step.hpp"

#include <QtTest>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "core/physics/engine.hpp"
#include "core/physics/probe_run.hpp"
#include "core/physics/quasi_static.hpp"
#include "core/physics/simulate.hpp"
#include "tests/core/test_friction.hpp"
#include "tests/core/test_rig.hpp"

using namespace pb;

namespace {

constexpr double kG = kGravity;
constexpr double kDeck = 0.15;
const test::ConstantMu kCoulomb{1.0, 0.4, 0.4, 0.75};  // carton on the deck: mu_s 0.4, mu_d 0.3
const test::ConstantMu kStatic{1.0, 0.4, 0.4, 1.0};    // the same, one coefficient

using test::Rig;

// A 10 kg carton (0.4 x 0.3 x 0.2 m, 2 g from tipping) on an EUR pallet, settled.
Rig settled(const test::ConstantMu& mu, const SceneOptions& options = {}) {
  PalletConfig config;
  config.pallet_id = "step-test";
  Item item;
  item.sku = "TEST";
  item.weight_kg = 10.0;
  item.dims_m = {0.4, 0.3, 0.2};
  item.position = {0.0, 0.0, kDeck};
  config.items = {item};
  config.wrap = WrapType::none;
  config.env = Environment::thawed;
  config.body_temp_c = 20.0;
  config.seconds_since_temp_change = 3600.0;
  return test::settled_rig(config, test::constant_friction(mu), options);
}

// The same slide with the static phase lasting t_static and the sliding at mu_sliding: a belt
// ramp at a for T, then the catch-up at mu_sliding g (relative slide, m).
double ramp_slide(double a, double T, double mu_s, double mu_sliding, double t_static) {
  const double a1 = a - mu_s * kG, a2 = a - mu_sliding * kG;
  const double t1 = std::min(t_static, T), t2 = T - t1;
  const double v1 = a1 * t1, v2 = v1 + a2 * t2;
  const double during = a1 * t1 * t1 / 2 + v1 * t2 + a2 * t2 * t2 / 2;
  return during + v2 * v2 / (2.0 * mu_sliding * kG);
}

// The belt accelerates at `a` for `ramp_s`, then runs at a * ramp_s until `duration_s`.
ConveyorProfile ramp(double a, double ramp_s, double duration_s) {
  ConveyorProfile p;
  p.shape = ProfileShape::accel_hold;
  p.accel_mps2 = a;
  p.target_speed_mps = a * ramp_s;
  p.duration_s = duration_s;
  return p;
}

// Every step simulated and kept, no detector firing.
SimResult run(Rig& rig, const ConveyorProfile& profile) {
  return rig.sim->run(rig.rest, profile, test::every_step());
}

// The carton's displacement in the pallet's frame (against the belt's motion: negative x) at frame
// k of the trace.
double slide_at(const Rig& rig, const SimResult& r, std::size_t k) {
  const Vec3 start = to_frame(rig.rest.pallet, rig.rest.items[0].pos);
  const Vec3 now = to_frame(r.trace.pallet(k), r.trace.items(k)[0].pos);
  return start[0] - now[0];
}

}  // namespace

class StepTest : public QObject {
  Q_OBJECT

 private slots:
  // Kinetic friction's forces go onto the dofs by apply_force: mj_applyFT to the bit, on every
  // body of a rig (the belt's slides, the pallet's and the carton's free joints, turned), for
  // forces with zero and negative components.
  void applyForceIsMjApplyFtToTheBit() {
    Rig rig = settled(kCoulomb);
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    const mjModel* m = rig.scene->model.get();
    auto data = make_data(m);
    mjData* d = data->get();
    load_rest_state(rig.scene->layout, rig.rest, 0.3, *d);
    // Every free body turned off level, so that each dof's row of J is a sum of three terms.
    for (int j = 0; j < m->njnt; ++j) {
      if (m->jnt_type[j] != mjJNT_FREE) continue;
      mjtNum* q = d->qpos + m->jnt_qposadr[j] + 3;
      const mjtNum turned[4] = {0.93, 0.21 + 0.01 * j, -0.17, 0.26};
      mju_copy4(q, turned);
      mju_normalize4(q);
    }
    mj_kinematics(m, d);
    mj_comPos(m, d);
    const mjtNum forces[][3] = {{3.5, -1.25, 0.0},
                                {0.0, 0.0, -98.1},
                                {-0.7, 2.0, 11.0},
                                {3.7312961, -1.2571043, 0.44396127},
                                {-17.033519, 5.9170321, -2.6034483}};
    const mjtNum none[3] = {0.0, 0.0, 0.0};
    int moved = 0;
    for (int body = 0; body < m->nbody; ++body) {
      for (const auto& f : forces) {
        const mjtNum at[3] = {0.1371 + 0.0173 * body, -0.2219, 0.3137};
        std::vector<mjtNum> a(std::size_t(m->nv)), b(std::size_t(m->nv));
        for (int i = 0; i < m->nv; ++i) a[i] = b[i] = 0.5 * i - 1.0;  // no -0
        mj_applyFT(m, d, f, none, at, body, a.data());
        apply_force(m, d, f, at, body, b.data());
        QVERIFY2(std::memcmp(a.data(), b.data(), sizeof(mjtNum) * a.size()) == 0,
                 qPrintable(QString("body %1").arg(body)));
        for (int i = 0; i < m->nv; ++i) moved += a[i] != 0.5 * i - 1.0 ? 1 : 0;
      }
    }
    QVERIFY(moved > 0);  // the forces did something
  }

  // Held at 0.9 mu_s g for 1.5 s: above the kinetic coefficient's mu_d g (2.94 m/s^2), so a model
  // with mu_d alone would slide it 0.5 (3.53 - 2.94) 1.5^2 = 0.67 m; static friction holds it.
  void holdsBelowItsStaticOnset() {
    Rig rig = settled(kCoulomb);
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    const double a = 0.9 * 0.4 * kG;
    const SimResult r = run(rig, ramp(a, 1.5, 1.5));
    QCOMPARE(r.outcome, Outcome::safe);
    const double slide = slide_at(rig, r, r.trace.size() - 1);
    qInfo("at %.3f m/s^2 (0.9 of the onset) for 1.5 s: slid %.2e m", a, slide);
    QVERIFY(std::abs(slide) < 2e-3);
  }

  // Below the onset no pair breaks loose, so the kinetic coefficient changes nothing: the same
  // trajectory, bit for bit, as one coefficient gives.
  void belowItsOnsetTheKineticCoefficientChangesNothing() {
    Rig coulomb = settled(kCoulomb);
    Rig one = settled(kStatic);
    QVERIFY2(coulomb.error.empty() && one.error.empty(), "rigs");
    const ConveyorProfile p = ramp(0.8 * 0.4 * kG, 0.5, 1.0);
    const SimResult a = run(coulomb, p);
    const SimResult b = run(one, p);
    QCOMPARE(a.trace.size(), b.trace.size());
    const std::size_t last = a.trace.size() - 1;
    for (int k = 0; k < 3; ++k) {
      QCOMPARE(a.trace.items(last)[0].pos[k], b.trace.items(last)[0].pos[k]);
      QCOMPARE(a.trace.pallet(last).pos[k], b.trace.pallet(last).pos[k]);
    }
  }

  // Above the onset: the belt accelerates at a for T and then runs on. The carton slips on its
  // static cone at a - mu_s g until it has slipped kBreakLooseM (t_D = sqrt(2 D / (a - mu_s g))),
  // breaks loose and lags at a - mu_d g until T, then catches up at mu_d g and sticks. Coulomb's
  // slide (t_D = 0) and that of the static coefficient alone are 2-13 % and 40-70 % away.
  void slidesAsKineticFrictionSaysAndSticksAgain() {
    Rig rig = settled(kCoulomb);
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    const double mu_s = 0.4, mu_d = 0.3, T = 0.3;
    for (const double a : {4.5, 5.0, 7.0}) {
      const SimResult r = run(rig, ramp(a, T, T + 0.8));
      QCOMPARE(r.outcome, Outcome::safe);
      auto slide_of = [&](double t_static, double mu_sliding) {
        return ramp_slide(a, T, mu_s, mu_sliding, t_static);
      };
      const double t_d = std::sqrt(2.0 * kBreakLooseM / (a - mu_s * kG));
      const double expected = slide_of(t_d, mu_d);
      const std::size_t last = r.trace.size() - 1;
      const double slide = slide_at(rig, r, last);
      qInfo("a %.1f: slid %.4f m; this model %.4f m (%+.2f %%), Coulomb %.4f m, mu_s alone %.4f m",
            a, slide, expected, 100.0 * (slide / expected - 1.0), slide_of(0.0, mu_d),
            slide_of(T, mu_s));
      QVERIFY(std::abs(slide / expected - 1.0) < 0.03);
      // Stuck again: no further motion on the pallet over the last 0.2 s.
      std::size_t earlier = last;
      while (earlier > 0 && r.trace.time(earlier) > r.trace.time(last) - 0.2) --earlier;
      QVERIFY(std::abs(slide - slide_at(rig, r, earlier)) < 1e-3);
    }
  }

  // The pallet on a belt of mu_s 0.3, mu_d 0.225 under the same carton (0.4 / 0.3 on the deck):
  // a belt ramp at 4 m/s^2 breaks the pallet loose at 0.3 g and drags it at 0.225 g, which the
  // carton's 0.4 g holds with room to spare: Coulomb says the carton never moves on the deck and
  // the pallet slides as the carton did above. MuJoCo's own cone at mu_d (solver_kinetic_friction)
  // lets the sliding pallet hop and shakes the carton centimetres along the deck.
  void aPalletSlippingOnItsBeltCarriesItsCartonAsCoulombSays() {
    const test::ConstantMu mu{0.3, 0.4, 0.4, 0.75};
    const double a = 4.0, T = 0.4, mu_s = 0.3, mu_d = 0.225;
    const double t_d = std::sqrt(2.0 * kBreakLooseM / (a - mu_s * kG));
    const double expected = ramp_slide(a, T, mu_s, mu_d, t_d);
    for (const bool solver : {false, true}) {
      SceneOptions options;
      options.solver_kinetic_friction = solver;
      Rig rig = settled(mu, options);
      QVERIFY2(rig.error.empty(), rig.error.c_str());
      const SimResult r = run(rig, ramp(a, T, T + 0.8));
      double carton = 0.0;  // the most the carton moved on the deck, m
      for (std::size_t k = 0; k < r.trace.size(); ++k)
        carton = std::max(carton, std::abs(slide_at(rig, r, k)));
      // The pallet's slide on the belt at the end, where both run at the belt's speed (the trace
      // takes the belt's position after the step: one step's travel corrected).
      const std::size_t last = r.trace.size() - 1;
      const auto& belt = r.trace.belt(last);
      const double belt_travel =
          belt.x - r.trace.belt(0).x - belt.vx * rig.scene->options.timestep_s;
      const double pallet = belt_travel - (r.trace.pallet(last).pos[0] - rig.rest.pallet.pos[0]);
      qInfo(
          "%s: pallet slid %.4f m (Coulomb with the static phase %.4f m, %+.2f %%), the carton "
          "moved %.2f mm on the deck",
          solver ? "MuJoCo's cone at mu_d" : "explicit kinetic friction", pallet, expected,
          100.0 * (pallet / expected - 1.0), carton * 1e3);
      if (solver) continue;  // the model until session 17, shown for the record
      QCOMPARE(r.outcome, Outcome::safe);
      QVERIFY(std::abs(pallet / expected - 1.0) < 0.03);
      QVERIFY(carton < 1e-3);
    }
  }

  // Held at half its onset the carton's pair uses about half its cone (max_cone_use); at 0.995
  // of it the solver holds its friction at the cone (kConeSaturated) while it has not broken
  // loose: a creeping load's jump is not cut short while a pair is near its cone.
  void aPairNearItsOnsetIsOnItsCone() {
    Rig rig = settled(kCoulomb);
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    const mjModel* m = rig.scene->model.get();
    for (const double share : {0.5, 0.995}) {
      const ConveyorProfile p = ramp(share * 0.4 * kG, 0.4, 0.4);
      SimOptions o = test::every_step();
      o.record_trace = false;
      ProbeRun run(*rig.scene, rig.rest, p, o);
      auto data = make_data(m);
      mjData* d = data->get();
      load_rest_state(rig.scene->layout, rig.rest, run.initial_speed(), *d);
      int on_cone = 0, sliding = 0, steps = 0;
      double most = 0.0;
      while (!run.done()) {
        run.before_step(*d);
        step(m, d);
        ++steps;
        const double use = max_cone_use(m, d);
        most = std::max(most, use);
        on_cone += use >= kConeSaturated ? 1 : 0;
        sliding += any_pair_sliding(m, d) ? 1 : 0;
        if (!run.after_step(*m, *d)) break;
      }
      qInfo("at %.3f of its onset: at most %.3f of its cone, on it %d of %d steps, broken loose %d",
            share, most, on_cone, steps, sliding);
      QCOMPARE(sliding, 0);
      if (share < 0.9) {
        QVERIFY(most > 0.4 && most < 0.6);
      } else {
        QVERIFY(on_cone > steps / 2);
      }
    }
  }
};

QTEST_GUILESS_MAIN(StepTest)
#include "step_test.moc"
