#pragma once

// Hosts a VTK render window inside a Qt6 widget.
//
// Debian's VTK 9.1 Qt module (QVTKOpenGLNativeWidget) is built against Qt5,
// so this is a small stand-in: a QOpenGLWidget whose context drives a
// vtkGenericOpenGLRenderWindow, and whose input events are replayed on a
// vtkGenericRenderWindowInteractor. VTK renders into its own framebuffer;
// paintGL() blits the result into the widget's framebuffer. The render
// window's SwapBuffers is off (its display framebuffer is never filled): an
// image capture must read the back buffer (vtkWindowToImageFilter::
// ReadFrontBufferOff).

#include <QOpenGLWidget>
#include <QSurfaceFormat>

#include <vtkSmartPointer.h>

class QInputEvent;
class vtkGenericOpenGLRenderWindow;
class vtkGenericRenderWindowInteractor;
class vtkObject;
class vtkRenderWindowInteractor;

namespace linkscape::gui {

class VtkWidget : public QOpenGLWidget {
  Q_OBJECT

 public:
  explicit VtkWidget(QWidget* parent = nullptr);
  ~VtkWidget() override;

  // OpenGL 3.2 core, depth 24, stencil 8. Pass it to
  // QSurfaceFormat::setDefaultFormat() before constructing QApplication.
  static QSurfaceFormat defaultFormat();

  vtkGenericOpenGLRenderWindow* renderWindow() const;
  // Uses vtkInteractorStyleTrackballCamera. Never runs its own event loop;
  // its Render() requests become update() calls on this widget.
  vtkRenderWindowInteractor* interactor() const;

 signals:
  // Emitted after each paintGL() with the time vtkRenderWindow::Render() and
  // the copy of its image into the widget took (software OpenGL rasterises
  // until the copy).
  void rendered(double milliseconds);

 protected:
  void initializeGL() override;
  void resizeGL(int w, int h) override;
  void paintGL() override;

  void mousePressEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void wheelEvent(QWheelEvent* event) override;
  void enterEvent(QEnterEvent* event) override;
  void leaveEvent(QEvent* event) override;
  void keyPressEvent(QKeyEvent* event) override;
  void keyReleaseEvent(QKeyEvent* event) override;

 private:
  void onRenderWindowEvent(vtkObject* caller, unsigned long eventId, void* callData);
  void releaseGraphics();
  void setEventPosition(const QPointF& pos, const QInputEvent* event, int repeatCount = 0);

  vtkSmartPointer<vtkGenericOpenGLRenderWindow> renderWindow_;
  vtkSmartPointer<vtkGenericRenderWindowInteractor> interactor_;
  unsigned long observerTags_[6] = {};
  unsigned long renderRequestTag_ = 0;
  bool inPaint_ = false;
  int wheelDelta_ = 0;  // Accumulates high-resolution wheel deltas into notches.
};

}  // namespace linkscape::gui
