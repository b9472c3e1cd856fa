// SPDX-License-Identifier: MIT
#include "core/analysis/replay.hpp"
#include "core/base/text.hpp"
#include "core/contract/json_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <utility>

namespace pb {

namespace {

// Display precision of the written poses (see replay_to_json).
constexpr double kPositionScale = 1e5;  // 0.01 mm
constexpr double kQuatScale = 1e6;
// Largest accepted | |q| - 1 | of a quaternion read back.
constexpr double kUnitTolerance = 1e-3;
// An item count while reading when the pallet could not be read.
constexpr int kUnknown = -1;

// ---------------------------------------------------------------------------------------------
// Resampling.

// The state of the trace at time t, where time(j) <= t and, if j is not the last frame, t <
// time(j + 1).
ReplayFrame sample(const Trace& trace, std::size_t j, double t) {
  ReplayFrame out;
  out.t = t;
  const bool between = j + 1 < trace.size() && t > trace.time(j);
  const std::size_t k = between ? j + 1 : j;
  const double s = between ? (t - trace.time(j)) / (trace.time(k) - trace.time(j)) : 0.0;
  out.belt_x = trace.belt(j).x + s * (trace.belt(k).x - trace.belt(j).x);
  out.belt_y = trace.belt(j).y + s * (trace.belt(k).y - trace.belt(j).y);
  out.pallet = interpolate(trace.pallet(j), trace.pallet(k), s);
  const auto a = trace.items(j);
  const auto b = trace.items(k);
  out.items.reserve(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) out.items.push_back(interpolate(a[i], b[i], s));
  return out;
}

}  // namespace

Replay as_built_replay(const PalletConfig& pallet) {
  Replay r;
  r.pallet = pallet;
  ReplayFrame f;
  f.pallet.pos = {0.0, 0.0, pallet.base_dims_m[2] / 2.0};
  for (const Item& item : pallet.items) {
    Pose p;
    p.pos = item.center_of_mass();
    const double half = item.orientation_deg * std::numbers::pi / 360.0;
    p.quat = {std::cos(half), 0.0, 0.0, std::sin(half)};
    f.items.push_back(p);
  }
  r.frames.push_back(std::move(f));
  return r;
}

ReplayFrame frame_at(const Replay& replay, double t) {
  const auto& frames = replay.frames;
  if (frames.empty()) return {};
  if (!(t > frames.front().t)) return frames.front();  // also NaN
  if (t >= frames.back().t) return frames.back();
  const auto next = std::upper_bound(frames.begin(), frames.end(), t,
                                     [](double x, const ReplayFrame& f) { return x < f.t; });
  const ReplayFrame& a = *(next - 1);
  const ReplayFrame& b = *next;
  const double s = (t - a.t) / (b.t - a.t);
  ReplayFrame out;
  out.t = t;
  out.belt_x = a.belt_x + s * (b.belt_x - a.belt_x);
  out.belt_y = a.belt_y + s * (b.belt_y - a.belt_y);
  out.pallet = interpolate(a.pallet, b.pallet, s);
  out.items.reserve(a.items.size());
  for (std::size_t i = 0; i < a.items.size() && i < b.items.size(); ++i) {
    out.items.push_back(interpolate(a.items[i], b.items[i], s));
  }
  return out;
}

Json failure_to_json(const std::optional<FailureEvent>& failure) {
  if (!failure) return nullptr;
  Json j = {{"mode", to_string(failure->mode)},
            {"time_s", failure->time_s},
            {"value", failure->value},
            {"items", failure->items}};
  if (failure->mode == FailureMode::top_item_slide) {
    j["item_tilt_deg"] = failure->item_tilt_deg;
    j["least_item_move_m"] = failure->least_item_move_m;
  }
  return j;
}

namespace {

// ---------------------------------------------------------------------------------------------
// Writing.

double rounded(double value, double scale) {
  return std::round(value * scale) / scale + 0.0;  // + 0.0 turns -0 into 0
}

Json pose_to_json(const Pose& pose) {
  return Json::array({rounded(pose.pos[0], kPositionScale), rounded(pose.pos[1], kPositionScale),
                      rounded(pose.pos[2], kPositionScale), rounded(pose.quat[0], kQuatScale),
                      rounded(pose.quat[1], kQuatScale), rounded(pose.quat[2], kQuatScale),
                      rounded(pose.quat[3], kQuatScale)});
}

Json frame_to_json(const ReplayFrame& frame) {
  Json items = Json::array();
  for (const Pose& pose : frame.items) items.push_back(pose_to_json(pose));
  return {{"t", frame.t},
          {"belt", Json::array({rounded(frame.belt_x, kPositionScale),
                                rounded(frame.belt_y, kPositionScale)})},
          {"pallet", pose_to_json(frame.pallet)},
          {"items", std::move(items)}};
}

// ---------------------------------------------------------------------------------------------
// Reading.

std::string at(const std::string& pointer, std::string_view key) {
  return member_pointer(pointer, key);
}

std::string at(const std::string& pointer, std::size_t index) {
  return element_pointer(pointer, index);
}

// A pose [x, y, z, qw, qx, qy, qz] whose quaternion is of unit length (within kUnitTolerance).
bool read_pose(JsonReader& reader, const Json& json, const std::string& pointer, Pose& out) {
  std::array<double, 7> v{};
  if (!reader.numbers(json, pointer, v, "[x, y, z, qw, qx, qy, qz]")) return false;
  out.pos = {v[0], v[1], v[2]};
  out.quat = {v[3], v[4], v[5], v[6]};
  const double norm = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6]);
  if (std::abs(norm - 1.0) <= kUnitTolerance) return true;
  reader.error(pointer, "the quaternion (qw, qx, qy, qz) has length " + short_number(norm) +
                            "; write a unit quaternion");
  return false;
}

