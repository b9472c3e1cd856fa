// SPDX-License-Identifier: MIT
#include "ui/replay/replay_view.hpp"

#include "ui/widgets/sku_color.hpp"

#include <QMouseEvent>
#include <QOffscreenSurface>
#include <QOpenGLContext>
#include <QOpenGLShaderProgram>
#include <QPainter>
#include <QQuaternion>
#include <QWheelEvent>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace pb::ui {

namespace {

constexpr float kGroundZ = -0.6f;     ///< the floor under the conveyor
constexpr float kBeltThick = 0.1f;    ///< the belt's top face is z = 0
constexpr float kBeltLength = 40.0f;  ///< from x = -10 m to x = 30 m
constexpr float kStripePitch = 0.5f;  ///< m between the belt's cross stripes
constexpr float kGridPitch = 0.5f;
constexpr float kGridHalf = 20.0f;

const char* kVertexShader = R"(
attribute vec3 a_pos;
attribute vec3 a_normal;
uniform mat4 u_mvp;
uniform mat3 u_normal;
varying vec3 v_normal;
void main() {
  v_normal = u_normal * a_normal;
  gl_Position = u_mvp * vec4(a_pos, 1.0);
}
)";

// Lit faces are the colour scaled by a Lambert term, so a face keeps its hue.
const char* kFragmentShader = R"(
uniform vec4 u_color;
uniform float u_lit;
varying vec3 v_normal;
void main() {
  float d = max(dot(normalize(v_normal), normalize(vec3(0.35, -0.5, 0.8))), 0.0);
  float k = mix(1.0, 0.55 + 0.45 * d, u_lit);
  gl_FragColor = vec4(u_color.rgb * k, u_color.a);
}
)";

QVector3D toQt(const pb::Vec3& v) {
  return QVector3D(static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]));
}

QQuaternion toQt(const pb::Quat& q) {
  return QQuaternion(static_cast<float>(q[0]), static_cast<float>(q[1]), static_cast<float>(q[2]),
                     static_cast<float>(q[3]));
}

/// The unit cube's 6 faces as 12 triangles: x, y, z, nx, ny, nz per vertex.
std::vector<float> cubeTriangles() {
  std::vector<float> out;
  for (int axis = 0; axis < 3; ++axis) {
    for (float sign : {-1.0f, 1.0f}) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const std::array<std::array<float, 2>, 6> corners{
          {{-1, -1}, {1, -1}, {1, 1}, {-1, -1}, {1, 1}, {-1, 1}}};
      for (const auto& c : corners) {
        std::array<float, 6> vertex{};
        vertex[axis] = 0.5f * sign;
        vertex[u] = 0.5f * c[0];  // no face culling: the winding does not matter
        vertex[v] = 0.5f * c[1];
        vertex[3 + axis] = sign;
        out.insert(out.end(), vertex.begin(), vertex.end());
      }
    }
  }
  return out;
}

/// The unit cube's 12 edges as line pairs (position only, normal 0).
std::vector<float> cubeEdges() {
  std::vector<float> out;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (float a : {-0.5f, 0.5f}) {
      for (float b : {-0.5f, 0.5f}) {
        for (float end : {-0.5f, 0.5f}) {
          std::array<float, 6> vertex{};
          vertex[axis] = end;
          vertex[u] = a;
          vertex[v] = b;
          out.insert(out.end(), vertex.begin(), vertex.end());
        }
      }
    }
  }
  return out;
}

std::vector<float> gridLines() {
  std::vector<float> out;
  const int n = static_cast<int>(kGridHalf / kGridPitch);
  for (int i = -n; i <= n; ++i) {
    const float c = static_cast<float>(i) * kGridPitch;
    for (const std::array<float, 6>& v : {std::array<float, 6>{c, -kGridHalf, kGroundZ, 0, 0, 1},
                                          std::array<float, 6>{c, kGridHalf, kGroundZ, 0, 0, 1},
                                          std::array<float, 6>{-kGridHalf, c, kGroundZ, 0, 0, 1},
                                          std::array<float, 6>{kGridHalf, c, kGroundZ, 0, 0, 1}}) {
      out.insert(out.end(), v.begin(), v.end());
    }
  }
  return out;
}

