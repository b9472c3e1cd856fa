// SPDX-License-Identifier: MIT
#include "app/server/service.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <exception>
#include <random>
#include <tuple>
#include <variant>

#include "app/server/reference_api.hpp"
#include "core/analysis/explain.hpp"
#include "core/analysis/replay.hpp"
#include "core/analysis/result_json.hpp"
#include "core/analysis/uncertainty.hpp"
#include "core/base/text.hpp"
#include "core/contract/json_io.hpp"
#include "core/contract/json_reader.hpp"
#include "core/inputs/catalog.hpp"
#include "core/inputs/friction.hpp"
#include "core/inputs/pallet_source.hpp"
#include "core/inputs/random_pallet.hpp"
#include "core/inputs/scenario.hpp"
#include "core/inputs/validation.hpp"
#include "core/physics/scene.hpp"

namespace pb::server {

using Params = std::map<std::string, std::string>;

namespace {

// ---- responses ----

Response json_response(int status, const Json& body) {
  Response r;
  r.status = status;
  r.body = body.dump(-1, ' ', false, Json::error_handler_t::replace);
  return r;
}

/// {"detail": sentence, "errors": [{"pointer", "message"}]}: "detail" as the reference's
/// (FastAPI's) clients read it, "errors" as ours (the CLI's pointers and sentences).
/// "errors" is never empty: a refusal with no member to point at carries its sentence there too
/// (pointer "", the whole request), so a client that reads only "errors" still learns why.
Response error_response(int status, const std::string& detail, const Diagnostics& errors = {}) {
  const Diagnostics listed = errors.empty() ? Diagnostics{{"", detail, Severity::error}} : errors;
  return json_response(status, {{"detail", detail}, {"errors", diagnostics_to_json(listed)}});
}

Response diagnostics_response(int status, const Diagnostics& diagnostics) {
  const Diagnostics errors = errors_of(diagnostics);
  // "detail" is read by people: many items' one problem is told once (the list keeps them all).
  std::string detail;
  for (const auto& d : condensed(errors)) {
    detail += (detail.empty() ? "" : "; ") + (d.pointer.empty() ? d.message : to_string(d));
  }
  if (detail.empty()) detail = "the request was refused";
  return error_response(status, detail, errors);
}

/// A run that ended without a verdict: 200, "unstable" and its reason (never limits).
Response no_verdict(const std::string& reason) {
  return json_response(200, {{"result", nullptr}, {"unstable", true}, {"reason", reason}});
}

/// Work the pool did not do or stopped: busy or stopped by the deadline, by the client going
/// away (nobody reads this answer; 499, as proxies log it) or by the service stopping.
Response refusal_response(const Refusal& refusal, const Ticket& ticket) {
  if (refusal.kind == Refusal::busy) {
    Response r = error_response(503, refusal.message);
    r.headers["Retry-After"] = "1";
    return r;
  }
  switch (ticket.reason()) {
    case StopReason::client_gone:
      return error_response(499, "the client closed the connection; the work was stopped");
    case StopReason::shutdown:
      return error_response(503, "the service is shutting down; retry on another instance");
    default:
      return error_response(
          503, "the work took longer than this service's limit of " +
                   short_number(ticket.time_limit_s()) +
                   " s per request and was stopped (--time-limit); nothing of it is cached. "
                   "Retry later, or ask the operator for a longer limit");
  }
}

/// Core diagnostics of a pallet read at `prefix`: pointers moved into the request's document. The
/// Analyzer's "/profile/..." already is the request's profile (read at /profile). The line is the
/// service's (--curve-radius), which no request sets: what it says is about the whole request.
Diagnostics located(Diagnostics diagnostics, const std::string& prefix) {
  for (auto& d : diagnostics) {
    if (d.pointer == kLineRadiusPointer) {
      d.pointer.clear();
      d.message = "this service's line (its --curve-radius) cannot carry this pallet: " + d.message;
    } else if (!d.pointer.empty() && !d.pointer.starts_with("/profile/")) {
      d.pointer = prefix + d.pointer;
    }
  }
  return diagnostics;
}

/// A core failure: the input's fault (422) when a diagnostic points into it, else a run without
/// a verdict (the engine or instability: 200, "unstable").
Response core_failure(const Diagnostics& diagnostics, const std::string& prefix) {
  for (const auto& d : errors_of(diagnostics)) {
    if (!d.pointer.empty()) return diagnostics_response(422, located(diagnostics, prefix));
  }
  std::string reason;
  for (const auto& d : errors_of(diagnostics)) reason += (reason.empty() ? "" : "; ") + d.message;
  return no_verdict(reason.empty() ? "the engine gave no verdict" : reason);
}

// ---- reading requests ----

using Read = std::variant<Json, Response>;

Read parse_body(const Request& request) {
  if (request.body.empty()) {
    return error_response(400,
                          "the request has no body; send JSON (content-type: application/json)");
  }
  auto json = parse_json(request.body);
  if (!json) return diagnostics_response(400, json.diagnostics);
  return std::move(*json.value);
}

/// A valid pallet from `json` (read at `prefix`), or the response that says why not: 413 over the
/// item limit (before any work), 422 with every error otherwise. Warnings come with the pallet.
/// A pallet is also refused where the service's analyzers could not simulate it (no friction data
/// for a pair, a scene larger than the engine holds: Analyzer::simulation_problems), so a
/// validation that passes is one an analysis will not refuse.
struct PalletReading {
  std::size_t max_items = 400;
  AnalyzerOptions analyzer;
};

/// What read_pallet finds: a refusal before the pallet is read (not an object, too many items),
/// or the pallet as read, if it could be, with every finding, errors and warnings.
struct PalletFindings {
  std::optional<Response> refused;
  std::optional<PalletConfig> config;
  Diagnostics diagnostics;
};

PalletFindings check_pallet(const Json& json, const std::string& prefix,
                            const PalletReading& reading) {
  const std::size_t max_items = reading.max_items;
  if (!json.is_object()) {
    return {error_response(
                422, (prefix.empty() ? "the body" : prefix) + " must be a PalletConfig JSON object",
                {{prefix, "must be a PalletConfig JSON object", Severity::error}}),
            std::nullopt,
            {}};
  }
  if (auto it = json.find("items"); it != json.end() && it->is_array() && it->size() > max_items) {
    const std::string message =
        "the pallet has " + std::to_string(it->size()) + " items; this service analyses at most " +
        std::to_string(max_items) + " (--max-items); split the load" +
        (max_items < ValidationLimits{}.max_items ? " or ask for a larger limit" : "");
    return {error_response(413, message, {{prefix + "/items", message, Severity::error}}),
            std::nullopt,
            {}};
  }
  auto pallet = pallet_from_json(json, prefix);
  if (!pallet) return {std::nullopt, std::nullopt, pallet.diagnostics};
  Diagnostics diags = pallet.diagnostics;
  for (auto d : validate(*pallet.value)) {
    d.pointer = prefix + d.pointer;
    diags.push_back(std::move(d));
  }
  if (!has_errors(diags)) {
    for (auto d : Analyzer(reading.analyzer).simulation_problems(*pallet.value)) {
      d.pointer = prefix + d.pointer;
      diags.push_back(std::move(d));
    }
  }
  return {std::nullopt, std::move(*pallet.value), std::move(diags)};
}

/// A valid pallet's findings from the service's line (--curve-radius): an analysis refuses a
/// pallet its curves would turn about a point under it, so its validation says so too.
Diagnostics line_findings(const PalletConfig& config, const PalletReading& reading) {
  return located(Analyzer(reading.analyzer).line_radius_problem(config), "");
}

/// A valid pallet, or the response that refuses it (see check_pallet).
std::variant<Result<PalletConfig>, Response> read_pallet(const Json& json,
                                                         const std::string& prefix,
                                                         const PalletReading& reading) {
  PalletFindings found = check_pallet(json, prefix, reading);
  if (found.refused) return std::move(*found.refused);
  if (!found.config || has_errors(found.diagnostics)) {
    return diagnostics_response(422, found.diagnostics);
  }
  return Result<PalletConfig>{std::move(*found.config), std::move(found.diagnostics)};
}

/// A /v1/ request that wraps its pallet ({"pallet": ..., ...}) may hold only the members its route
/// reads: one misspelt ("samples" as "sample") or not taken per request (the line is the
/// service's own, from its flags) would otherwise be ignored and the answer computed without it.
/// 422 with an error at each such member. The reference API's routes ignore extra members, as
/// its clients expect.
std::optional<Response> unknown_members(const Json& body,
                                        std::initializer_list<std::string_view> known) {
  if (!body.is_object() || !body.contains("pallet")) return std::nullopt;
  std::string reads;
  for (std::size_t i = 0; i < known.size(); ++i) {
    reads += std::string(i == 0                  ? ""
                         : i + 1 == known.size() ? " and "
                                                 : ", ") +
             "'" + std::string(known.begin()[i]) + "'";
  }
  Diagnostics errors;
  for (const auto& [key, value] : body.items()) {
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    std::string message = "unknown member '" + key + "'; this route reads " + reads +
                          ": remove it or fix its spelling";
    if (key == "line") {
      message =
          "the line is this service's own (its --estop-decel and --curve-radius; every "
          "analysis says it under 'line'), not a member of a request: remove 'line'";
    }
    errors.push_back({member_pointer("", key), std::move(message), Severity::error});
  }
  if (errors.empty()) return std::nullopt;
  return diagnostics_response(422, errors);
}

/// A number from a JSON member (absent: `fallback`), in [lo, hi], `whole` for a count or a seed
/// (2.5 samples is refused, not run as 2); an error naming the member.
std::variant<double, Response> number_member(const Json& body, const std::string& key,
                                             double fallback, double lo, double hi,
                                             bool whole = false) {
  if (!body.is_object() || !body.contains(key) || body[key].is_null()) return fallback;
  const Json& v = body[key];
  if (!v.is_number() || !(v.get<double>() >= lo && v.get<double>() <= hi) ||
      (whole && v.get<double>() != std::floor(v.get<double>()))) {
    const std::string what = std::string("must be a ") + (whole ? "whole " : "") + "number from " +
                             short_number(lo) + " to " + short_number(hi);
    return error_response(422, "/" + key + " " + what, {{"/" + key, what, Severity::error}});
  }
  return v.get<double>();
}

/// A query parameter as a number (absent: `fallback`), in [lo, hi], `whole` for a count.
std::variant<double, Response> number_param(const Request& request, const std::string& key,
                                            std::optional<double> fallback, double lo, double hi,
                                            bool whole = false) {
  auto it = request.query.find(key);
  const std::string range = std::string("a ") + (whole ? "whole " : "") + "number from " +
                            short_number(lo) + " to " + short_number(hi);
  if (it == request.query.end()) {
    if (fallback) return *fallback;
    return error_response(422, "the query parameter '" + key + "' is required: " + range);
  }
  const std::string& text = it->second;
  double v = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || !(v >= lo && v <= hi) ||
      (whole && v != std::floor(v))) {
    return error_response(422, "the query parameter '" + key + "' is '" + text + "'; use " + range);
  }
  return v;
}

/// A boolean JSON member (absent or null: `fallback`); an error naming the member otherwise.
std::variant<bool, Response> bool_member(const Json& body, const std::string& key, bool fallback) {
  if (!body.is_object() || !body.contains(key) || body[key].is_null()) return fallback;
  if (!body[key].is_boolean()) {
    return error_response(422, "/" + key + " must be true or false",
                          {{"/" + key, "must be true or false", Severity::error}});
  }
  return body[key].get<bool>();
}

template <class T>
bool holds_response(const std::variant<T, Response>& v) {
  return std::holds_alternative<Response>(v);
}

/// A member's refusal, or nullptr when it was read.
template <class T>
const Response* refusal_in(const std::variant<T, Response>& v) {
  return std::get_if<Response>(&v);
}

/// One answer for a request whose members were each read on their own (a pallet and a profile,
/// a pallet and its grids): the first refusal, with the errors of every later member that is
/// unprocessable too (both 422) added to its "errors" and "detail", so that a client fixes them
/// all at once rather than learning of the next after fixing the first. nullopt: all were read.
std::optional<Response> refusal_of(std::initializer_list<const Response*> refusals) {
  std::optional<Response> out;
  Json merged;
  for (const Response* r : refusals) {
    if (r == nullptr) continue;
    if (!out) {
      out = *r;
      if (r->status == 422) merged = Json::parse(r->body);
    } else if (out->status == 422 && r->status == 422) {
      const Json more = Json::parse(r->body);
      merged["detail"] =
          merged["detail"].get<std::string>() + "; " + more["detail"].get<std::string>();
      for (const Json& e : more["errors"]) merged["errors"].push_back(e);
      *out = json_response(422, merged);
    }
  }
  return out;
}

/// The body's "profile", read and validated, with its warnings. `strict` (a /v1/ route): the
/// profile is required and a member a profile does not have is refused at its pointer, as the
/// body's own unknown members are ("speed_mps" for "target_speed_mps" would otherwise leave the
/// default 0.5 m/s in force and answer for a profile nobody asked for). The reference's route
/// keeps its clients' leniency: absent, the default profile; an unknown member, a warning.
std::variant<Result<ConveyorProfile>, Response> read_profile(const Json& body, bool strict) {
  if (!body.contains("profile")) {
    if (strict) {
      return error_response(422, "/profile is required: the conveyor profile to simulate",
                            {{"/profile",
                              "is required: a ConveyorProfile such as {\"target_speed_mps\": 1, "
                              "\"accel_mps2\": 2}",
                              Severity::error}});
    }
    return Result<ConveyorProfile>{ConveyorProfile{}, {}};
  }
  Result<ConveyorProfile> p = profile_from_json(body["profile"], "/profile");
  if (strict) {  // a profile's only warnings are its unknown members
    for (Diagnostic& d : p.diagnostics) {
      if (d.severity != Severity::warning) continue;
      d.severity = Severity::error;
      d.message = "'" + d.pointer.substr(d.pointer.rfind('/') + 1) +
                  "' is not a member of a conveyor profile: it would be ignored and its default "
                  "run instead; fix its spelling (target_speed_mps, accel_mps2, decel_mps2, ...) "
                  "or remove it";
    }
  }
  if (has_errors(p.diagnostics)) return diagnostics_response(422, p.diagnostics);
  Diagnostics checked = validate_profile(*p.value, "/profile");
  if (has_errors(checked)) return diagnostics_response(422, checked);
  p.diagnostics.insert(p.diagnostics.end(), checked.begin(), checked.end());
  return p;
}

std::string known_pairs() {
  std::string out;
  for (const auto& k : FrictionModel::builtin().pair_keys()) out += (out.empty() ? "" : ", ") + k;
  return out;
}

// ---- the service's own answers ----

Json axis_json(const AxisLimit& a, bool lateral = false) {
  Json j = {{"limit", a.limit},       {"mode", to_string(a.mode)},    {"at_ceiling", a.at_ceiling},
            {"at_floor", a.at_floor}, {"closed_form", a.closed_form}, {"probes", a.probes},
            {"derived", a.derived}};
  if (lateral) j["turn"] = to_string(a.turn);
  return j;
}

Json explain_json(const SafetyResult& result) {
  const Grade g = grade(result);
  return {{"grade", std::string(1, g.letter)},
          {"label", g.label},
          {"advice", g.advice},
          {"reason", result.reason},
          {"compared_with", "the fixed table the line runs today: " + short_number(kTableSpeedMps) +
                                " m/s, start-up " + short_number(kTableAccelMps2) + " m/s^2"}};
}

struct AxisChoice {
  Axis axis;
  const AxisLimit* limit;
  double lo, hi, precision;
};

std::vector<AxisChoice> axes_of(const Envelope& env, const SearchConfig& s) {
  return {{Axis::accel, &env.accel, s.accel_min_mps2, s.accel_max_mps2, s.accel_precision_mps2},
          {Axis::decel, &env.decel, s.decel_min_mps2, s.decel_max_mps2, s.decel_precision_mps2},
          {Axis::lateral, &env.lateral, s.lateral_min_g, s.lateral_max_g, s.lateral_precision_g},
          {Axis::speed, &env.speed, s.speed_min_mps, s.speed_max_mps, s.speed_precision_mps}};
}

ConveyorProfile probe_profile(Axis axis, double value, CurveTurn turn, const LineDescription& line,
                              const SearchConfig& s) {
  switch (axis) {
    case Axis::accel:
      return accel_probe_profile(value, s);
    case Axis::decel:
      return decel_probe_profile(value, s.speed_max_mps, s);
    case Axis::lateral:
      return lateral_probe_profile(value, line, s, turn);
    case Axis::speed:
      return stop_probe_profile(value, line, s);
  }
  return {};
}

}  // namespace