// A required member read into `out`.
template <class T>
bool required(JsonReader& reader, const Json& object, const std::string& pointer,
              std::string_view key, T& out) {
  return reader.field(object, pointer, key, out, Need::required);
}

// The failure modes a detector fires: every mode but no_failure.
constexpr auto kFiredModes = [] {
  std::array<std::string_view, EnumTable<FailureMode>::names.size() - 1> names{};
  std::size_t n = 0;
  for (const auto& entry : EnumTable<FailureMode>::names) {
    if (entry.value != FailureMode::no_failure) names[n++] = entry.name;
  }
  return names;
}();

std::optional<FailureEvent> read_failure(JsonReader& reader, const Json& json,
                                         const std::string& p) {
  if (!reader.object(json, p, "the failure",
                     "null or {\"mode\", \"time_s\", \"value\", \"items\"}")) {
    return std::nullopt;
  }
  reader.unknown_keys(json, p,
                      {"mode", "time_s", "value", "items", "item_tilt_deg", "least_item_move_m"});
  FailureEvent event;
  bool ok = true;
  if (const Json* mode = reader.member(json, p, "mode", Need::required)) {
    std::size_t index = 0;
    if (reader.choice(*mode, at(p, "mode"), kFiredModes, index)) {
      event.mode = *enum_from_string<FailureMode>(kFiredModes[index]);
    } else {
      ok = false;
    }
  } else {
    ok = false;
  }
  ok = required(reader, json, p, "time_s", event.time_s) && ok;
  ok = required(reader, json, p, "value", event.value) && ok;
  // Replays written before session 13 do not have it.
  ok = reader.field(json, p, "item_tilt_deg", event.item_tilt_deg, Need::optional) && ok;
  // Nor, before session 42, this one.
  ok = reader.field(json, p, "least_item_move_m", event.least_item_move_m, Need::optional) && ok;
  const std::string ip = at(p, "items");
  const Json* items = reader.member(json, p, "items", Need::required);
  if (items && reader.array(*items, ip, "the item indices", "[3, 7] or []")) {
    for (std::size_t k = 0; k < items->size(); ++k) {
      int index = 0;
      if (!reader.read((*items)[k], at(ip, k), index)) {
        ok = false;
      } else if (index < 0) {
        reader.error(at(ip, k), wording::out_of_range(std::to_string(index),
                                                      "an item index, a whole number >= 0"));
        ok = false;
      } else {
        event.items.push_back(index);
      }
    }
  } else {
    ok = false;
  }
  if (!ok) return std::nullopt;
  return event;
}