void upload(QOpenGLBuffer& buffer, const std::vector<float>& data) {
  buffer.create();
  buffer.bind();
  buffer.allocate(data.data(), static_cast<int>(data.size() * sizeof(float)));
  buffer.release();
}

/// Centre of the load at rest (pallet and items), where the camera looks first.
QVector3D loadCentre(const pb::Replay& replay) {
  if (replay.frames.empty()) return QVector3D(0.0f, 0.0f, 0.5f);
  const pb::ReplayFrame& f = replay.frames.front();
  float top = static_cast<float>(replay.pallet.base_dims_m[2]);
  for (std::size_t i = 0; i < f.items.size() && i < replay.pallet.items.size(); ++i) {
    top = std::max(top,
                   static_cast<float>(f.items[i].pos[2] + replay.pallet.items[i].dims_m[2] / 2.0));
  }
  return QVector3D(static_cast<float>(f.pallet.pos[0]), static_cast<float>(f.pallet.pos[1]),
                   top / 2.0f);
}

}  // namespace

QVector3D OrbitCamera::eye() const {
  const float yaw = qDegreesToRadians(yawDeg), pitch = qDegreesToRadians(pitchDeg);
  return target + distance * QVector3D(std::cos(pitch) * std::cos(yaw),
                                       std::cos(pitch) * std::sin(yaw), std::sin(pitch));
}

QMatrix4x4 OrbitCamera::view() const {
  QMatrix4x4 m;
  m.lookAt(eye(), target, QVector3D(0.0f, 0.0f, 1.0f));
  return m;
}

QMatrix4x4 OrbitCamera::projection(float aspect) const {
  QMatrix4x4 m;
  m.perspective(fovDeg, aspect, 0.05f, 200.0f);
  return m;
}

ReplayView::ReplayView(QWidget* parent) : QOpenGLWidget(parent) {
  setMinimumSize(320, 240);
  setFocusPolicy(Qt::StrongFocus);
}

ReplayView::~ReplayView() {
  if (context() == nullptr) return;
  makeCurrent();
  _program.reset();
  _cube.destroy();
  _edges.destroy();
  _grid.destroy();
  doneCurrent();
}

void ReplayView::setReplay(const pb::Replay& replay) {
  _replay = replay;
  _time = replay.frames.empty() ? 0.0 : replay.frames.front().t;
  _frame = frameAt(_replay, _time);
  float size = 1.0f;
  for (const pb::Item& item : _replay.pallet.items) {
    size = std::max(size, static_cast<float>(item.top_z()));
  }
  size = std::max(size, static_cast<float>(_replay.pallet.base_dims_m[0]));
  _camera.distance = 2.6f * size;
  _camera.target = loadCentre(_replay);
  setPreset(_preset);
}

void ReplayView::setTime(double t) {
  const pb::Vec3 before = _frame.pallet.pos;
  _frame = frameAt(_replay, t);
  _time = _frame.t;
  if (!_follow) {
    // Ride along with the load: the view moves with the pallet's travel (the belt's stripes show
    // the motion), so a wreck seconds down the belt stays in view; orbit and zoom are kept.
    _camera.target += QVector3D(static_cast<float>(_frame.pallet.pos[0] - before[0]),
                                static_cast<float>(_frame.pallet.pos[1] - before[1]), 0.0f);
  }
  updateFollowTarget();
  update();
}

pb::ReplayFrame ReplayView::frameAt(const pb::Replay& replay, double t) {
  return pb::frame_at(replay, t);
}