// ---- the routes ----

Service::Service(ServiceOptions options) : options_(std::move(options)), pool_(options_.pool) {
  const PalletReading reading{options_.max_items, options_.pool.analyzer};
  auto ticket_for = [this](const Request& request) {
    return std::make_unique<Ticket>(std::chrono::duration_cast<Ticket::Clock::duration>(
                                        std::chrono::duration<double>(options_.time_limit_s)),
                                    request.client_alive);
  };
  const AnalyzerOptions& ao = options_.pool.analyzer;

  // The path every analysing route shares: the body read, its pallet (the body, or its "pallet")
  // validated, then `check` on the body before any work, then the envelope from the pool.
  struct Analysed {
    Json body;
    std::string prefix;  ///< where the pallet is in the body: "" or "/pallet"
    Result<PalletConfig> config;
    std::unique_ptr<Ticket> ticket;
    Analysis analysis;
  };
  using Check = std::function<std::optional<Response>(const Json& body, bool wrapped)>;
  auto analysed = [this, reading, ticket_for](
                      const Request& request,
                      const Check& check) -> std::variant<Analysed, Response> {
    auto parsed = parse_body(request);
    if (holds_response(parsed)) return std::get<Response>(parsed);
    Analysed a;
    a.body = std::move(std::get<Json>(parsed));
    auto pallet = read_pallet(pallet_member(a.body, a.prefix), a.prefix, reading);
    if (holds_response(pallet)) return std::get<Response>(pallet);
    a.config = std::move(std::get<Result<PalletConfig>>(pallet));
    if (check) {
      if (auto refused = check(a.body, !a.prefix.empty())) return *refused;
    }
    a.ticket = ticket_for(request);
    auto analysis = pool_.analyze(*a.ticket, *a.config);
    if (auto* r = std::get_if<Refusal>(&analysis)) return refusal_response(*r, *a.ticket);
    if (auto* d = std::get_if<Diagnostics>(&analysis)) return core_failure(*d, a.prefix);
    a.analysis = std::move(std::get<Analysis>(analysis));
    return a;
  };

  auto get = [this](std::string pattern, auto handler, std::vector<std::string> query = {}) {
    routes_.push_back({"GET", std::move(pattern), handler, std::move(query)});
  };
  auto post = [this](std::string pattern, auto handler, std::vector<std::string> query = {}) {
    routes_.push_back({"POST", std::move(pattern), handler, std::move(query)});
  };

  get("/", [this](const Request&, const Params&) {
    Json list = Json::array();
    for (const auto& r : routes_) list.push_back(r.method + " " + r.pattern);
    return json_response(
        200, {{"service", "palletballet-server"}, {"version", options_.version}, {"routes", list}});
  });
  get("/healthz", [this](const Request&, const Params&) {
    const PoolStats s = pool_.stats();
    return json_response(200, {{"status", "ok"},
                               {"version", options_.version},
                               {"analyzers", s.analyzers},
                               {"busy", s.busy},
                               {"queue_depth", s.waiting},
                               {"cached_envelopes", s.cached_envelopes}});
  });
  get("/metrics", [this](const Request&, const Params&) {
    Response r;
    r.body = metrics_.text(pool_.stats());
    r.content_type = "text/plain; version=0.0.4";
    return r;
  });

  // -- scenarios, catalog, friction --
  get("/scenarios", [](const Request&, const Params&) {
    Json list = Json::array();
    for (const auto& s : all_scenarios()) list.push_back(scenario_summary_json(s));
    return json_response(200, list);
  });
  get("/scenarios/{slug}", [](const Request&, const Params& p) {
    auto scenario = load_scenario(p.at("slug"));
    if (!scenario) return diagnostics_response(404, scenario.diagnostics);
    return json_response(200, scenario_to_json(*scenario));
  });
  get("/catalog/skus", [](const Request&, const Params&) {
    Json list = Json::array();
    for (const auto& t : Catalog::builtin().all()) list.push_back(sku_info_json(t));
    return json_response(200, list);
  });
  get("/catalog/skus/{sku}", [](const Request&, const Params& p) {
    const SkuTemplate* t = Catalog::builtin().find(p.at("sku"));
    if (t == nullptr) {
      return error_response(404, "no SKU '" + p.at("sku") +
                                     "' in the catalog; GET /catalog/skus "
                                     "lists them");
    }
    return json_response(200, sku_info_json(*t));
  });
  auto pair_param = [](const Request& request) -> std::variant<std::string, Response> {
    auto it = request.query.find("pair");
    const std::string pair = it == request.query.end() ? "wood_pallet/rubber_belt" : it->second;
    if (FrictionModel::builtin().find(pair) == nullptr) {
      return error_response(
          422, "the query parameter 'pair' is '" + pair + "'; use one of " + known_pairs());
    }
    return pair;
  };
  get("/friction/pairs", [](const Request&, const Params&) {
    return json_response(200, FrictionModel::builtin().pair_keys());
  });
  get("/friction",
      [pair_param](const Request& request, const Params&) {
        auto pair = pair_param(request);
        if (holds_response(pair)) return std::get<Response>(pair);
        auto t = number_param(request, "temp_c", std::nullopt, kMinTempC, kMaxTempC);
        if (holds_response(t)) return std::get<Response>(t);
        auto since = number_param(request, "seconds_since_temp_change", 3600.0, 0.0, 1e9);
        if (holds_response(since)) return std::get<Response>(since);
        const auto value = FrictionModel::builtin().effective(
            std::get<std::string>(pair), std::get<double>(t), std::get<double>(since));
        return json_response(200, friction_point_json(std::get<double>(t), *value));
      },
      {"pair", "temp_c", "seconds_since_temp_change"});
  get("/friction/curve",
      [pair_param](const Request& request, const Params&) {
        auto pair = pair_param(request);
        if (holds_response(pair)) return std::get<Response>(pair);
        auto since = number_param(request, "seconds_since_temp_change", 3600.0, 0.0, 1e9);
        auto t_min = number_param(request, "t_min", -30.0, kMinTempC, kMaxTempC);
        auto t_max = number_param(request, "t_max", 25.0, kMinTempC, kMaxTempC);
        auto n = number_param(request, "n", 56.0, 2.0, 500.0, true);
        for (const auto* v : {&since, &t_min, &t_max, &n}) {
          if (holds_response(*v)) return std::get<Response>(*v);
        }
        const double lo = std::get<double>(t_min), hi = std::get<double>(t_max);
        const int count = int(std::get<double>(n));
        if (hi < lo) return error_response(422, "t_max must not be below t_min");
        const std::string& key = std::get<std::string>(pair);
        Json points = Json::array();
        for (int i = 0; i < count; ++i) {
          const double t = lo + i * (hi - lo) / (count - 1);
          points.push_back(friction_point_json(
              t, *FrictionModel::builtin().effective(key, t, std::get<double>(since))));
        }
        const auto slash = key.find('/');
        return json_response(200, {{"surface_pair", {key.substr(0, slash), key.substr(slash + 1)}},
                                   {"seconds_since_temp_change", std::get<double>(since)},
                                   {"points", std::move(points)}});
      },
      {"pair", "seconds_since_temp_change", "t_min", "t_max", "n"});

  // -- pallets --
  post("/pallet/random", [](const Request& request, const Params&) {
    Json body = Json::object();
    if (!request.body.empty()) {
      auto parsed = parse_body(request);
      if (holds_response(parsed)) return std::get<Response>(parsed);
      body = std::get<Json>(parsed);
      if (!body.is_object()) return error_response(422, "the body must be a JSON object");
    }
    RandomPalletOptions o;
    Diagnostics problems;
    auto integer = [&](const char* key, auto& field, std::int64_t lo, std::int64_t hi) {
      if (!body.contains(key) || body[key].is_null()) return;
      const Json& v = body[key];
      if (!v.is_number_integer() || v.get<std::int64_t>() < lo || v.get<std::int64_t>() > hi) {
        problems.push_back(
            {std::string("/") + key,
             "must be a whole number from " + std::to_string(lo) + " to " + std::to_string(hi),
             Severity::error});
        return;
      }
      field = static_cast<std::remove_reference_t<decltype(field)>>(v.get<std::int64_t>());
    };
    if (!body.contains("seed") || body["seed"].is_null()) {
      o.seed = std::random_device{}();  // the reference draws one too; the pallet_id names it
    }
    integer("seed", o.seed, 0, std::numeric_limits<std::int64_t>::max());
    integer("min_layers", o.min_layers, 1, 100);
    integer("max_layers", o.max_layers, 1, 100);
    integer("min_items_per_layer", o.min_items_per_layer, 1, 100);
    integer("max_items_per_layer", o.max_items_per_layer, 1, 100);
    if (body.contains("anomaly_rate") && !body["anomaly_rate"].is_null()) {
      if (!body["anomaly_rate"].is_number()) {
        problems.push_back({"/anomaly_rate", "must be a number from 0 to 1", Severity::error});
      } else {
        o.anomaly_rate = body["anomaly_rate"].get<double>();
      }
    }
    if (body.contains("wrap") && !body["wrap"].is_null()) {
      const Json& w = body["wrap"];
      const auto wrap = w.is_string() ? enum_from_string<WrapType>(w.get<std::string>())
                                      : std::optional<WrapType>();
      if (w.is_string() && w.get<std::string>() == "mixed") {
        o.wrap = std::nullopt;
      } else if (!wrap) {
        problems.push_back(
            {"/wrap", "must be " + enum_choices<WrapType>() + " or mixed", Severity::error});
      } else {
        o.wrap = *wrap;
      }
    }
    if (!has_errors(problems)) problems = validate_random_options(o);
    if (has_errors(problems)) return diagnostics_response(422, problems);
    auto pallet = random_pallet(o, Catalog::builtin());
    if (!pallet) return core_failure(pallet.diagnostics, "");
    return json_response(200, pallet_to_json(*pallet));
  });
  post("/pallet/validate", [reading](const Request& request, const Params&) {
    auto body = parse_body(request);
    if (holds_response(body)) return std::get<Response>(body);
    std::string prefix;  // a pallet on its own, or wrapped as every /v1 route and the CLI take it
    auto pallet = read_pallet(pallet_member(std::get<Json>(body), prefix), prefix, reading);
    if (holds_response(pallet)) return std::get<Response>(pallet);
    const PalletConfig& config = *std::get<Result<PalletConfig>>(pallet);
    if (Diagnostics line = line_findings(config, reading); has_errors(line)) {
      return diagnostics_response(422, line);
    }
    return json_response(200, pallet_to_json(config));
  });
  post("/v1/validate", [reading](const Request& request, const Params&) {
    auto body = parse_body(request);
    if (holds_response(body)) return std::get<Response>(body);
    if (auto refused = unknown_members(std::get<Json>(body), {"pallet"})) return *refused;
    std::string prefix;
    const Json& pj = pallet_member(std::get<Json>(body), prefix);
    // An invalid pallet is still a report (200): what is wrong, where, and its warnings too (the
    // CLI's validate lists them; a 422 carries errors only).
    PalletFindings found = check_pallet(pj, prefix, reading);
    if (found.config) {
      if (!has_errors(found.diagnostics)) {
        for (Diagnostic& d : line_findings(*found.config, reading)) {
          found.diagnostics.push_back(std::move(d));
        }
      }
      return json_response(
          200, validation_report_to_json(*found.config, found.diagnostics, reading.max_items));
    }
    if (!found.refused) {
      return json_response(200,
                           {{"valid", false},
                            {"errors", diagnostics_to_json(errors_of(found.diagnostics))},
                            {"warnings", diagnostics_to_json(warnings_of(found.diagnostics))}});
    }
    const Response& r = *found.refused;
    if (r.status != 422) return r;
    const Json refused = Json::parse(r.body);
    return json_response(
        200, {{"valid", false}, {"errors", refused["errors"]}, {"warnings", Json::array()}});
  });
  post("/mjcf/build",
       [reading](const Request& request, const Params&) {
         auto body = parse_body(request);
         if (holds_response(body)) return std::get<Response>(body);
         std::string prefix;
         auto pallet = read_pallet(pallet_member(std::get<Json>(body), prefix), prefix, reading);
         if (holds_response(pallet)) return std::get<Response>(pallet);
         const PalletConfig& config = *std::get<Result<PalletConfig>>(pallet);
         Json out;
         if (auto it = request.query.find("surface_pair"); it != request.query.end()) {
           if (FrictionModel::builtin().find(it->second) == nullptr) {
             return error_response(
                 422, "surface_pair is '" + it->second + "'; use one of " + known_pairs());
           }
           out["note"] =
               "surface_pair is not used: each contact's friction pair follows from the "
               "pallet (its base type, the items' material and temperature)";
         }
         auto scene = build_scene(config);
         if (!scene) return core_failure(scene.diagnostics, "");
         out["pallet_id"] = config.pallet_id;
         out["mjcf_xml"] = scene->mjcf;
         out["bytes"] = scene->mjcf.size();
         return json_response(200, out);
       },
       {"surface_pair"});

  // -- physics --
  auto solve = [this, reading, ticket_for, &ao](const Request& request, bool reference) {
    auto parsed = parse_body(request);
    if (holds_response(parsed)) return std::get<Response>(parsed);
    const Json& body = std::get<Json>(parsed);
    if (!body.is_object() || !body.contains("pallet")) {
      return error_response(422,
                            "the body must be {\"pallet\": PalletConfig, \"profile\": "
                            "ConveyorProfile, ...}",
                            {{"/pallet", "is required", Severity::error}});
    }
    if (!reference) {
      if (auto refused =
              unknown_members(body, {"pallet", "profile", "thresholds", "hz", "include_replay"})) {
        return *refused;
      }
    }
    auto pallet = read_pallet(body["pallet"], "/pallet", reading);
    auto read = read_profile(body, !reference);
    if (auto refused = refusal_of({refusal_in(pallet), refusal_in(read)})) return *refused;
    const PalletConfig& config = *std::get<Result<PalletConfig>>(pallet);
    const Result<ConveyorProfile>& profile_read = std::get<Result<ConveyorProfile>>(read);
    const ConveyorProfile& profile = *profile_read.value;
    if (body.contains("thresholds") && !body["thresholds"].is_null()) {
      const Json& t = body["thresholds"];
      const DetectorThresholds& ours = ao.sim.thresholds;
      auto agrees = [&t](const char* key, double value) {
        return !t.contains(key) || (t[key].is_number() && t[key].get<double>() == value);
      };
      const bool same = t.is_object() && agrees("tip_angle_deg", ours.tip_deg) &&
                        agrees("item_slide_m", ours.item_slide_m) &&
                        agrees("load_shift_m", ours.load_shift_m) &&
                        agrees("pallet_slip_m", ours.pallet_slip_m);
      if (!same) {
        return error_response(
            422,
            "/thresholds: this service detects failures at its own thresholds (tip " +
                short_number(ours.tip_deg) + " deg, item slide " + short_number(ours.item_slide_m) +
                " m, load shift " + short_number(ours.load_shift_m) + " m, pallet slip " +
                short_number(ours.pallet_slip_m) + " m); remove the field or send those",
            {{"/thresholds", "differs from the service's detector thresholds", Severity::error}});
      }
    }
    auto hz =
        number_member(body, reference ? "output_hz" : "hz", reference ? 50.0 : 30.0, 1.0, 1000.0);
    if (holds_response(hz)) return std::get<Response>(hz);
    auto replay_wanted = bool_member(body, "include_replay", false);
    if (holds_response(replay_wanted)) return std::get<Response>(replay_wanted);
    const bool include_replay = !reference || std::get<bool>(replay_wanted);
    auto ticket = ticket_for(request);
    std::optional<Result<Solve>> run;
    std::string fidelity;
    auto refusal = pool_.run(*ticket, [&](Analyzer& analyzer) {
      run = analyzer.solve(config, profile, std::get<double>(hz));
      if (auto prepared = analyzer.prepare(config)) {
        fidelity = std::string(to_string((*prepared.value)->fidelity.level));
      }
    });
    if (refusal) return refusal_response(*refusal, *ticket);
    if (!*run) return core_failure(run->diagnostics, "/pallet");
    pool_.count_simulations(1);
    const Solve& s = **run;
    if (reference)
      return json_response(200, solve_response_json(config, s, include_replay, fidelity));
    Json out = sim_result_to_json(s.sim, profile);
    out["fidelity"] = fidelity;
    // What reading the pallet and the profile found, then what the run adds.
    Diagnostics warnings = warnings_of(std::get<Result<PalletConfig>>(pallet).diagnostics);
    for (const Diagnostics* more :
         {&profile_read.diagnostics, static_cast<const Diagnostics*>(&run->diagnostics)}) {
      for (const Diagnostic& d : warnings_of(*more)) {
        if (std::find(warnings.begin(), warnings.end(), d) == warnings.end()) warnings.push_back(d);
      }
    }
    out["warnings"] = diagnostics_to_json(warnings);
    out["replay"] = replay_to_json(s.replay);
    return json_response(200, out);
  };
  post("/solve", [solve](const Request& r, const Params&) { return solve(r, true); });
  post("/v1/solve", [solve](const Request& r, const Params&) { return solve(r, false); });

  post("/safety/analyze", [analysed](const Request& request, const Params&) {
    auto a = analysed(request, {});
    if (auto* r = std::get_if<Response>(&a)) return *r;
    return json_response(200, analyze_response_json(std::get<Analysed>(a).analysis));
  });
  post("/safety/batch", [this, reading, ticket_for](const Request& request, const Params&) {
    auto parsed = parse_body(request);
    if (holds_response(parsed)) return std::get<Response>(parsed);
    const Json& body = std::get<Json>(parsed);
    if (!body.is_array()) return error_response(422, "the body must be a JSON array of pallets");
    if (body.size() > options_.max_batch) {
      return error_response(413, "the batch has " + std::to_string(body.size()) +
                                     " pallets; this service takes at most " +
                                     std::to_string(options_.max_batch) +
                                     " per request (--max-batch); send several batches");
    }
    std::vector<PalletConfig> pallets;
    Diagnostics problems;
    for (std::size_t i = 0; i < body.size(); ++i) {
      auto pallet = read_pallet(body[i], "/" + std::to_string(i), reading);
      if (auto* r = std::get_if<Response>(&pallet)) {
        if (r->status == 413) return *r;
        const Json refused = Json::parse(r->body);
        for (const auto& e : refused["errors"]) {
          problems.push_back({e["pointer"], e["message"], Severity::error});
        }
        continue;
      }
      pallets.push_back(std::move(*std::get<Result<PalletConfig>>(pallet).value));
    }
    if (has_errors(problems)) return diagnostics_response(422, problems);
    auto ticket = ticket_for(request);
    Json out = Json::array();
    for (std::size_t i = 0; i < pallets.size(); ++i) {
      auto analysis = pool_.analyze(*ticket, pallets[i]);
      if (auto* r = std::get_if<Refusal>(&analysis)) return refusal_response(*r, *ticket);
      if (auto* d = std::get_if<Diagnostics>(&analysis)) {
        out.push_back(Json::parse(core_failure(*d, "/" + std::to_string(i)).body));
        continue;
      }
      out.push_back(analyze_response_json(std::get<Analysis>(analysis)));
    }
    return json_response(200, out);
  });

  // -- ours --
  const Check only_pallet = [](const Json& body, bool) {
    return unknown_members(body, {"pallet"});
  };
  post("/v1/analyze", [this, analysed, only_pallet](const Request& request, const Params&) {
    auto result = analysed(request, only_pallet);
    if (auto* r = std::get_if<Response>(&result)) return *r;
    const Analysed& a = std::get<Analysed>(result);
    const Envelope& env = a.analysis.cached->envelope;
    Json out;
    out["result"] = analyze_response_json(a.analysis)["result"];
    out["cached"] = a.analysis.cache_hit;
    out["axes"] = {{"accel", axis_json(env.accel)},
                   {"decel", axis_json(env.decel)},
                   {"lateral", axis_json(env.lateral, true)},
                   {"speed", axis_json(env.speed)}};
    out["probes"] = probes_to_json(env.probes);
    out["explain"] = explain_json(env.result);
    out["warnings"] = diagnostics_to_json(warnings_of(a.config.diagnostics));
    out["line"] = line_to_json(pool_.options().analyzer.line, pool_.options().analyzer.search);
    return json_response(200, out);
  });
  post("/v1/explain", [analysed, only_pallet](const Request& request, const Params&) {
    auto a = analysed(request, only_pallet);
    if (auto* r = std::get_if<Response>(&a)) return *r;
    return json_response(200, explain_json(std::get<Analysed>(a).analysis.cached->envelope.result));
  });
  post("/v1/map", [this, reading, ticket_for](const Request& request, const Params&) {
    auto parsed = parse_body(request);
    if (holds_response(parsed)) return std::get<Response>(parsed);
    const Json& body = std::get<Json>(parsed);
    if (auto refused = unknown_members(body, {"pallet", "speeds_mps", "accels_mps2"})) {
      return *refused;
    }
    std::string prefix;
    auto pallet = read_pallet(pallet_member(body, prefix), prefix, reading);
    MapOptions grids;
    Diagnostics bad_grids;
    // Every bad member of both grids is named at once: the ones that are not numbers, and the
    // numbers out of range or out of order among the rest.
    for (auto [key, grid, kind] :
         {std::tuple{"speeds_mps", &grids.speeds_mps, MapGrid::speeds},
          std::tuple{"accels_mps2", &grids.accels_mps2, MapGrid::accels}}) {
      if (prefix.empty() || !body.contains(key)) continue;
      const Json& v = body[key];
      const std::string at = std::string("/") + key;
      if (!v.is_array() || v.empty() || v.size() > 64) {
        bad_grids.push_back({at, "must be an array of 1 to 64 numbers (absent: the default grid)",
                             Severity::error});
        continue;
      }
      std::vector<double> numbers;
      std::vector<std::size_t> index;
      for (std::size_t i = 0; i < v.size(); ++i) {
        if (v[i].is_number()) {
          numbers.push_back(v[i].get<double>());
          index.push_back(i);
          continue;
        }
        bad_grids.push_back({at + "/" + std::to_string(i),
                             "must be a number, not " + std::string(v[i].type_name()),
                             Severity::error});
      }
      if (numbers.empty()) continue;  // (every member is named already)
      for (Diagnostic& d : map_grid_problems(kind, numbers, at, index)) {
        bad_grids.push_back(std::move(d));
      }
      if (numbers.size() == v.size()) *grid = std::move(numbers);
    }
    const std::optional<Response> grids_refused =
        bad_grids.empty() ? std::nullopt
                          : std::optional<Response>(diagnostics_response(422, bad_grids));
    if (auto refused =
            refusal_of({refusal_in(pallet), grids_refused ? &*grids_refused : nullptr})) {
      return *refused;
    }
    auto ticket = ticket_for(request);
    std::optional<Result<FailureMap>> map;
    const PalletConfig& config = *std::get<Result<PalletConfig>>(pallet);
    auto refusal = pool_.run(*ticket, [&](Analyzer& a) { map = a.failure_map(config, grids); });
    if (refusal) return refusal_response(*refusal, *ticket);
    if (!*map) {  // the grids are the request's own members; the rest points into the pallet
      Diagnostics d = map->diagnostics;
      for (auto& x : d) {
        const bool grid =
            x.pointer.starts_with("/speeds_mps") || x.pointer.starts_with("/accels_mps2");
        if (!grid && !x.pointer.empty()) x.pointer = prefix + x.pointer;
      }
      return core_failure(d, "");
    }
    pool_.count_simulations((*map)->sims);
    Json out = failure_map_to_json(**map);
    out["pallet_id"] = config.pallet_id;
    return json_response(200, out);
  });
  post("/v1/uncertainty", [this, reading, ticket_for](const Request& request, const Params&) {
    auto parsed = parse_body(request);
    if (holds_response(parsed)) return std::get<Response>(parsed);
    const Json& body = std::get<Json>(parsed);
    if (!body.is_object() || !body.contains("pallet") || !body.contains("profile")) {
      return error_response(422,
                            "the body must be {\"pallet\": PalletConfig, \"profile\": "
                            "ConveyorProfile, \"samples\"?: M, \"seed\"?: S}");
    }
    if (auto refused = unknown_members(body, {"pallet", "profile", "samples", "seed"})) {
      return *refused;
    }
    auto pallet = read_pallet(body["pallet"], "/pallet", reading);
    auto read = read_profile(body, true);
    if (auto refused = refusal_of({refusal_in(pallet), refusal_in(read)})) return *refused;
    const ConveyorProfile profile = *std::get<Result<ConveyorProfile>>(read).value;
    auto samples = number_member(body, "samples", 32, 1, options_.max_uncertainty_samples, true);
    if (holds_response(samples)) return std::get<Response>(samples);
    auto seed = number_member(body, "seed", 0, 0, 9007199254740991.0, true);
    if (holds_response(seed)) return std::get<Response>(seed);
    UncertaintyOptions uo;
    uo.samples = int(std::get<double>(samples));
    uo.seed = std::uint64_t(std::get<double>(seed));
    const PalletConfig& config = *std::get<Result<PalletConfig>>(pallet);
    std::optional<Result<UncertaintyResult>> result;
    Diagnostics refused;
    auto ticket = ticket_for(request);
    auto refusal = pool_.run(*ticket, [&](Analyzer& a) {
      auto prepared = a.prepare(config);
      if (!prepared) {
        refused = prepared.diagnostics;
        return;
      }
      const PreparedPallet& p = **prepared.value;
      if (p.rest.cannot_stand) {
        refused = {{"/items/" + std::to_string(p.rest.cannot_stand->item),
                    p.rest.cannot_stand->sentence, Severity::error}};
        return;
      }
      result = failure_probability(*p.scene, p.rest, {profile}, uo, a.options().sim);
    });
    if (refusal) return refusal_response(*refusal, *ticket);
    if (!result) return core_failure(refused, "/pallet");
    if (!*result) return core_failure(result->diagnostics, "");
    const UncertaintyResult& u = **result;
    pool_.count_simulations(u.sims);
    Json modes = Json::object();
    for (const auto& [mode, n] : u.modes) modes[std::string(to_string(mode))] = n;
    return json_response(200, {{"samples", u.samples},
                               {"failures", u.failures},
                               {"unstable", u.unstable},
                               {"p_fail", u.p_fail},
                               {"ci95", {u.ci_low, u.ci_high}},
                               {"modes", modes},
                               {"sims", u.sims},
                               {"wall_ms", u.wall_ms},
                               {"profile", profile_to_json(profile)}});
  });
  post("/v1/replay", [this, analysed](const Request& request, const Params&) {
    std::optional<Axis> wanted;
    double hz = 30.0;
    auto check = [&](const Json& body, bool wrapped) -> std::optional<Response> {
      if (!wrapped) return std::nullopt;  // a bare pallet: every default
      if (auto refused = unknown_members(body, {"pallet", "axis", "hz"})) return refused;
      if (body.contains("axis")) {
        const Json& a = body["axis"];
        for (Axis axis : {Axis::accel, Axis::decel, Axis::lateral, Axis::speed}) {
          if (a.is_string() && a.get<std::string>() == to_string(axis)) wanted = axis;
        }
        if (!wanted) {
          return error_response(
              422, "/axis must be accel, decel, lateral or speed",
              {{"/axis", "must be accel, decel, lateral or speed", Severity::error}});
        }
      }
      auto rate = number_member(body, "hz", 30.0, 1.0, 1000.0);
      if (holds_response(rate)) return std::get<Response>(rate);
      hz = std::get<double>(rate);
      return std::nullopt;
    };
    auto result = analysed(request, check);
    if (auto* r = std::get_if<Response>(&result)) return *r;
    Analysed& a = std::get<Analysed>(result);
    const PalletConfig& config = *a.config;
    const std::string& prefix = a.prefix;
    Ticket& ticket = *a.ticket;
    const Envelope& env = a.analysis.cached->envelope;
    const AnalyzerOptions& o = pool_.options().analyzer;
    if (env.result.dominant_failure_mode == FailureMode::cannot_stand) {
      return json_response(200, {{"replay", nullptr}, {"reason", env.result.reason}});
    }
    // The axis asked for, or the tightest: the lowest limit for its place in its range.
    const auto axes = axes_of(env, o.search);
    const AxisChoice* choice = nullptr;
    for (const auto& c : axes) {
      if (wanted && c.axis != *wanted) continue;
      if (!wanted && c.limit->at_ceiling) continue;
      const double place = (c.limit->limit - c.lo) / (c.hi - c.lo);
      if (!choice || place < (choice->limit->limit - choice->lo) / (choice->hi - choice->lo)) {
        choice = &c;
      }
    }
    if (!choice || choice->limit->at_ceiling) {
      return json_response(200, {{"replay", nullptr},
                                 {"reason",
                                  "nothing fails within the search ranges; no probe "
                                  "failed to replay"}});
    }
    // The failing probe just above the limit, or (a derived axis has no probes) one step above.
    // A lateral limit fails in its own turn (AxisLimit::turn).
    double value = choice->limit->at_floor ? choice->lo : choice->limit->limit + choice->precision;
    bool probed = false;
    for (const auto& p : env.probes) {
      if (p.axis != choice->axis || p.outcome != Outcome::failed) continue;
      if (p.axis == Axis::lateral && p.turn != choice->limit->turn) continue;
      if (p.value > choice->limit->limit - 1e-12 && (!probed || p.value < value)) {
        value = p.value;
        probed = true;
      }
    }
    const ConveyorProfile profile =
        probe_profile(choice->axis, value, choice->limit->turn, o.line, o.search);
    std::optional<Result<Solve>> run;
    auto refusal =
        pool_.run(ticket, [&](Analyzer& analyzer) { run = analyzer.solve(config, profile, hz); });
    if (refusal) return refusal_response(*refusal, ticket);
    if (!*run) return core_failure(run->diagnostics, prefix);
    pool_.count_simulations(1);
    Json out = sim_result_to_json((*run)->sim, profile);
    out["axis"] = to_string(choice->axis);
    out["value"] = value;
    out["limit"] = choice->limit->limit;
    out["probed"] = probed;
    out["replay"] = replay_to_json((*run)->replay);
    return json_response(200, out);
  });
}

