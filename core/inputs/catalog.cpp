// SPDX-License-Identifier: MIT
#include "core/inputs/catalog.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>

#include "core/base/resources.hpp"
#include "core/contract/json_reader.hpp"

namespace pb {

namespace {

constexpr std::string_view kHeader =
    "sku,name,weight_kg,length_m,width_m,height_m,fragility,category,default_env";

// Splits one CSV record; a field may be double-quoted, with "" for a quote inside it.
std::vector<std::string> split_csv_line(std::string_view line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        fields.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

// The whole text as a number (finite or not), like a JSON number read from a cell.
bool parse_double(const std::string& text, double& out) {
  const char* begin = text.data();
  const char* end = begin + text.size();
  auto [ptr, ec] = std::from_chars(begin, end, out);
  return ec == std::errc() && ptr == end;
}

}  // namespace

Result<Catalog> Catalog::from_csv(std::string_view text) {
  Catalog catalog;
  Diagnostics diags;
  std::vector<std::string_view> lines;
  for (std::size_t start = 0; start < text.size();) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (!line.empty()) lines.push_back(line);
    start = end + 1;
  }
  if (lines.empty() || lines.front() != kHeader) {
    return Result<Catalog>::failure(
        "", "the catalog must start with the header line '" + std::string(kHeader) + "'");
  }
  static constexpr std::string_view kColumns[] = {"sku",       "name",     "weight_kg",
                                                  "length_m",  "width_m",  "height_m",
                                                  "fragility", "category", "default_env"};
  for (std::size_t row = 1; row < lines.size(); ++row) {
    std::string where = "/";
    where += std::to_string(row - 1);
    auto fields = split_csv_line(lines[row]);
    if (fields.size() != 9) {
      diags.push_back({where, "row has " + std::to_string(fields.size()) +
                                  " fields; a catalog row needs 9 (" + std::string(kHeader) + ")"});
      continue;
    }
    SkuTemplate t;
    t.sku = fields[0];
    t.name = fields[1];
    t.category = fields[7];
    bool row_ok = true;
    if (t.sku.empty()) {
      diags.push_back({where + "/sku", "the SKU code is empty; give every row a unique code"});
      row_ok = false;
    } else if (catalog.find(t.sku) != nullptr) {
      diags.push_back({where + "/sku", "SKU " + t.sku + " appears twice; keep one row per SKU"});
      row_ok = false;
    }
    double* numbers[] = {&t.weight_kg, &t.dims_m[0], &t.dims_m[1], &t.dims_m[2]};
    for (int k = 0; k < 4; ++k) {
      const std::string& f = fields[static_cast<std::size_t>(2 + k)];
      const std::string pointer = where + "/" + std::string(kColumns[2 + k]);
      if (!parse_double(f, *numbers[k])) {
        diags.push_back(
            {pointer, wording::wrong_type("a number", "'" + f + "'", "write a plain number")});
        row_ok = false;
      } else if (!(*numbers[k] > 0.0) || !std::isfinite(*numbers[k])) {
        diags.push_back({pointer, wording::out_of_range(f, k == 0 ? "a number of kilograms above 0"
                                                                  : "a number of metres above 0")});
        row_ok = false;
      }
    }
    if (auto v = enum_from_string<Fragility>(fields[6])) {
      t.fragility = *v;
    } else {
      diags.push_back(
          {where + "/fragility", wording::not_a_choice(fields[6], enum_choices<Fragility>())});
      row_ok = false;
    }
    if (auto v = enum_from_string<Environment>(fields[8])) {
      t.default_env = *v;
    } else {
      diags.push_back(
          {where + "/default_env", wording::not_a_choice(fields[8], enum_choices<Environment>())});
      row_ok = false;
    }
    if (row_ok) catalog.skus_.push_back(std::move(t));
  }
  if (has_errors(diags)) return Result<Catalog>::failure(std::move(diags));
  return Result<Catalog>{std::move(catalog), std::move(diags)};
}

const Catalog& Catalog::builtin() {
  static const Catalog catalog = [] {
    auto text = embedded_file("resources/sku_catalog.csv");
    if (!text) throw std::logic_error("resources/sku_catalog.csv is not embedded in palletcore");
    auto parsed = from_csv(*text);
    if (!parsed) throw std::logic_error("resources/sku_catalog.csv does not parse");
    return std::move(*parsed.value);
  }();
  return catalog;
}

const SkuTemplate* Catalog::find(std::string_view sku) const {
  for (const auto& t : skus_) {
    if (t.sku == sku) return &t;
  }
  return nullptr;
}

std::vector<const SkuTemplate*> Catalog::for_env(Environment env) const {
  std::vector<const SkuTemplate*> out;
  for (const auto& t : skus_) {
    if (t.default_env == env) out.push_back(&t);
  }
  return out;
}

Item make_item(const SkuTemplate& sku, const Vec3& position, double orientation_deg) {
  Item item;
  item.sku = sku.sku;
  item.weight_kg = sku.weight_kg;
  item.dims_m = sku.dims_m;
  item.fragility = sku.fragility;
  item.position = position;
  item.orientation_deg = orientation_deg;
  return item;
}

}  // namespace pb