void ReplayView::setPreset(CameraPreset preset) {
  _preset = preset;
  switch (preset) {
    case CameraPreset::front:
      _camera.yawDeg = 0.0f, _camera.pitchDeg = 10.0f;
      break;
    case CameraPreset::side:
      _camera.yawDeg = -90.0f, _camera.pitchDeg = 10.0f;
      break;
    case CameraPreset::top:
      _camera.yawDeg = -90.0f, _camera.pitchDeg = 89.0f;
      break;
    case CameraPreset::iso:
      _camera.yawDeg = -45.0f, _camera.pitchDeg = 25.0f;
      break;
  }
  updateFollowTarget();
  update();
}

void ReplayView::setFollowFailure(bool follow) {
  if (follow == _follow) return;
  _follow = follow;
  if (follow) {
    // Close in on the followed item: three of its sizes away, where it fills about a quarter of
    // the view's height with its neighbours around it (the wheel still zooms).
    _distanceBeforeFollow = _camera.distance;
    double size = _replay.pallet.base_dims_m[0];
    if (_replay.failure && !_replay.failure->items.empty()) {
      const auto i = static_cast<std::size_t>(_replay.failure->items.front());
      if (i < _replay.pallet.items.size()) {
        const auto& d = _replay.pallet.items[i].dims_m;
        size = std::max({d[0], d[1], d[2]});
      }
    }
    _camera.distance = std::min(_camera.distance, static_cast<float>(std::max(0.8, 3.0 * size)));
  } else if (_distanceBeforeFollow > 0.0f) {
    _camera.distance = _distanceBeforeFollow;
  }
  updateFollowTarget();
  update();
}

void ReplayView::setCamera(const OrbitCamera& camera) {
  _camera = camera;
  update();
}

void ReplayView::updateFollowTarget() {
  if (!_follow || _frame.items.empty()) return;
  const pb::Pose* followed = &_frame.pallet;
  if (_replay.failure && !_replay.failure->items.empty()) {
    const auto i = static_cast<std::size_t>(_replay.failure->items.front());
    if (i < _frame.items.size()) followed = &_frame.items[i];
  }
  _camera.target = toQt(followed->pos);
}

QPointF ReplayView::project(const OrbitCamera& camera, QSize size, const QVector3D& world) {
  const float aspect =
      static_cast<float>(size.width()) / static_cast<float>(std::max(1, size.height()));
  const QVector3D ndc = (camera.projection(aspect) * camera.view()).map(world);
  return QPointF((ndc.x() + 1.0) / 2.0 * size.width(), (1.0 - ndc.y()) / 2.0 * size.height());
}

std::vector<ReplayView::Box> ReplayView::sceneBoxes() const {
  std::vector<Box> boxes;
  const double beltX = _frame.belt_x, beltY = _frame.belt_y;
  const auto beltWidth = static_cast<float>(_replay.pallet.base_dims_m[1] + 0.6);
  pb::Pose belt;
  belt.pos = {kBeltLength / 2.0 - 10.0, beltY, -kBeltThick / 2.0};
  boxes.push_back({belt, QVector3D(kBeltLength, beltWidth, kBeltThick), QColor(58, 60, 66)});
  // Cross stripes that travel with the belt (one pitch of travel looks like none).
  const double offset = std::fmod(beltX, static_cast<double>(kStripePitch));
  for (float x = -10.0f; x < kBeltLength - 10.0f; x += kStripePitch) {
    pb::Pose stripe;
    stripe.pos = {x + offset, beltY, 0.0005};
    boxes.push_back({stripe, QVector3D(0.06f, beltWidth, 0.001f), QColor(96, 99, 107)});
  }
  if (_frame.items.size() != _replay.pallet.items.size()) return boxes;
  // Every carton and the pallet with their edges, so that cartons of one SKU side by side or
  // stacked read as separate boxes, not one block; the failing item's in black, thicker.
  const QColor pallet(176, 132, 84);
  boxes.push_back(
      {_frame.pallet, toQt(_replay.pallet.base_dims_m), pallet, true, edgeColor(pallet)});
  std::vector<bool> failing(_frame.items.size(), false);
  if (_replay.failure) {
    for (int i : _replay.failure->items) {
      if (i >= 0 && static_cast<std::size_t>(i) < failing.size()) failing[i] = true;
    }
  }
  for (std::size_t i = 0; i < _frame.items.size(); ++i) {
    const pb::Item& item = _replay.pallet.items[i];
    if (failing[i]) {
      boxes.push_back(
          {_frame.items[i], toQt(item.dims_m), highlightColor(), false, QColor(20, 20, 20), 2.0f});
    } else {
      const QColor c = pb::ui::skuColor(item.sku);
      boxes.push_back({_frame.items[i], toQt(item.dims_m), c, true, edgeColor(c)});
    }
  }
  return boxes;
}