std::vector<std::string> Service::routes() const {
  std::vector<std::string> out;
  for (const auto& r : routes_) out.push_back(r.method + " " + r.pattern);
  return out;
}

namespace {

std::vector<std::string> segments(const std::string& path) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i < path.size()) {
    if (path[i] == '/') {
      ++i;
      continue;
    }
    const std::size_t j = path.find('/', i);
    out.push_back(path.substr(i, j == std::string::npos ? std::string::npos : j - i));
    i = j == std::string::npos ? path.size() : j;
  }
  return out;
}

bool match(const std::string& pattern, const std::string& path, Params& params) {
  const auto p = segments(pattern), s = segments(path);
  if (p.size() != s.size()) return false;
  Params found;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p[i].size() > 2 && p[i].front() == '{' && p[i].back() == '}') {
      found[p[i].substr(1, p[i].size() - 2)] = s[i];
    } else if (p[i] != s[i]) {
      return false;
    }
  }
  params = std::move(found);
  return true;
}

// A Content-Type's media type, lower case, without its parameters.
std::string media_type(std::string_view content_type) {
  std::string type(content_type.substr(0, content_type.find(';')));
  std::transform(type.begin(), type.end(), type.begin(),
                 [](unsigned char ch) { return char(std::tolower(ch)); });
  while (!type.empty() && type.back() == ' ') type.pop_back();
  return type;
}

