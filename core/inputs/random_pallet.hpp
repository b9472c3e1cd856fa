// SPDX-License-Identifier: MIT
// The seeded random scanner adapter: realistic synthetic pallets with the reference's
// distributions, byte-identical for the same seed on every platform.
#pragma once

#include <cstdint>
#include <optional>

#include "core/base/diagnostic.hpp"
#include "core/contract/pallet_config.hpp"
#include "core/inputs/catalog.hpp"
#include "core/inputs/layer_layout.hpp"
#include "core/inputs/validation.hpp"

namespace pb {

struct RandomPalletOptions {
  std::uint64_t seed = 0;
  double anomaly_rate = 0.08;  ///< [0, 1]
  int min_layers = 3;          ///< Hi range, >= 1
  int max_layers = 7;
  int min_items_per_layer = 4;  ///< Ti range, >= 1
  int max_items_per_layer = 10;
  /// The wrap of every pallet; nullopt ("mixed"): drawn per pallet, each of none, shrink, stretch
  /// and banded with probability 1/4 (drawn after every other field, so the rest of a seed's
  /// pallet is the same whatever the wrap).
  std::optional<WrapType> wrap = WrapType::stretch;
};

/// Range checks of the options; pointers "/seed", "/anomaly_rate", "/min_layers", ...
Diagnostics validate_random_options(const RandomPalletOptions& options);

/// Draws scanner inputs (reference distributions, REFERENCE_FACTS.md "Random scanner adapter"):
/// environment frozen .45 (-25..-18 C) / refrigerated .35 (0..5) / thawed .10 (15..22) /
/// transitioning .10 (-2..8, 30..300 s since the change; otherwise 1800..7200 s); pattern brick .55
/// / column .20 / pinwheel .20 / irregular .05; homogeneity single SKU .70 / one SKU per layer .20
/// / mixed .10; base EUR .55 / GMA .35 / CHEP .10; Ti from the options' range with the pattern's
/// minimum (brick and pinwheel 4, irregular 3, column 1) and column at most 2; Hi from the range;
/// an anomaly with probability anomaly_rate: lean 2..8 deg and top-layer overhang 2.5..10 cm;
/// SKUs from the environment's default products (transitioning: the frozen ones); the options' wrap
/// (stretch by default, as the reference).
ScannerInputs random_scanner_inputs(const RandomPalletOptions& options, const Catalog& catalog);

/// random_scanner_inputs() laid out by build_from_scanner(), with layers trimmed from the top
/// until the pallet is within the gross-mass and height caps of `limits` and every item stands
/// (and Ti reduced to what fits a layer of the deck; anomalies reduced as build_from_scanner
/// does). The pallet id is "R-<seed>"; `notes` records the pattern, Ti x Hi, any anomaly and what
/// was reduced. Always valid, wrapped or not; never fails for valid options.
Result<PalletConfig> random_pallet(const RandomPalletOptions& options, const Catalog& catalog,
                                   const ValidationLimits& limits = {});

}  // namespace pb