// Reads "outcome" and "failure" and checks that they agree and that the failure's items exist.
void read_verdict(JsonReader& reader, const Json& json, int n_items, Replay& out) {
  bool outcome_ok = false;
  if (const Json* outcome = reader.member(json, "", "outcome", Need::required)) {
    std::size_t index = 0;
    outcome_ok = reader.choice(*outcome, "/outcome", kReplayOutcomes, index);
    if (outcome_ok) out.outcome = kReplayOutcomes[index];
  }
  const Json* failure = reader.member(json, "", "failure", Need::required);
  if (!failure) return;
  if (!failure->is_null()) {
    out.failure = read_failure(reader, *failure, "/failure");
    if (!out.failure) return;
  }
  if (outcome_ok && out.failure.has_value() != (out.outcome == "failed")) {
    reader.error("/failure", out.failure ? "a failure is given but the outcome is \"" +
                                               out.outcome + "\"; write null or set \"failed\""
                                         : "the outcome is \"failed\" but the failure is null; "
                                           "write the failure event");
  }
  if (!out.failure || n_items == kUnknown) return;
  for (std::size_t k = 0; k < out.failure->items.size(); ++k) {
    if (out.failure->items[k] < n_items) continue;
    reader.error("/failure/items/" + std::to_string(k),
                 "item " + std::to_string(out.failure->items[k]) +
                     " does not exist (the pallet has " + std::to_string(n_items) +
                     " items); name an item of the pallet");
  }
}

// Reads one frame; `n_items` is the pallet's item count or kUnknown.
std::optional<ReplayFrame> read_frame(JsonReader& reader, const Json& json, const std::string& p,
                                      int n_items) {
  if (!reader.object(json, p, "a frame", "{\"t\", \"belt\", \"pallet\", \"items\"}")) {
    return std::nullopt;
  }
  reader.unknown_keys(json, p, {"t", "belt", "pallet", "items"});
  ReplayFrame frame;
  bool ok = required(reader, json, p, "t", frame.t);
  std::array<double, 2> belt{};
  const Json* belt_json = reader.member(json, p, "belt", Need::required);
  ok = belt_json && reader.numbers(*belt_json, at(p, "belt"), belt, "[x, y]") && ok;
  frame.belt_x = belt[0];
  frame.belt_y = belt[1];
  const Json* pallet = reader.member(json, p, "pallet", Need::required);
  ok = pallet && read_pose(reader, *pallet, at(p, "pallet"), frame.pallet) && ok;
  const Json* items = reader.member(json, p, "items", Need::required);
  if (!items) return std::nullopt;
  const std::string ip = at(p, "items");
  if (!reader.array(*items, ip, "the item poses",
                    "[[x, y, z, qw, qx, qy, qz], ...], one per item")) {
    return std::nullopt;
  }
  if (n_items != kUnknown && items->size() != static_cast<std::size_t>(n_items)) {
    reader.error(ip, "the frame has " + std::to_string(items->size()) +
                         " item poses but the pallet has " + std::to_string(n_items) +
                         " items; write one pose per item of the pallet");
    ok = false;
  }
  frame.items.resize(items->size());
  for (std::size_t i = 0; i < items->size(); ++i) {
    ok = read_pose(reader, (*items)[i], at(ip, i), frame.items[i]) && ok;
  }
  if (!ok) return std::nullopt;
  return frame;
}

void read_frames(JsonReader& reader, const Json& json, int n_items, std::vector<ReplayFrame>& out) {
  if (!reader.array(json, "/frames", "the frames", "[] or [{...}, ...]")) return;
  // Time of the previous frame that was read (-inf after a frame that could not be read).
  constexpr double kNone = -std::numeric_limits<double>::infinity();
  double previous_t = kNone;
  for (std::size_t k = 0; k < json.size(); ++k) {
    const std::string p = at("/frames", k);
    auto frame = read_frame(reader, json[k], p, n_items);
    if (!frame) {
      previous_t = kNone;
      continue;
    }
    if (!(frame->t > previous_t)) {
      reader.error(at(p, "t"), "t = " + short_number(frame->t) +
                                   " s does not come after the previous frame's " +
                                   short_number(previous_t) +
                                   " s; order the frames by increasing time");
    }
    previous_t = frame->t;
    out.push_back(std::move(*frame));
  }
}

}  // namespace