bool ReplayView::buildProgram() {
  _program = std::make_unique<QOpenGLShaderProgram>();
  if (!_program->addShaderFromSourceCode(QOpenGLShader::Vertex, kVertexShader) ||
      !_program->addShaderFromSourceCode(QOpenGLShader::Fragment, kFragmentShader)) {
    _glProblem = tr("The replay cannot be drawn: this OpenGL driver rejected the shaders (%1).")
                     .arg(_program->log().trimmed());
    return false;
  }
  _program->bindAttributeLocation("a_pos", 0);
  _program->bindAttributeLocation("a_normal", 1);
  if (!_program->link()) {
    _glProblem =
        tr("The replay cannot be drawn: this OpenGL driver could not link the shaders (%1).")
            .arg(_program->log().trimmed());
    return false;
  }
  return true;
}

QString ReplayView::noContextMessage() {
  return tr(
      "The replay needs OpenGL 2.1, and no OpenGL context could be created here. Every "
      "other panel works without it.");
}

QString ReplayView::probeOpenGl() {
  // Test hook (and a way out on a machine whose driver misbehaves): behave as if there were none.
  if (qEnvironmentVariableIntValue("PB_NO_OPENGL") != 0) return noContextMessage();
  QOpenGLContext context;
  if (!context.create()) return noContextMessage();
  QOffscreenSurface surface;
  surface.setFormat(context.format());
  surface.create();
  if (!surface.isValid() || !context.makeCurrent(&surface)) return noContextMessage();
  context.doneCurrent();
  return {};
}

void ReplayView::initializeGL() {
  QOpenGLContext* ctx = context();
  if (ctx == nullptr || !ctx->isValid()) {
    _glProblem = noContextMessage();
    return;
  }
  initializeOpenGLFunctions();
  if (!buildProgram()) return;
  upload(_cube, cubeTriangles());
  upload(_edges, cubeEdges());
  const std::vector<float> grid = gridLines();
  upload(_grid, grid);
  _gridVertices = static_cast<int>(grid.size() / 6);
}

void ReplayView::resizeGL(int, int) {}

void ReplayView::paintProblem() {
  QPainter painter(this);
  painter.fillRect(rect(), palette().window());
  painter.setPen(palette().windowText().color());
  painter.drawText(rect().adjusted(24, 24, -24, -24), Qt::AlignCenter | Qt::TextWordWrap,
                   _glProblem);
}

void ReplayView::paintGL() {
  if (!_glProblem.isEmpty() || !_program) {
    if (_glProblem.isEmpty()) _glProblem = tr("The replay cannot be drawn: OpenGL did not start.");
    paintProblem();
    return;
  }
  const QColor bg = backgroundColor();
  glClearColor(bg.redF(), bg.greenF(), bg.blueF(), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  // Faces a little behind their depth, so that the edges drawn on them (and on the faces of the
  // carton beside or above, at the same depth) are never hidden by them.
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.0f, 1.0f);
  const float aspect = static_cast<float>(width()) / static_cast<float>(std::max(1, height()));
  const QMatrix4x4 viewProjection = _camera.projection(aspect) * _camera.view();
  _program->bind();
  _program->enableAttributeArray(0);
  _program->enableAttributeArray(1);
  drawGrid(viewProjection);
  for (const Box& box : sceneBoxes()) drawBox(viewProjection, box);
  _program->disableAttributeArray(0);
  _program->disableAttributeArray(1);
  _program->release();
}

