// SPDX-License-Identifier: MIT
#include "ui/models/pallet_document.hpp"

#include <QFile>
#include <QFileInfo>
#include <QSaveFile>
#include <QUndoCommand>
#include <algorithm>
#include <cmath>
#include <optional>

#include "core/contract/json_io.hpp"
#include "core/contract/pallet_type.hpp"
#include "core/inputs/catalog.hpp"
#include "core/inputs/layer_layout.hpp"
#include "core/inputs/pallet_source.hpp"
#include "core/inputs/validation.hpp"
#include "ui/models/stack_builder_model.hpp"

namespace pb::ui {

namespace {

// Merge keys of drag edits (QUndoCommand::id() needs one per kind of edit).
enum MergeKey : int {
  kNoMerge = 0,
  kMoveStack = 1,
  kResizeStack = 2,
  kBodyTemp = 3,
  kSinceChange = 4,
};

QString file_name(const QString& path) {
  return QFileInfo(path).fileName();
}

QStringList messages_of(const pb::Diagnostics& diagnostics) {
  QStringList out;
  for (const auto& d : pb::condensed(diagnostics)) out << QString::fromStdString(pb::to_string(d));
  return out;
}

pb::PalletConfig empty_pallet() {
  pb::PalletConfig config;
  const auto& spec = pb::pallet_type_spec(config.base_pallet_type);
  config.base_dims_m = spec.dims_m;
  config.base_mass_kg = spec.mass_kg;
  return config;
}

}  // namespace

/// One edit: the pallet before and after. Drag edits with the same key (and stack, folded into
/// the key by the caller) merge while the document's drag is open.
class PalletEditCommand : public QUndoCommand {
 public:
  PalletEditCommand(PalletDocument* document, pb::PalletConfig before, pb::PalletConfig after,
                    const QString& text, int mergeKey)
      : QUndoCommand(text),
        _document(document),
        _before(std::move(before)),
        _after(std::move(after)),
        _mergeKey(mergeKey) {}

  void undo() override { _document->apply(_before); }
  void redo() override { _document->apply(_after); }
  int id() const override { return _mergeKey == kNoMerge ? -1 : _mergeKey; }
  bool mergeWith(const QUndoCommand* other) override {
    const auto* next = static_cast<const PalletEditCommand*>(other);
    if (next->_mergeKey != _mergeKey || !_open) return false;
    _after = next->_after;
    _open = next->_open;
    setObsolete(_after == _before);
    return true;
  }
  void close() { _open = false; }