Replay make_replay(const Trace& trace, const PalletConfig& pallet, const ConveyorProfile& profile,
                   std::string outcome, std::optional<FailureEvent> failure, double hz) {
  Replay out{pallet, profile, std::move(outcome), std::move(failure), hz, {}};
  if (trace.empty() || !(hz > 0.0)) return out;
  const double first = trace.time(0);
  const double last = trace.time(trace.size() - 1);
  const auto grid = [hz](std::int64_t k) { return static_cast<double>(k) / hz; };
  // The first k with k / hz >= first, robust to rounding of first * hz.
  auto k = static_cast<std::int64_t>(std::ceil(first * hz));
  while (grid(k - 1) >= first) --k;
  while (grid(k) < first) ++k;
  // The failure's own instant is a frame too (the moment the detector fired, exactly), wherever
  // it falls between two grid times.
  const double fired = out.failure ? out.failure->time_s : 0.0;
  bool fired_placed = !out.failure || fired < first || fired > last;
  std::size_t j = 0;
  auto place = [&](double t) {
    while (j + 1 < trace.size() && trace.time(j + 1) <= t) ++j;
    out.frames.push_back(sample(trace, j, t));
  };
  for (; grid(k) <= last; ++k) {
    const double t = grid(k);
    if (!fired_placed && fired <= t) {
      if (fired < t) place(fired);
      fired_placed = true;
    }
    place(t);
  }
  if (!fired_placed && (out.frames.empty() || out.frames.back().t < fired)) place(fired);
  if (out.frames.empty() || out.frames.back().t != last) {
    out.frames.push_back(sample(trace, trace.size() - 1, last));
  }
  return out;
}

Json replay_to_json(const Replay& replay) {
  Json frames = Json::array();
  for (const ReplayFrame& frame : replay.frames) frames.push_back(frame_to_json(frame));
  return {{"schema_version", kSchemaVersion},
          {"pallet", pallet_to_json(replay.pallet)},
          {"profile", profile_to_json(replay.profile)},
          {"outcome", replay.outcome},
          {"failure", failure_to_json(replay.failure)},
          {"hz", replay.hz},
          {"frames", std::move(frames)}};
}

Result<Replay> replay_from_json(const Json& json) {
  JsonReader reader;
  if (!reader.object(json, "", "a replay",
                     "{\"pallet\", \"profile\", \"outcome\", \"failure\", \"hz\", "
                     "\"frames\"}")) {
    return Result<Replay>::failure(reader.diagnostics);
  }
  reader.schema_version(json, "");
  reader.unknown_keys(
      json, "", {"schema_version", "pallet", "profile", "outcome", "failure", "hz", "frames"});
  Replay out;
  std::optional<PalletConfig> pallet;
  if (const Json* p = reader.member(json, "", "pallet", Need::required)) {
    auto read = pallet_from_json(*p, "/pallet");
    reader.merge(read.diagnostics);
    pallet = std::move(read.value);
  }
  std::optional<ConveyorProfile> profile;
  if (const Json* p = reader.member(json, "", "profile", Need::required)) {
    auto read = profile_from_json(*p, "/profile");
    reader.merge(read.diagnostics);
    profile = std::move(read.value);
  }
  const int n_items = pallet ? static_cast<int>(pallet->items.size()) : kUnknown;
  read_verdict(reader, json, n_items, out);
  if (required(reader, json, "", "hz", out.hz) && !(out.hz > 0.0)) {
    reader.error("/hz",
                 wording::out_of_range(short_number(out.hz), "a frame rate above 0, e.g. 30"));
  }
  if (const Json* frames = reader.member(json, "", "frames", Need::required)) {
    read_frames(reader, *frames, n_items, out.frames);
  }
  if (has_errors(reader.diagnostics)) return Result<Replay>::failure(reader.diagnostics);
  out.pallet = std::move(*pallet);
  out.profile = std::move(*profile);
  return Result<Replay>{std::move(out), reader.diagnostics};
}

}  // namespace pb
