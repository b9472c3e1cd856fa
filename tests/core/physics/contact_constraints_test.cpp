// SPDX-License-Identifier: MIT
// make_contact_constraints against mj_makeConstraint, bit for bit, on an unwrapped load in motion:
// every field MuJoCo's version writes that the step reads afterwards, for contacts of three
// dimensions and of one (a sliding pair's), with impedances inside their transition zone and
// saturated; and where it cannot build the rows (a contact of four dimensions, a wrapped load's
// welds), it says so and leaves the data as it was.
#include "core/physics/contact_constraints.hpp"

#include <QtTest>

#include <cstring>
#include <string>
#include <vector>

#include "core/physics/engine.hpp"
#include "core/physics/probe_run.hpp"
#include "core/physics/step.hpp"
#include "tests/core/test_friction.hpp"
#include "tests/core/test_rig.hpp"

using namespace pb;

namespace {

// Two columns of three 12 kg cartons side by side, and a fourth across their tops: pairs of free
// bodies, cartons on the pallet, the pallet on the belt.
PalletConfig two_columns(WrapType wrap) {
  PalletConfig config;
  config.pallet_id = "contact-constraints-test";
  auto carton = [](double x, double y, double z, double w, double d) {
    Item item;
    item.sku = "TEST";
    item.weight_kg = 12.0;
    item.dims_m = {w, d, 0.2};
    item.position = {x, y, z};
    return item;
  };
  for (int level = 0; level < 3; ++level) {
    const double z = 0.15 + 0.2 * level;
    config.items.push_back(carton(-0.21, 0.0, z, 0.4, 0.3));
    config.items.push_back(carton(0.21, 0.0, z, 0.4, 0.3));
  }
  config.items.push_back(carton(0.0, 0.0, 0.75, 0.8, 0.3));
  config.wrap = wrap;
  config.env = Environment::thawed;
  config.body_temp_c = 20.0;
  config.seconds_since_temp_change = 3600.0;
  return config;
}

// A data at the rig's rest state, stepped `steps` times with the belt accelerating, its last body
// pressed `sink_m` further into what it rests on, then through mj_collision of the next step (the
// stage make_contact_constraints follows).
void at_collision(const test::Rig& rig, mjData* d, int steps, double sink_m = 0.0) {
  const mjModel* m = rig.scene->model.get();
  load_rest_state(rig.scene->layout, rig.rest, 0.0, *d);
  for (int k = 0; k < steps; ++k) {
    for (int a = 0; a < m->nu; ++a) d->ctrl[a] = 0.004 * k;  // the belt speeds up
    step(m, d);
  }
  const int last = m->njnt - 1;
  if (m->jnt_type[last] == mjJNT_FREE) d->qpos[m->jnt_qposadr[last] + 2] -= sink_m;
  mj_kinematics(m, d);
  mj_comPos(m, d);
  mj_crb(m, d);
  mj_factorM(m, d);
  mj_collision(m, d);
}

template <typename T>
bool same(const T* a, const T* b, int n) {
  return n <= 0 || std::memcmp(a, b, sizeof(T) * std::size_t(n)) == 0;
}

// Every field of the constraint rows, compared bitwise; empty when all agree.
std::string difference(const mjData* a, const mjData* b) {
  if (a->nefc != b->nefc || a->ne != b->ne || a->nf != b->nf) return "nefc";
  const int n = a->nefc;
  if (!same(a->efc_J_rownnz, b->efc_J_rownnz, n)) return "efc_J_rownnz";
  if (!same(a->efc_J_rowadr, b->efc_J_rowadr, n)) return "efc_J_rowadr";
  if (!same(a->efc_J_rowsuper, b->efc_J_rowsuper, n)) return "efc_J_rowsuper";
  const int nnz = n ? a->efc_J_rowadr[n - 1] + a->efc_J_rownnz[n - 1] : 0;
  if (!same(a->efc_J_colind, b->efc_J_colind, nnz)) return "efc_J_colind";
  if (!same(a->efc_J, b->efc_J, nnz)) return "efc_J";
  if (!same(a->efc_type, b->efc_type, n)) return "efc_type";
  if (!same(a->efc_id, b->efc_id, n)) return "efc_id";
  if (!same(a->efc_pos, b->efc_pos, n)) return "efc_pos";
  if (!same(a->efc_margin, b->efc_margin, n)) return "efc_margin";
  if (!same(a->efc_frictionloss, b->efc_frictionloss, n)) return "efc_frictionloss";
  if (!same(a->efc_diagApprox, b->efc_diagApprox, n)) return "efc_diagApprox";
  if (!same(a->efc_R, b->efc_R, n)) return "efc_R";
  if (!same(a->efc_D, b->efc_D, n)) return "efc_D";
  if (!same(a->efc_KBIP, b->efc_KBIP, 4 * n)) return "efc_KBIP";
  if (a->ncon != b->ncon || a->maxuse_con != b->maxuse_con || a->maxuse_efc != b->maxuse_efc) {
    return "ncon or maxuse";
  }
  for (int i = 0; i < a->ncon; ++i) {
    const mjContact &x = a->contact[i], &y = b->contact[i];
    if (x.efc_address != y.efc_address || x.exclude != y.exclude ||
        std::memcmp(&x.mu, &y.mu, sizeof x.mu) != 0) {
      return "contact " + std::to_string(i);
    }
  }
  return {};
}

}  // namespace