void ReplayView::drawGrid(const QMatrix4x4& viewProjection) {
  _grid.bind();
  _program->setAttributeBuffer(0, GL_FLOAT, 0, 3, 6 * sizeof(float));
  _program->setAttributeBuffer(1, GL_FLOAT, 3 * sizeof(float), 3, 6 * sizeof(float));
  _program->setUniformValue("u_mvp", viewProjection);
  _program->setUniformValue("u_normal", QMatrix3x3());
  _program->setUniformValue("u_color", QColor(196, 202, 210));
  _program->setUniformValue("u_lit", 0.0f);
  glDrawArrays(GL_LINES, 0, _gridVertices);
  _grid.release();
}

void ReplayView::drawBox(const QMatrix4x4& viewProjection, const Box& box) {
  QMatrix4x4 model;
  model.translate(toQt(box.pose.pos));
  model.rotate(toQt(box.pose.quat));
  model.scale(box.dims);
  _program->setUniformValue("u_mvp", viewProjection * model);
  _program->setUniformValue("u_normal", model.normalMatrix());
  _program->setUniformValue("u_color", box.color);
  _program->setUniformValue("u_lit", box.lit ? 1.0f : 0.0f);
  _cube.bind();
  _program->setAttributeBuffer(0, GL_FLOAT, 0, 3, 6 * sizeof(float));
  _program->setAttributeBuffer(1, GL_FLOAT, 3 * sizeof(float), 3, 6 * sizeof(float));
  glDrawArrays(GL_TRIANGLES, 0, 36);
  _cube.release();
  if (!box.edge.isValid()) return;
  _edges.bind();
  _program->setAttributeBuffer(0, GL_FLOAT, 0, 3, 6 * sizeof(float));
  _program->setAttributeBuffer(1, GL_FLOAT, 3 * sizeof(float), 3, 6 * sizeof(float));
  _program->setUniformValue("u_color", box.edge);
  _program->setUniformValue("u_lit", 0.0f);
  glLineWidth(box.edgeWidth);
  glDrawArrays(GL_LINES, 0, 24);
  glLineWidth(1.0f);
  _edges.release();
}

void ReplayView::mousePressEvent(QMouseEvent* event) {
  _lastMouse = event->position().toPoint();
}

void ReplayView::mouseMoveEvent(QMouseEvent* event) {
  const QPoint now = event->position().toPoint();
  const QPoint delta = now - _lastMouse;
  _lastMouse = now;
  if (event->buttons() & Qt::LeftButton) {  // orbit
    _camera.yawDeg -= 0.4f * static_cast<float>(delta.x());
    _camera.pitchDeg =
        std::clamp(_camera.pitchDeg + 0.4f * static_cast<float>(delta.y()), -89.0f, 89.0f);
  } else if (event->buttons() & (Qt::RightButton | Qt::MiddleButton)) {  // pan (stops following)
    _follow = false;
    const QMatrix4x4 view = _camera.view();
    const QVector3D right(view(0, 0), view(0, 1), view(0, 2));
    const QVector3D up(view(1, 0), view(1, 1), view(1, 2));
    const float perPixel = _camera.distance * 2.0f *
                           std::tan(qDegreesToRadians(_camera.fovDeg) / 2.0f) /
                           static_cast<float>(std::max(1, height()));
    _camera.target +=
        perPixel * (-static_cast<float>(delta.x()) * right + static_cast<float>(delta.y()) * up);
  }
  update();
}

void ReplayView::wheelEvent(QWheelEvent* event) {
  const float steps = static_cast<float>(event->angleDelta().y()) / 120.0f;
  _camera.distance = std::clamp(_camera.distance * std::pow(0.9f, steps), 0.3f, 60.0f);
  update();
}

}  // namespace pb::ui
