#pragma once

// Hosts a VTK render window inside a Qt6 widget.
//
// Debian's VTK 9.1 Qt module (QVTKOpenGLNativeWidget) is built against Qt5,
// so this is a small stand-in: a native OpenGL window (QOpenGLWindow) in a
// window container, whose context drives a vtkGenericOpenGLRenderWindow,
// and whose input events are replayed on a vtkGenericRenderWindowInteractor.
// VTK renders into its own framebuffer; paintGL() blits the result into the
// window's. A native window reaches the screen by its own buffer swap: a
// QOpenGLWidget's frame is instead composed with the whole top-level window
// by OpenGL on every frame, which under software OpenGL cost more than
// drawing the scene (docs/performance.md). The render window's SwapBuffers
// is off (its display framebuffer is never filled): an image capture must
// read the back buffer (vtkWindowToImageFilter::ReadFrontBufferOff).
//
// A widget's grab() leaves a native child window out: grabWindow() below
// paints the views into the grabbed image.

#include <QImage>
#include <QSurfaceFormat>
#include <QWidget>

#include <vtkSmartPointer.h>

class QEnterEvent;
class QInputEvent;
class QKeyEvent;
class QMouseEvent;
class QWheelEvent;
class QWindow;
class vtkGenericOpenGLRenderWindow;
class vtkGenericRenderWindowInteractor;
class vtkObject;
class vtkRenderWindowInteractor;
class vtkRenderer;

namespace linkscape::gui {

class ViewWindow;

// The largest side of the window and of a view image, in pixels: off-screen
// framebuffers beyond that fail inside the OpenGL driver (a crash, not an error).
inline constexpr int kMaxWindowSide = 8192;

class VtkWidget : public QWidget {
  Q_OBJECT

 public:
  explicit VtkWidget(QWidget* parent = nullptr);
  ~VtkWidget() override;

  // OpenGL 3.2 core, depth 24, stencil 8. Pass it to
  // QSurfaceFormat::setDefaultFormat() before constructing QApplication.
  static QSurfaceFormat defaultFormat();

  vtkGenericOpenGLRenderWindow* renderWindow() const;
  // Uses vtkInteractorStyleTrackballCamera. Never runs its own event loop;
  // its Render() requests become requestRender() calls.
  vtkRenderWindowInteractor* interactor() const;

  // Schedules a frame (the scene changed).
  void requestRender();
  // The scene rendered now, at the view's size in device pixels (a null
  // image before the view has been shown).
  QImage grabFramebuffer();
  // The view alone drawn at width x height pixels (the view is resized for
  // one frame, so the picture is rendered at that size, not scaled; text
  // and the colour bar's strip grow with the height, so they keep their
  // share of the picture). Throws std::invalid_argument outside
  // 16..kMaxWindowSide pixels a side.
  QImage imageAt(int width, int height);
  // How much larger than on screen text is drawn: 1 but while imageAt() draws.
  double textScale() const { return textScale_; }
  // Whether imageAt() is drawing (the view is resized for the picture only).
  bool drawingPicture() const { return drawingPicture_; }
  // The view's renderers: the scene's, on a gradient; at its right the colour
  // bar's strip (not interactive), so the bar never covers the data; and over
  // the scene, with its camera and viewport, the handles the user drags.
  struct Renderers {
    vtkRenderer* scene;
    vtkRenderer* legend;
    vtkRenderer* handles;
  };
  Renderers addRenderers();
  // `window` as grab() shows it, with every visible view inside it painted in.
  static QImage grabWindow(QWidget* window);
  // The native window that draws the view and receives its input.
  QWindow* nativeWindow() const;

 signals:
  // Emitted after each paintGL() with the time vtkRenderWindow::Render() and
  // the copy of its image into the window took (software OpenGL rasterises
  // until the copy).
  void rendered(double milliseconds);
  // The render window has taken the view's new size (after resizeGL()).
  void resized();

 protected:
  // Input arrives at the native window, which hands it here; events sent
  // to this widget itself (tests) take the same way.
  void mousePressEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;
  void enterEvent(QEnterEvent* event) override;
  void leaveEvent(QEvent* event) override;
  void keyPressEvent(QKeyEvent* event) override;
  void keyReleaseEvent(QKeyEvent* event) override;

 private:
  friend class ViewWindow;
  void initializeGL();
  void resizeGL();
  void paintGL();
  // Renders the scene into VTK's framebuffer and binds it for reading, with
  // VTK's GL state pushed (the caller pops it).
  void renderForReading();
  void onRenderWindowEvent(vtkObject* caller, unsigned long eventId, void* callData);
  void releaseGraphics();
  void setEventPosition(const QPointF& pos, const QInputEvent* event, int repeatCount = 0);
  double pixelRatio() const;

  ViewWindow* window_ = nullptr;  // owned by its container, a child of this widget
  vtkSmartPointer<vtkGenericOpenGLRenderWindow> renderWindow_;
  vtkSmartPointer<vtkGenericRenderWindowInteractor> interactor_;
  unsigned long observerTags_[6] = {};
  unsigned long renderRequestTag_ = 0;
  bool inPaint_ = false;
  bool renderPosted_ = false;  // a paint event is on its way to window_
  int wheelDelta_ = 0;  // Accumulates high-resolution wheel deltas into notches.
  double textScale_ = 1.0;
  bool drawingPicture_ = false;
};

}  // namespace linkscape::gui
