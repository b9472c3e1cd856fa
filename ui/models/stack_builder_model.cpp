// SPDX-License-Identifier: MIT
#include "ui/models/stack_builder_model.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numeric>

#include "core/base/text.hpp"
#include "core/contract/pallet_metrics.hpp"
#include "core/inputs/catalog.hpp"

namespace pb::ui {

namespace {

bool same_centre(const pb::Item& a, const pb::Item& b) {
  return std::hypot(a.position[0] - b.position[0], a.position[1] - b.position[1]) <=
         kStackCentreTolerance;
}

// Ray casting: is `p` inside the polygon (counter-clockwise corners)?
bool inside(const std::array<pb::Vec2, 4>& poly, pb::Vec2 p) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const auto& a = poly[i];
    const auto& b = poly[j];
    if ((a[1] > p[1]) != (b[1] > p[1]) &&
        p[0] < (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1]) + a[0]) {
      in = !in;
    }
  }
  return in;
}

// The item index of a pointer "/items/<k>..." (with an optional prefix such as "/pallet"), or -1.
int item_of_pointer(const std::string& pointer) {
  constexpr std::string_view kItems = "/items/";
  const std::size_t at = pointer.find(kItems);
  if (at == std::string::npos) return -1;
  const std::size_t begin = at + kItems.size();
  const std::size_t end = std::min(pointer.find('/', begin), pointer.size());
  int k = -1;
  const auto [ptr, ec] = std::from_chars(pointer.data() + begin, pointer.data() + end, k);
  if (ec != std::errc() || ptr != pointer.data() + end) return -1;
  return k;
}

}  // namespace

std::vector<StackView> stacks_of(const pb::PalletConfig& config) {
  std::vector<StackView> stacks;
  const auto& items = config.items;
  for (int i = 0; i < static_cast<int>(items.size()); ++i) {
    auto it = std::find_if(stacks.begin(), stacks.end(), [&](const StackView& s) {
      return same_centre(items[s.items.front()], items[i]);
    });
    if (it == stacks.end()) {
      stacks.push_back(StackView{});
      it = std::prev(stacks.end());
    }
    it->items.push_back(i);
  }
  for (StackView& s : stacks) {
    std::stable_sort(s.items.begin(), s.items.end(),
                     [&](int a, int b) { return items[a].position[2] < items[b].position[2]; });
    const pb::Item& bottom = items[s.items.front()];
    s.centre = {bottom.position[0], bottom.position[1]};
    s.sku = bottom.sku;
    s.top_z = 0.0;
    for (int k : s.items) {
      s.mixed = s.mixed || items[k].sku != s.sku;
      s.top_z = std::max(s.top_z, items[k].top_z());
    }
  }
  return stacks;
}

int stack_of_item(const std::vector<StackView>& stacks, int item) {
  for (int s = 0; s < static_cast<int>(stacks.size()); ++s) {
    const auto& items = stacks[s].items;
    if (std::find(items.begin(), items.end(), item) != items.end()) return s;
  }
  return -1;
}

pb::GridShape builder_grid(const pb::PalletConfig& config, std::string_view extra_sku) {
  std::vector<pb::StackSpec> specs;
  for (const pb::Item& item : config.items) specs.push_back({item.sku, 0, 0, 1});
  if (!extra_sku.empty()) specs.push_back({std::string(extra_sku), 0, 0, 1});
  return pb::grid_for(specs, config.base_dims_m, pb::Catalog::builtin());
}

pb::Vec2 cell_centre(const pb::PalletConfig& config, const pb::GridShape& grid, int row, int col) {
  const auto& dims = config.base_dims_m;
  return {-dims[0] / 2.0 + (col + 0.5) * dims[0] / grid.cols,
          -dims[1] / 2.0 + (row + 0.5) * dims[1] / grid.rows};
}

std::optional<Cell> cell_at(const pb::PalletConfig& config, const pb::GridShape& grid,
                            pb::Vec2 point) {
  const auto& dims = config.base_dims_m;
  const double u = (point[0] + dims[0] / 2.0) / dims[0];
  const double v = (point[1] + dims[1] / 2.0) / dims[1];
  if (!(u >= 0.0 && u < 1.0 && v >= 0.0 && v < 1.0)) return std::nullopt;
  return Cell{std::clamp(static_cast<int>(std::floor(v * grid.rows)), 0, grid.rows - 1),
              std::clamp(static_cast<int>(std::floor(u * grid.cols)), 0, grid.cols - 1)};
}

int stack_at(const pb::PalletConfig& config, const std::vector<StackView>& stacks, pb::Vec2 point) {
  int best = -1;
  double best_top = -1.0;
  for (int s = 0; s < static_cast<int>(stacks.size()); ++s) {
    for (int k : stacks[s].items) {
      const pb::Item& item = config.items[k];
      if (item.top_z() > best_top && inside(pb::item_footprint(item), point)) {
        best = s;
        best_top = item.top_z();
      }
    }
  }
  return best;
}

QString stack_label(const std::vector<StackView>& stacks, int stack) {
  if (stack < 0 || stack >= static_cast<int>(stacks.size())) return QStringLiteral("No stack");
  const StackView& s = stacks[stack];
  return QStringLiteral("Stack %1 (%2%3, %4 high)")
      .arg(stack + 1)
      .arg(QString::fromStdString(s.sku.empty() ? std::string("no SKU") : s.sku))
      .arg(s.mixed ? QStringLiteral(" and others") : QString())
      .arg(s.height());
}

int stack_of_finding(const pb::Diagnostic& finding, const std::vector<StackView>& stacks) {
  const int item = item_of_pointer(finding.pointer);
  return item < 0 ? -1 : stack_of_item(stacks, item);
}

QString describe_finding(const pb::Diagnostic& finding, const std::vector<StackView>& stacks) {
  const QString prefix =
      finding.severity == pb::Severity::warning ? QStringLiteral("Warning: ") : QString();
  const QString message = QString::fromStdString(finding.message);
  const int item = item_of_pointer(finding.pointer);
  const int stack = item < 0 ? -1 : stack_of_item(stacks, item);
  if (stack < 0) {
    const QString where = finding.pointer.empty() ? QStringLiteral("pallet")
                                                  : QString::fromStdString(finding.pointer);
    return prefix + where + QStringLiteral(": ") + message;
  }
  const auto& items = stacks[stack].items;
  const int level =
      static_cast<int>(std::find(items.begin(), items.end(), item) - items.begin()) + 1;
  return prefix + stack_label(stacks, stack) +
         QStringLiteral(", carton %1 from the bottom: ").arg(level) + message;
}

QString summary_line(const pb::PalletConfig& config) {
  const pb::Vec3 com = pb::composite_com_m(config);
  const auto support = pb::support_fractions(config);
  const double least = support.empty() ? 1.0 : *std::min_element(support.begin(), support.end());
  const auto num = [](double v, int d) { return QString::fromStdString(pb::fixed(v, d)); };
  return QStringLiteral(
             "%1 kg · %2 cartons · CoM (%3, %4, %5) m · height %6 m · overhang %7 m · "
             "least support %8 %")
      .arg(num(pb::total_mass_kg(config), 1))
      .arg(config.items.size())
      .arg(num(com[0], 2), num(com[1], 2), num(com[2], 2))
      .arg(num(pb::stack_height_m(config), 2))
      .arg(num(pb::overhang_m(config), 2))
      .arg(num(100.0 * least, 0));
}

}  // namespace pb::ui