class ContactConstraintsTest : public QObject {
  Q_OBJECT

 private slots:
  void buildsWhatMjMakeConstraintBuildsToTheBit() {
    test::Rig rig = test::settled_rig(two_columns(WrapType::none),
                                      test::constant_friction({1.0, 0.4, 0.4, 0.75}));
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    const mjModel* m = rig.scene->model.get();
    QVERIFY(contact_constraints_apply(m));
    auto ours = make_data(m);
    auto theirs = make_data(m);
    int in_zone = 0, saturated = 0, single = 0;
    for (int steps : {0, 40, 160}) {
      // After 40 steps, the top carton 2 mm into its supports: beyond the impedance's 1 mm zone.
      at_collision(rig, theirs->get(), steps, steps == 40 ? 0.002 : 0.0);
      mjData* t = theirs->get();
      // A sliding pair's contacts are frictionless (step.cpp): make every fifth one so.
      for (int i = 0; i < t->ncon; i += 5) t->contact[i].dim = 1;
      mj_copyData(ours->get(), m, t);
      mj_makeConstraint(m, t);
      QVERIFY(make_contact_constraints(m, ours->get()));
      const std::string diff = difference(ours->get(), t);
      QVERIFY2(diff.empty(),
               qPrintable(QString("after %1 steps: %2").arg(steps).arg(diff.c_str())));
      QVERIFY(t->nefc > 0);
      for (int i = 0; i < t->ncon; ++i) {
        const mjContact& c = t->contact[i];
        const double x = -(c.dist - c.includemargin) / c.solimp[2];
        (x > 0 && x < 1 ? in_zone : saturated) += 1;
        single += c.dim == 1 ? 1 : 0;
      }
    }
    // Both branches of the impedance and both kinds of contact were compared.
    QVERIFY(in_zone > 0);
    QVERIFY(saturated > 0);
    QVERIFY(single > 0);
  }

  void refusesWhatItCannotBuildAndLeavesTheDataAlone() {
    test::Rig rig = test::settled_rig(two_columns(WrapType::none),
                                      test::constant_friction({1.0, 0.4, 0.4, 0.75}));
    QVERIFY2(rig.error.empty(), rig.error.c_str());
    const mjModel* m = rig.scene->model.get();
    auto data = make_data(m);
    mjData* d = data->get();
    at_collision(rig, d, 10);
    QVERIFY(d->ncon > 1);
    d->nefc = 17;           // left from an earlier step
    d->contact[1].dim = 4;  // torsional friction: rows this file does not build
    const int address = d->contact[0].efc_address;
    QVERIFY(!make_contact_constraints(m, d));
    QCOMPARE(d->nefc, 17);
    QCOMPARE(d->contact[0].efc_address, address);

    // A wrapped load's welds are equality constraints: not accepted at all.
    test::Rig wrapped = test::settled_rig(two_columns(WrapType::stretch),
                                          test::constant_friction({1.0, 0.4, 0.4, 0.75}));
    QVERIFY2(wrapped.error.empty(), wrapped.error.c_str());
    QVERIFY(!contact_constraints_apply(wrapped.scene->model.get()));
  }
};

QTEST_GUILESS_MAIN(ContactConstraintsTest)
#include "contact_constraints_test.moc"