 private:
  PalletDocument* _document;
  pb::PalletConfig _before;
  pb::PalletConfig _after;
  int _mergeKey;
  bool _open = true;
};

PalletDocument::PalletDocument(QObject* parent) : QObject(parent) {
  _pallet = empty_pallet();
  _diagnostics = pb::validate(_pallet);
  _name = tr("Untitled");
  // Undo or redo ends any drag: what comes next is a new step.
  connect(&_undo, &QUndoStack::indexChanged, this, [this] {
    if (!_pushing) endDrag();
  });
  connect(&_undo, &QUndoStack::cleanChanged, this, [this](bool clean) {
    emit modifiedChanged(!clean);
    emit titleChanged(windowTitle());
  });
}

PalletDocument::~PalletDocument() {
  // The undo stack outlives the name and path (members die in reverse order) and signals as it
  // clears itself: nothing of this document may listen to it by then.
  _undo.disconnect(this);
}

QString PalletDocument::windowTitle() const {
  return _name + QStringLiteral("[*] — PalletBallet");
}

void PalletDocument::apply(const pb::PalletConfig& pallet) {
  _pallet = pallet;
  _diagnostics = pb::validate(_pallet);
  emit changed(_pallet);
  emit validated(_diagnostics);
}

void PalletDocument::setFile(const QString& path, const QString& name) {
  const bool pathChanged = path != _path;
  const bool nameChanged = name != _name;
  _path = path;
  _name = name;
  if (nameChanged) emit titleChanged(windowTitle());
  if (pathChanged || !path.isEmpty()) emit fileChanged(_path);
}

bool PalletDocument::push(pb::PalletConfig after, const QString& text, int mergeKey) {
  if (after == _pallet) return true;  // nothing to record
  // A step edit, or the first edit of a drag: the command before it must not absorb it.
  if (mergeKey == kNoMerge || !_dragOpen) closeTop();
  auto* command = new PalletEditCommand(this, _pallet, std::move(after), text, mergeKey);
  if (mergeKey == kNoMerge) command->close();
  _dragOpen = mergeKey != kNoMerge;
  _pushing = true;
  _undo.push(command);
  _pushing = false;
  return true;
}

void PalletDocument::closeTop() {
  if (_undo.index() > 0) {
    auto* top = const_cast<QUndoCommand*>(_undo.command(_undo.index() - 1));
    static_cast<PalletEditCommand*>(top)->close();
  }
}

void PalletDocument::endDrag() {
  _dragOpen = false;
  closeTop();
}

// ---- Files

void PalletDocument::newDocument() {
  _undo.clear();
  _dragOpen = false;
  apply(empty_pallet());
  setFile(QString(), tr("Untitled"));
  emit modifiedChanged(false);
}

FileOutcome PalletDocument::open(const QString& path) {
  QFile file(path);
  if (!file.open(QIODevice::ReadOnly)) {
    return {false,
            {tr("cannot open '%1': %2; check the path and its permissions")
                 .arg(path, file.errorString())}};
  }
  const QByteArray bytes = file.read(qint64(pb::kMaxDocumentBytes) + 1);  // parse_json refuses more
  auto json = pb::parse_json(std::string_view(bytes.constData(), bytes.size()));
  if (!json) return {false, messages_of(json.diagnostics)};
  // A PalletConfig, or a scenario file holding one under "pallet" (the CLI's reader too).
  auto source = pb::pallet_source_from_json(*json);
  if (!source) return {false, messages_of(source.diagnostics)};
  const bool isScenario = !source->pointer_prefix.empty();
  QStringList messages = messages_of(source.diagnostics);
  _undo.clear();
  _dragOpen = false;
  apply(source->pallet);
  QString name = file_name(path);
  if (isScenario) {
    if (!source->scenario_name.empty()) name = QString::fromStdString(source->scenario_name);
    setFile(QString(), tr("%1 (scenario)").arg(name));
  } else {
    setFile(QFileInfo(path).absoluteFilePath(), name);
  }
  pb::Diagnostics findings = _diagnostics;
  for (auto& d : findings) d.pointer = source->pointer_prefix + d.pointer;
  messages << messages_of(findings);
  emit modifiedChanged(false);
  return {true, messages};
}

QByteArray PalletDocument::serialize(const pb::PalletConfig& config) {
  const std::string text = pb::pallet_to_json(config).dump(2) + "\n";
  return QByteArray(text.data(), static_cast<qsizetype>(text.size()));
}

FileOutcome PalletDocument::save() {
  if (_path.isEmpty()) {
    return {false, {tr("this pallet has no file yet; use Save As to choose one")}};
  }
  return saveAs(_path);
}

FileOutcome PalletDocument::saveAs(const QString& path) {
  QSaveFile file(path);
  // Unbuffered: Qt 6.4's buffered flush at commit() takes a short write (a full disk, a file-size
  // limit) for success and commits a truncated file; here every write is checked.
  if (!file.open(QIODevice::WriteOnly | QIODevice::Unbuffered)) {
    return {
        false,
        {tr("cannot write '%1': %2; choose another folder or name").arg(path, file.errorString())}};
  }
  const QByteArray bytes = serialize(_pallet);
  qsizetype done = 0;
  while (done < bytes.size()) {
    const qint64 n = file.write(bytes.constData() + done, bytes.size() - done);
    if (n <= 0) break;
    done += n;
  }
  if (done != bytes.size()) {
    file.cancelWriting();  // commit() then removes the temporary file and keeps the old one
  }
  if (done != bytes.size() || !file.commit()) {
    // QSaveFile leaves the old file untouched when the write or the rename fails.
    return {false,
            {tr("cannot write '%1' (%2 of %3 bytes written: %4); the file on disk is "
                "unchanged")
                 .arg(path)
                 .arg(done)
                 .arg(bytes.size())
                 .arg(file.errorString())}};
  }
  setFile(QFileInfo(path).absoluteFilePath(), file_name(path));
  _undo.setClean();
  return {true, {}};
}

// ---- Edits

bool PalletDocument::addStack(pb::Vec2 centre, const QString& sku, int height) {
  const pb::SkuTemplate* tmpl = pb::Catalog::builtin().find(sku.toStdString());
  if (!tmpl || height < 1 || !std::isfinite(centre[0]) || !std::isfinite(centre[1])) return false;
  pb::PalletConfig after = _pallet;
  double z = after.base_dims_m[2];
  for (int level = 0; level < height; ++level) {
    after.items.push_back(pb::make_item(*tmpl, {centre[0], centre[1], z}));
    z += tmpl->dims_m[2];
  }
  return push(std::move(after), tr("Add %1 × %2").arg(height).arg(sku));
}

bool PalletDocument::moveStack(int stack, pb::Vec2 centre, Edit edit) {
  const auto stacks = stacks_of(_pallet);
  if (stack < 0 || stack >= static_cast<int>(stacks.size())) return false;
  if (!std::isfinite(centre[0]) || !std::isfinite(centre[1])) return false;
  pb::PalletConfig after = _pallet;
  const double dx = centre[0] - stacks[stack].centre[0];
  const double dy = centre[1] - stacks[stack].centre[1];
  for (int k : stacks[stack].items) {
    after.items[k].position[0] += dx;
    after.items[k].position[1] += dy;
  }
  const int key = edit == Edit::drag ? kMoveStack + 16 * (stack + 1) : kNoMerge;
  return push(std::move(after), tr("Move stack %1").arg(stack + 1), key);
}

bool PalletDocument::deleteStack(int stack) {
  const auto stacks = stacks_of(_pallet);
  if (stack < 0 || stack >= static_cast<int>(stacks.size())) return false;
  pb::PalletConfig after = _pallet;
  std::vector<int> gone = stacks[stack].items;
  std::sort(gone.rbegin(), gone.rend());
  for (int k : gone) after.items.erase(after.items.begin() + k);
  return push(std::move(after), tr("Delete stack %1").arg(stack + 1));
}

bool PalletDocument::resizeStack(int stack, int height, Edit edit) {
  const auto stacks = stacks_of(_pallet);
  if (stack < 0 || stack >= static_cast<int>(stacks.size()) || height < 1) return false;
  const StackView& s = stacks[stack];
  pb::PalletConfig after = _pallet;
  if (height < s.height()) {
    std::vector<int> gone(s.items.begin() + height, s.items.end());
    std::sort(gone.rbegin(), gone.rend());
    for (int k : gone) after.items.erase(after.items.begin() + k);
  } else {
    pb::Item next = _pallet.items[s.items.back()];
    for (int level = s.height(); level < height; ++level) {
      next.position[2] += next.dims_m[2];
      after.items.push_back(next);
    }
  }
  const int key = edit == Edit::drag ? kResizeStack + 16 * (stack + 1) : kNoMerge;
  return push(std::move(after), tr("Stack %1: %2 high").arg(stack + 1).arg(height), key);
}

bool PalletDocument::applyPreset(pb::LayerPattern pattern, const QString& sku, int layers,
                                 QStringList* messages) {
  const auto fail = [&](QStringList why) {
    if (messages) *messages = std::move(why);
    return false;
  };
  if (pattern == pb::LayerPattern::irregular) {
    return fail({tr("/pattern: choose column, brick or pinwheel for a preset")});
  }
  const pb::Catalog& catalog = pb::Catalog::builtin();
  const pb::SkuTemplate* tmpl = catalog.find(sku.toStdString());
  if (!tmpl) return fail({tr("/sku: choose a SKU from the catalog list for the preset")});
  if (layers < 1) return fail({tr("/layers: give at least 1 layer")});
  pb::ScannerInputs inputs;
  inputs.pallet_id = _pallet.pallet_id;
  inputs.base_pallet_type = _pallet.base_pallet_type;
  inputs.pattern = pattern;
  inputs.layers = layers;
  inputs.skus = {tmpl->sku};
  inputs.wrap = _pallet.wrap;
  inputs.env = _pallet.env;
  inputs.body_temp_c = _pallet.body_temp_c;
  inputs.seconds_since_temp_change = _pallet.seconds_since_temp_change;
  inputs.belt_surface = _pallet.belt_surface;
  // As many per layer as fit: the most the scanner layout accepts (it says how many fit).
  const auto& dims = pb::pallet_type_spec(_pallet.base_pallet_type).dims_m;
  const double footprint = tmpl->dims_m[0] * tmpl->dims_m[1];
  int most = std::max(1, static_cast<int>(std::floor(dims[0] * dims[1] / footprint + 1e-9)));
  // A layout whose alternate layers had to be laid plain (turned or shifted, some cartons could
  // not stand) is kept only when no smaller count gives the pattern itself.
  const auto laid_plain = [](const pb::Result<pb::PalletConfig>& r) {
    return std::any_of(r.diagnostics.begin(), r.diagnostics.end(),
                       [](const pb::Diagnostic& d) { return d.pointer == "/pattern"; });
  };
  pb::Result<pb::PalletConfig> built;
  std::optional<pb::Result<pb::PalletConfig>> plain;
  for (int ti = most; ti >= 1; --ti) {
    inputs.items_per_layer = ti;
    built = pb::build_from_scanner(inputs, catalog);
    if (built && laid_plain(built)) {
      if (!plain) plain = built;
      continue;
    }
    if (built) break;
    // Only too many per layer is worth another try; any other reason is final.
    const bool perLayer = std::all_of(
        built.diagnostics.begin(), built.diagnostics.end(), [](const pb::Diagnostic& d) {
          return d.severity == pb::Severity::warning || d.pointer == "/items_per_layer";
        });
    if (!perLayer) break;
  }
  if (plain && (!built || laid_plain(built))) built = std::move(*plain);
  if (!built) {
    QStringList why;
    for (const auto& d : pb::condensed(pb::errors_of(built.diagnostics))) {
      why << QString::fromStdString(pb::to_string(d));
    }
    return fail(why);
  }
  pb::PalletConfig after = _pallet;
  after.base_dims_m = built->base_dims_m;
  after.base_mass_kg = built->base_mass_kg;
  after.items = built->items;
  if (messages) messages->clear();
  return push(std::move(after), tr("Preset %1: %2 layers of %3")
                                    .arg(QString::fromUtf8(pb::to_string(pattern).data(),
                                                           pb::to_string(pattern).size()))
                                    .arg(layers)
                                    .arg(sku));
}

bool PalletDocument::setWrap(pb::WrapType wrap) {
  pb::PalletConfig after = _pallet;
  after.wrap = wrap;
  return push(std::move(after), tr("Wrap"));
}

bool PalletDocument::setEnvironment(pb::Environment env) {
  pb::PalletConfig after = _pallet;
  after.env = env;
  return push(std::move(after), tr("Environment"));
}

bool PalletDocument::setBodyTemperature(double celsius, Edit edit) {
  if (!std::isfinite(celsius)) return false;
  pb::PalletConfig after = _pallet;
  after.body_temp_c = celsius;
  return push(std::move(after), tr("Body temperature"), edit == Edit::drag ? kBodyTemp : kNoMerge);
}

bool PalletDocument::setSecondsSinceTempChange(double seconds, Edit edit) {
  if (!std::isfinite(seconds)) return false;
  pb::PalletConfig after = _pallet;
  after.seconds_since_temp_change = seconds;
  return push(std::move(after), tr("Time since the temperature changed"),
              edit == Edit::drag ? kSinceChange : kNoMerge);
}

bool PalletDocument::setPalletType(pb::PalletType type) {
  const auto& spec = pb::pallet_type_spec(type);
  pb::PalletConfig after = _pallet;
  const double lift = spec.dims_m[2] - _pallet.base_dims_m[2];
  after.base_pallet_type = type;
  after.base_dims_m = spec.dims_m;
  after.base_mass_kg = spec.mass_kg;
  for (pb::Item& item : after.items) item.position[2] += lift;
  return push(std::move(after), tr("Pallet type"));
}

bool PalletDocument::replacePallet(const pb::PalletConfig& config, const QString& text) {
  return push(config, text);
}

void PalletDocument::restoreUnsaved(const pb::PalletConfig& pallet, const QString& path,
                                    const QString& name) {
  if (path.isEmpty() || !open(path).ok) {
    newDocument();
    if (!name.isEmpty()) setFile(QString(), name);
  }
  push(pallet, tr("Restore unsaved changes"));
}

bool PalletDocument::loadScenario(const pb::Scenario& scenario) {
  _undo.clear();
  _dragOpen = false;
  apply(scenario.pallet);
  setFile(QString(), QString::fromStdString(scenario.name));
  emit modifiedChanged(false);
  return true;
}

}  // namespace pb::ui
