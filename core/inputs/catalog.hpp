// SPDX-License-Identifier: MIT
// The SKU catalog: what a carton of each product weighs and measures.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/diagnostic.hpp"
#include "core/base/enums.hpp"
#include "core/base/vec3.hpp"
#include "core/contract/item.hpp"

namespace pb {

struct SkuTemplate {
  std::string sku;
  std::string name;
  double weight_kg = 0.0;
  Vec3 dims_m{};  ///< length, width, height
  Fragility fragility = Fragility::rigid;
  std::string category;
  Environment default_env = Environment::refrigerated;

  bool operator==(const SkuTemplate&) const = default;
};

class Catalog {
 public:
  /// Parses CSV with the header
  /// `sku,name,weight_kg,length_m,width_m,height_m,fragility,category,default_env`.
  /// Diagnostics point at "/<row>/<column>" (row 0 is the first data row).
  static Result<Catalog> from_csv(std::string_view text);

  /// The catalog shipped in resources/sku_catalog.csv (30 SKUs), parsed once.
  static const Catalog& builtin();

  /// The SKU, or nullptr.
  const SkuTemplate* find(std::string_view sku) const;
  std::span<const SkuTemplate> all() const { return skus_; }
  /// SKUs whose default environment is `env`, in catalog order.
  std::vector<const SkuTemplate*> for_env(Environment env) const;

 private:
  std::vector<SkuTemplate> skus_;
};

/// An item of this SKU at `position` (centre of its bottom face) with yaw `orientation_deg`.
Item make_item(const SkuTemplate& sku, const Vec3& position, double orientation_deg = 0.0);

}  // namespace pb