// A body sent as something other than JSON: refused (415). A body without a Content-Type (some
// scripts) or with a JSON type (application/json, or a structured ...+json type) is read as JSON.
// Among those refused are the types a web page may POST to another origin without asking first
// (a CORS "simple request": text/plain, a form), so that no page outside the allowlist can start
// analyses here, and a type that says the body is something else (application/xml: a client that
// sends XML is told so, not handed a JSON parse error). The HTTP layer parses a multipart body
// and drops it, so its body reads empty here.
bool not_json(const Request& request) {
  const std::string type = media_type(request.content_type);
  if (type == "multipart/form-data") return true;
  const bool json = type.empty() || type == "application/json" || type.ends_with("+json");
  return !request.body.empty() && !json;
}

}  // namespace

// A query parameter the route does not read (a misspelt one would silently leave its default in
// force), or one given twice (which would win?), is a 422 naming it.
std::optional<Response> Service::query_problem(const Request& request, const Route& route) {
  for (auto it = request.query.begin(); it != request.query.end();
       it = request.query.upper_bound(it->first)) {
    const std::string& key = it->first;
    const std::string where = route.method + " " + route.pattern;
    if (std::find(route.query.begin(), route.query.end(), key) == route.query.end()) {
      std::string reads;
      for (const auto& q : route.query) reads += (reads.empty() ? "" : ", ") + q;
      return error_response(422, "the query parameter '" + key + "' is not read by " + where +
                                     (reads.empty() ? "; it takes none" : "; it reads " + reads) +
                                     ": remove it or fix its name");
    }
    if (const auto n = request.query.count(key); n > 1) {
      return error_response(422, "the query parameter '" + key + "' is given " + std::to_string(n) +
                                     " times; give it once");
    }
  }
  return std::nullopt;
}

