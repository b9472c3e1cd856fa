// SPDX-License-Identifier: MIT
// The enumerations of the contract and their JSON names (the reference system's strings).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace pb {

enum class Fragility { rigid, semi_rigid, deformable };
enum class WrapType { none, shrink, stretch, banded };
enum class Environment { frozen, refrigerated, thawed, transitioning };
/// cannot_stand is ours: the load moves with the belt standing still (a build defect: no conveyor
/// limit is given for it).
enum class FailureMode {
  no_failure,
  tip_over,
  top_item_slide,
  pallet_slip,
  load_shift,
  cannot_stand
};
enum class ProfileShape { accel_hold, constant, ramp_decel, estop, curve, eumos };
/// Which way a curve turns, for a load riding along +X: left (its centre on the +Y side, so the
/// load is pushed towards -Y) or right.
enum class CurveTurn { left, right };
/// Pallet base types. The base's surface material (wood or plastic) follows from the type.
enum class PalletType { eur, gma, chep };
/// What the pallet rides on (our addition; the reference assumed a rubber belt).
enum class BeltSurface { rubber_belt, steel_roller };
/// Layer patterns a scanner reports.
enum class LayerPattern { column, brick, pinwheel, irregular };
/// The model level that answers (core/analysis/fidelity.hpp): `automatic` asks for the cheapest
/// whose agreement with the full model is established; a result names the level that ran.
enum class Fidelity { automatic, closed_form, reduced, clustered, full };
/// A SafetyResult's verdict: ok, or reject (unsafe at any motion, or a load that cannot stand).
enum class Verdict { ok, reject };
/// What sets a SafetyResult's max_speed_mps: the line's e-stop, its tightest curve, the top of the
/// search range, a rejected pallet or a build defect (both 0). `unset` only in a result
/// no analysis produced.
enum class SpeedGovernor { unset, estop, curve, ceiling, reject, build_defect };
/// How a top_item_slide (the reference's word for any item moving 5 cm on its pallet) went, as
/// measured (core/physics/detectors.hpp: item_tipped, load_slid_as_one): an item slid flat, an
/// item tipped over an edge, or the whole load slid on its pallet together. Ours.
enum class SlideKind { item_slid, item_tipped, load_as_one };

template <class E>
struct EnumName {
  E value;
  std::string_view name;
};

/// EnumTable<E>::names lists every value of E with its JSON name, in declaration order.
template <class E>
struct EnumTable;

template <>
struct EnumTable<Fragility> {
  static constexpr std::array<EnumName<Fragility>, 3> names{
      {{Fragility::rigid, "rigid"},
       {Fragility::semi_rigid, "semi_rigid"},
       {Fragility::deformable, "deformable"}}};
};
template <>
struct EnumTable<WrapType> {
  static constexpr std::array<EnumName<WrapType>, 4> names{{{WrapType::none, "none"},
                                                            {WrapType::shrink, "shrink"},
                                                            {WrapType::stretch, "stretch"},
                                                            {WrapType::banded, "banded"}}};
};
template <>
struct EnumTable<Environment> {
  static constexpr std::array<EnumName<Environment>, 4> names{
      {{Environment::frozen, "frozen"},
       {Environment::refrigerated, "refrigerated"},
       {Environment::thawed, "thawed"},
       {Environment::transitioning, "transitioning"}}};
};
template <>
struct EnumTable<FailureMode> {
  static constexpr std::array<EnumName<FailureMode>, 6> names{
      {{FailureMode::no_failure, "no_failure"},
       {FailureMode::tip_over, "tip_over"},
       {FailureMode::top_item_slide, "top_item_slide"},
       {FailureMode::pallet_slip, "pallet_slip"},
       {FailureMode::load_shift, "load_shift"},
       {FailureMode::cannot_stand, "cannot_stand"}}};
};
template <>
struct EnumTable<CurveTurn> {
  static constexpr std::array<EnumName<CurveTurn>, 2> names{
      {{CurveTurn::left, "left"}, {CurveTurn::right, "right"}}};
};
template <>
struct EnumTable<ProfileShape> {
  static constexpr std::array<EnumName<ProfileShape>, 6> names{
      {{ProfileShape::accel_hold, "accel_hold"},
       {ProfileShape::constant, "constant"},
       {ProfileShape::ramp_decel, "ramp_decel"},
       {ProfileShape::estop, "estop"},
       {ProfileShape::curve, "curve"},
       {ProfileShape::eumos, "eumos"}}};
};
template <>
struct EnumTable<PalletType> {
  static constexpr std::array<EnumName<PalletType>, 3> names{
      {{PalletType::eur, "EUR"}, {PalletType::gma, "GMA"}, {PalletType::chep, "CHEP"}}};
};
template <>
struct EnumTable<BeltSurface> {
  static constexpr std::array<EnumName<BeltSurface>, 2> names{
      {{BeltSurface::rubber_belt, "rubber_belt"}, {BeltSurface::steel_roller, "steel_roller"}}};
};
template <>
struct EnumTable<LayerPattern> {
  static constexpr std::array<EnumName<LayerPattern>, 4> names{
      {{LayerPattern::column, "column"},
       {LayerPattern::brick, "brick"},
       {LayerPattern::pinwheel, "pinwheel"},
       {LayerPattern::irregular, "irregular"}}};
};

template <>
struct EnumTable<Fidelity> {
  static constexpr std::array<EnumName<Fidelity>, 5> names{{{Fidelity::automatic, "auto"},
                                                            {Fidelity::closed_form, "closed_form"},
                                                            {Fidelity::reduced, "reduced"},
                                                            {Fidelity::clustered, "clustered"},
                                                            {Fidelity::full, "full"}}};
};
template <>
struct EnumTable<Verdict> {
  static constexpr std::array<EnumName<Verdict>, 2> names{
      {{Verdict::ok, "ok"}, {Verdict::reject, "reject"}}};
};
template <>
struct EnumTable<SpeedGovernor> {
  static constexpr std::array<EnumName<SpeedGovernor>, 6> names{
      {{SpeedGovernor::unset, "unset"},
       {SpeedGovernor::estop, "estop"},
       {SpeedGovernor::curve, "curve"},
       {SpeedGovernor::ceiling, "ceiling"},
       {SpeedGovernor::reject, "reject"},
       {SpeedGovernor::build_defect, "build_defect"}}};
};
template <>
struct EnumTable<SlideKind> {
  static constexpr std::array<EnumName<SlideKind>, 3> names{
      {{SlideKind::item_slid, "item_slid"},
       {SlideKind::item_tipped, "item_tipped"},
       {SlideKind::load_as_one, "load_as_one"}}};
};

/// The JSON name of a value.
template <class E>
constexpr std::string_view to_string(E value) {
  for (const auto& entry : EnumTable<E>::names) {
    if (entry.value == value) return entry.name;
  }
  return "?";
}

/// The value with this JSON name (exact, case-sensitive), or nullopt.
template <class E>
constexpr std::optional<E> enum_from_string(std::string_view name) {
  for (const auto& entry : EnumTable<E>::names) {
    if (entry.name == name) return entry.value;
  }
  return std::nullopt;
}

/// The accepted names, for error messages: "none, shrink, stretch or banded".
template <class E>
std::string enum_choices() {
  std::string out;
  const auto& names = EnumTable<E>::names;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += (i + 1 == names.size()) ? " or " : ", ";
    out += names[i].name;
  }
  return out;
}

}  // namespace pb
