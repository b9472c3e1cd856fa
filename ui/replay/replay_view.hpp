// SPDX-License-Identifier: MIT
// The 3D replay: the pallet on the moving belt, each item coloured by SKU and the failing item
// highlighted, played from the core's 30 Hz pose trace (lerp positions, slerp orientations).
#pragma once

#include <QColor>
#include <QMatrix4x4>
#include <QOpenGLBuffer>
#include <QOpenGLFunctions>
#include <QOpenGLWidget>
#include <QPoint>
#include <QPointF>
#include <QVector3D>
#include <memory>
#include <string>
#include <vector>

#include "core/analysis/replay.hpp"

class QOpenGLShaderProgram;

namespace pb::ui {

/// An orbit camera around `target` (world frame: +X belt travel, +Y lateral, +Z up).
struct OrbitCamera {
  QVector3D target{0.0f, 0.0f, 0.5f};
  float yawDeg = -45.0f;   ///< azimuth of the eye around +Z, 0 = on the +X side (the front)
  float pitchDeg = 25.0f;  ///< elevation of the eye above the horizon, in (-89, 89]
  float distance = 4.0f;   ///< m from the target
  float fovDeg = 40.0f;    ///< vertical field of view

  QVector3D eye() const;
  QMatrix4x4 view() const;
  QMatrix4x4 projection(float aspect) const;
};

enum class CameraPreset { front, side, top, iso };

/// The only owner of its GL context. Needs OpenGL 2.1 (or any compatibility context); if none can
/// be had, it shows why, in words, where the scene would be, and everything else keeps working.
class ReplayView : public QOpenGLWidget, protected QOpenGLFunctions {
  Q_OBJECT

 public:
  explicit ReplayView(QWidget* parent = nullptr);
  ~ReplayView() override;

  /// Shows `replay` at its first frame and frames the load with the current preset.
  void setReplay(const pb::Replay& replay);
  const pb::Replay& replay() const { return _replay; }
  /// Moves the replay to `t` seconds (clamped to the replay's frames). The camera rides along
  /// with the pallet's horizontal travel (or follows the failing item: setFollowFailure).
  void setTime(double t);
  double time() const { return _time; }
  /// The poses shown at the current time, interpolated between the two frames around it.
  const pb::ReplayFrame& currentFrame() const { return _frame; }

  void setPreset(CameraPreset preset);
  /// Keeps the failing item (the pallet when nothing failed) at the centre of the view, closer
  /// in (three of its sizes away); off again, the camera steps back to where it was.
  void setFollowFailure(bool follow);
  bool followFailure() const { return _follow; }
  const OrbitCamera& camera() const { return _camera; }
  void setCamera(const OrbitCamera& camera);

  /// Empty while OpenGL works; otherwise the sentence shown instead of the scene.
  QString glProblem() const { return _glProblem; }
  /// Tries to create an OpenGL context off screen: empty if one can be had, else the sentence to
  /// show instead of a ReplayView (a QOpenGLWidget whose context fails cannot paint at all).
  /// PB_NO_OPENGL=1 in the environment makes it fail (tests, or a driver that misbehaves).
  static QString probeOpenGl();

  /// Where `world` lands in a widget of `size` (logical pixels, origin top-left) seen by `camera`.
  static QPointF project(const OrbitCamera& camera, QSize size, const QVector3D& world);
  /// The same with this view's camera and size.
  QPointF project(const QVector3D& world) const { return project(_camera, size(), world); }

  /// The failing items' colour (drawn unlit, with a dark outline).
  static QColor highlightColor() { return QColor(255, 32, 32); }
  /// The colour a carton's (or the pallet's) edges are drawn in: its own, much darker.
  static QColor edgeColor(const QColor& face) { return face.darker(260); }
  static QColor backgroundColor() { return QColor(232, 236, 241); }

  /// The frame at time `t` of `replay` (clamped): pb::frame_at.
  static pb::ReplayFrame frameAt(const pb::Replay& replay, double t);

 protected:
  void initializeGL() override;
  void resizeGL(int w, int h) override;
  void paintGL() override;
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;

 private:
  struct Box {
    pb::Pose pose;
    QVector3D dims;
    QColor color;
    bool lit = true;
    QColor edge = QColor();  ///< its 12 edges drawn in this colour (none if invalid)
    float edgeWidth = 1.0f;
  };
  std::vector<Box> sceneBoxes() const;
  void updateFollowTarget();
  void drawBox(const QMatrix4x4& viewProjection, const Box& box);
  void drawGrid(const QMatrix4x4& viewProjection);
  void paintProblem();
  static QString noContextMessage();
  bool buildProgram();

  pb::Replay _replay;
  pb::ReplayFrame _frame;
  double _time = 0.0;
  OrbitCamera _camera;
  CameraPreset _preset = CameraPreset::iso;
  bool _follow = false;
  float _distanceBeforeFollow = 0.0f;  ///< restored when following stops
  QPoint _lastMouse;
  QString _glProblem;
  std::unique_ptr<QOpenGLShaderProgram> _program;
  QOpenGLBuffer _cube{QOpenGLBuffer::VertexBuffer};   ///< 36 vertices: position, normal
  QOpenGLBuffer _edges{QOpenGLBuffer::VertexBuffer};  ///< 24 vertices: the 12 edges
  QOpenGLBuffer _grid{QOpenGLBuffer::VertexBuffer};   ///< ground grid lines
  int _gridVertices = 0;
};

}  // namespace pb::ui