Response Service::dispatch(const Request& request, std::string& route) {
  // HEAD is GET without the body (the HTTP layer sends the headers only): a monitor's HEAD
  // /healthz is answered as its GET.
  const std::string method = request.method == "HEAD" ? "GET" : request.method;
  std::vector<std::string> allowed;
  for (const auto& r : routes_) {
    Params params;
    if (!match(r.pattern, request.path, params)) continue;
    route = r.pattern;
    if (r.method != method) {
      allowed.push_back(r.method);
      continue;
    }
    if (request.method == "POST" && not_json(request)) {
      return error_response(415, "the body was sent as '" + request.content_type +
                                     "'; send JSON with the header content-type: "
                                     "application/json");
    }
    // After the 415: the HTTP layer files a form body's fields among the query parameters.
    if (auto refused = query_problem(request, r)) return *refused;
    return r.handler(request, params);
  }
  if (!allowed.empty()) {
    std::string list;
    for (const auto& m : allowed) list += (list.empty() ? "" : ", ") + m;
    if (request.method == "OPTIONS") {  // what the path answers (a browser's preflight asks)
      Response r;
      r.status = 204;  // no content: no body, and no content type to claim one
      r.content_type.clear();
      r.headers["Allow"] = r.headers["Access-Control-Allow-Methods"] = list + ", OPTIONS";
      return r;
    }
    Response r = error_response(
        405, request.method + " is not allowed on " + request.path + "; use " + list);
    r.headers["Allow"] = list;
    return r;
  }
  return error_response(404, "no route " + request.path + "; GET / lists the routes");
}

void Service::refused(const std::string& method, const std::string& path, int status,
                      double seconds) {
  std::string route = "unmatched";
  for (const auto& r : routes_) {
    Params params;
    if (match(r.pattern, path, params)) {
      route = r.pattern;
      break;
    }
  }
  metrics_.observe(method, route, status, seconds);
}

Response Service::handle(const Request& request) {
  const auto start = std::chrono::steady_clock::now();
  std::string route;
  Response response;
  try {
    response = dispatch(request, route);
  } catch (const std::exception& e) {
    response = error_response(500, std::string("internal error: ") + e.what());
  } catch (...) {
    response = error_response(500, "internal error");
  }
  response.route = route;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  metrics_.observe(request.method, route.empty() ? "unmatched" : route, response.status, seconds);
  return response;
}

}  // namespace pb::server
