#include "gui/window/vtk_widget.h"

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QKeyEvent>
#include <QMouseEvent>
#include <QOpenGLContext>
#include <QOpenGLFunctions>
#include <QOpenGLWindow>
#include <QPaintEvent>
#include <QPainter>
#include <QScopedValueRollback>
#include <QScreen>
#include <QVBoxLayout>
#include <QWheelEvent>

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkGenericRenderWindowInteractor.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkNew.h>
#include <vtkRenderer.h>
#include <vtkOpenGLFramebufferObject.h>
#include <vtkOpenGLState.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <iterator>

#include "render/scene_renderer.h"

namespace linkscape::gui {

namespace {

// VTK names keys by X11 keysym; the interactor styles only look at a few.
const char* keySym(const QKeyEvent* event) {
  switch (event->key()) {
    case Qt::Key_Left: return "Left";
    case Qt::Key_Right: return "Right";
    case Qt::Key_Up: return "Up";
    case Qt::Key_Down: return "Down";
    case Qt::Key_PageUp: return "Prior";
    case Qt::Key_PageDown: return "Next";
    case Qt::Key_Home: return "Home";
    case Qt::Key_End: return "End";
    case Qt::Key_Return: return "Return";
    case Qt::Key_Enter: return "KP_Enter";
    case Qt::Key_Escape: return "Escape";
    case Qt::Key_Tab: return "Tab";
    case Qt::Key_Backspace: return "BackSpace";
    case Qt::Key_Delete: return "Delete";
    case Qt::Key_Space: return "space";
    case Qt::Key_Shift: return "Shift_L";
    case Qt::Key_Control: return "Control_L";
    case Qt::Key_Alt: return "Alt_L";
    default: return nullptr;
  }
}

// Returns the key's ASCII code, or 0 for keys without one.
char setKeyInformation(vtkRenderWindowInteractor* interactor, const QKeyEvent* event) {
  const QString text = event->text();
  const char ascii = text.size() == 1 && text[0].unicode() < 128 ? text[0].toLatin1() : '\0';
  const char letter[2] = {ascii, '\0'};
  const char* name = keySym(event);
  if (!name && ascii > ' ') name = letter;
  const Qt::KeyboardModifiers mods = event->modifiers();
  // SetKeyEventInformation copies the key sym string.
  interactor->SetKeyEventInformation((mods & Qt::ControlModifier) ? 1 : 0,
                                     (mods & Qt::ShiftModifier) ? 1 : 0, ascii,
                                     event->isAutoRepeat() ? 1 : 0, name);
  interactor->SetAltKey((mods & Qt::AltModifier) ? 1 : 0);
  return ascii;
}

}  // namespace

// The native window the view draws into: its OpenGL calls and its input go
// to the VtkWidget that owns it.
class ViewWindow : public QOpenGLWindow {
 public:
  // VTK redraws the whole frame; Qt need not preserve the old contents.
  explicit ViewWindow(VtkWidget* view) : QOpenGLWindow(QOpenGLWindow::NoPartialUpdate), view_(view) {}

 protected:
  void initializeGL() override { view_->initializeGL(); }
  void resizeGL(int, int) override { view_->resizeGL(); }
  void paintGL() override { view_->paintGL(); }

  void mousePressEvent(QMouseEvent* event) override { view_->mousePressEvent(event); }
  void mouseReleaseEvent(QMouseEvent* event) override { view_->mouseReleaseEvent(event); }
  void mouseDoubleClickEvent(QMouseEvent* event) override { view_->mousePressEvent(event); }
  void mouseMoveEvent(QMouseEvent* event) override { view_->mouseMoveEvent(event); }
  void wheelEvent(QWheelEvent* event) override { view_->wheelEvent(event); }
  void keyPressEvent(QKeyEvent* event) override { view_->keyPressEvent(event); }
  void keyReleaseEvent(QKeyEvent* event) override { view_->keyReleaseEvent(event); }
  bool event(QEvent* event) override {
    if (event->type() == QEvent::Paint) {
      view_->renderPosted_ = false;
      // A posted paint can arrive after the window lost its surface (its
      // top-level hidden or closed): it is drawn when next exposed.
      if (!isExposed() || !handle()) {
        update();
        return true;
      }
    }
    if (event->type() == QEvent::Enter) view_->enterEvent(static_cast<QEnterEvent*>(event));
    if (event->type() == QEvent::Leave) view_->leaveEvent(event);
    return QOpenGLWindow::event(event);
  }

 private:
  VtkWidget* view_;
};

VtkWidget::VtkWidget(QWidget* parent)
    : QWidget(parent),
      window_(new ViewWindow(this)),
      renderWindow_(vtkSmartPointer<vtkGenericOpenGLRenderWindow>::New()),
      interactor_(vtkSmartPointer<vtkGenericRenderWindowInteractor>::New()) {
  setFocusPolicy(Qt::StrongFocus);
  QWidget* container = QWidget::createWindowContainer(window_, this);
  container->setFocusPolicy(Qt::StrongFocus);
  setFocusProxy(container);
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(container);

  // Nothing can render before initializeGL() hands VTK a context.
  renderWindow_->SetReadyForRendering(false);
  // paintGL() blits VTK's render framebuffer into ours; VTK must not blit on
  // its own. With SwapBuffers off VTK also leaves out its copy of colour and
  // depth into its display framebuffer, a full-view copy per frame that
  // nothing reads (under software OpenGL about a millisecond and more).
  renderWindow_->SetFrameBlitModeToNoBlit();
  renderWindow_->SetSwapBuffers(0);
  renderWindow_->SetOwnContext(0);
  // Depth peeling (order-independent transparency of the workspace surfaces)
  // needs destination alpha in VTK's framebuffer and no multisampling.
  renderWindow_->SetAlphaBitPlanes(1);
  renderWindow_->SetMultiSamples(0);

  const unsigned long events[] = {
      vtkCommand::WindowMakeCurrentEvent, vtkCommand::WindowIsCurrentEvent,
      vtkCommand::WindowFrameEvent,       vtkCommand::WindowIsDirectEvent,
      vtkCommand::WindowSupportsOpenGLEvent, vtkCommand::CursorChangedEvent};
  static_assert(std::size(events) == std::size(decltype(observerTags_){}));
  for (std::size_t i = 0; i < std::size(events); ++i)
    observerTags_[i] = renderWindow_->AddObserver(events[i], this, &VtkWidget::onRenderWindowEvent);

  interactor_->SetRenderWindow(renderWindow_);
  vtkNew<vtkInteractorStyleTrackballCamera> style;
  interactor_->SetInteractorStyle(style);
  // All rendering happens in paintGL(), where the widget's framebuffer is
  // bound; the interactor's render requests are turned into requestRender() calls.
  interactor_->EnableRenderOff();
  renderRequestTag_ = interactor_->AddObserver(vtkCommand::RenderEvent, this,
                                               &VtkWidget::onRenderWindowEvent);
  interactor_->Initialize();
}

VtkWidget::~VtkWidget() {
  // The window's context outlives this part of the object only until its
  // container (a child) goes: clean up here while it exists.
  if (QOpenGLContext* ctx = window_->context()) {
    disconnect(ctx, &QOpenGLContext::aboutToBeDestroyed, this, nullptr);
    window_->makeCurrent();
    releaseGraphics();
    window_->doneCurrent();
  }
  interactor_->RemoveObserver(renderRequestTag_);
  for (unsigned long tag : observerTags_) renderWindow_->RemoveObserver(tag);
  // Others may hold references to the render window; keep them from
  // reaching this widget through the interactor.
  interactor_->SetInteractorStyle(nullptr);
  renderWindow_->SetInteractor(nullptr);
}

QSurfaceFormat VtkWidget::defaultFormat() {
  QSurfaceFormat format;
  format.setRenderableType(QSurfaceFormat::OpenGL);
  format.setVersion(3, 2);
  format.setProfile(QSurfaceFormat::CoreProfile);
  format.setSwapBehavior(QSurfaceFormat::DoubleBuffer);
  format.setRedBufferSize(8);
  format.setGreenBufferSize(8);
  format.setBlueBufferSize(8);
  format.setDepthBufferSize(24);
  format.setStencilBufferSize(8);
  // VTK multisamples in its own framebuffer if asked; the widget never needs to.
  format.setSamples(0);
  return format;
}

vtkGenericOpenGLRenderWindow* VtkWidget::renderWindow() const { return renderWindow_; }

vtkRenderWindowInteractor* VtkWidget::interactor() const { return interactor_; }

void VtkWidget::requestRender() {
  // Not QWindow::requestUpdate() (QOpenGLWindow::update()), which waits for
  // a 5 ms timer on xcb: a posted paint event is handled on the event loop's
  // next pass, as a widget's update is. One at a time; a hidden window
  // paints when it is exposed.
  if (!window_->isExposed()) {
    window_->update();
    return;
  }
  if (renderPosted_) return;
  renderPosted_ = true;
  QCoreApplication::postEvent(window_, new QPaintEvent(QRect(QPoint(0, 0), window_->size())), Qt::LowEventPriority);
}

QWindow* VtkWidget::nativeWindow() const { return window_; }

double VtkWidget::pixelRatio() const { return window_->devicePixelRatio(); }

void VtkWidget::initializeGL() {
  connect(window_->context(), &QOpenGLContext::aboutToBeDestroyed, this, &VtkWidget::releaseGraphics,
          static_cast<Qt::ConnectionType>(Qt::DirectConnection | Qt::UniqueConnection));

  vtkOpenGLState* state = renderWindow_->GetState();
  state->Reset();
  // Qt leaves GL_LESS; VTK's shaders rely on GL_LEQUAL.
  state->vtkglDepthFunc(GL_LEQUAL);

  renderWindow_->SetReadyForRendering(true);
  renderWindow_->OpenGLInitContext();
  resizeGL();
}

void VtkWidget::resizeGL() {
  // VTK wants device pixels.
  const double dpr = pixelRatio();
  interactor_->UpdateSize(static_cast<int>(std::lround(window_->width() * dpr)),
                          static_cast<int>(std::lround(window_->height() * dpr)));
  // Keeps text and line widths the same physical size on HiDPI screens.
  renderWindow_->SetDPI(std::max(1, static_cast<int>(std::lround(72 * dpr * textScale_))));
  if (const QScreen* s = window_->screen()) {
    const QSize screenSize = s->size() * dpr;
    renderWindow_->SetScreenSize(screenSize.width(), screenSize.height());
  }
  emit resized();
}

void VtkWidget::renderForReading() {
  // Qt changed GL state behind VTK's cache: resync it (the caller gives Qt
  // its state back with Pop()).
  vtkOpenGLState* state = renderWindow_->GetState();
  state->Reset();
  state->Push();
  state->vtkglDepthFunc(GL_LEQUAL);
  {
    QScopedValueRollback<bool> painting(inPaint_, true);
    renderWindow_->Render();
  }
  // Observers of the render (progress bars, other GL widgets) may have made
  // another context current.
  window_->makeCurrent();
  vtkOpenGLFramebufferObject* frame = renderWindow_->GetRenderFramebuffer();
  frame->Bind(GL_READ_FRAMEBUFFER);
  frame->ActivateReadBuffer(0);
}

void VtkWidget::paintGL() {
  if (!renderWindow_->GetReadyForRendering()) return;
  QElapsedTimer timer;
  timer.start();
  renderForReading();
  vtkOpenGLState* state = renderWindow_->GetState();
  const int w = static_cast<int>(std::lround(window_->width() * pixelRatio()));
  const int h = static_cast<int>(std::lround(window_->height() * pixelRatio()));
  const int* source = renderWindow_->GetSize();
  state->vtkglBindFramebuffer(GL_DRAW_FRAMEBUFFER, window_->defaultFramebufferObject());
  state->vtkglBlitFramebuffer(0, 0, source[0], source[1], 0, 0, w, h, GL_COLOR_BUFFER_BIT,
                              source[0] == w && source[1] == h ? GL_NEAREST : GL_LINEAR);
  // The copy waits for the rasteriser to finish VTK's frame: the time to here
  // is what the frame cost.
  const double milliseconds = static_cast<double>(timer.nsecsElapsed()) / 1e6;

  state->Pop();
  emit rendered(milliseconds);
}

QImage VtkWidget::grabFramebuffer() {
  if (!window_->isExposed() || !window_->context() || !renderWindow_->GetReadyForRendering()) return {};
  window_->makeCurrent();
  renderForReading();
  const int* size = renderWindow_->GetSize();
  QImage image(size[0], size[1], QImage::Format_RGBA8888);
  QOpenGLFunctions* gl = window_->context()->functions();
  gl->glPixelStorei(GL_PACK_ALIGNMENT, 4);
  gl->glReadPixels(0, 0, size[0], size[1], GL_RGBA, GL_UNSIGNED_BYTE, image.bits());
  renderWindow_->GetState()->Pop();
  // OpenGL's rows run bottom up; the view is opaque.
  image = image.mirrored().convertToFormat(QImage::Format_RGB32);
  image.setDevicePixelRatio(pixelRatio());
  return image;
}

QImage VtkWidget::grabWindow(QWidget* window) {
  QImage image = window->grab().toImage();
  QPainter painter(&image);
  for (VtkWidget* view : window->findChildren<VtkWidget*>()) {
    if (!view->isVisible()) continue;
    const QImage frame = view->grabFramebuffer();
    if (!frame.isNull()) painter.drawImage(QRect(view->mapTo(window, QPoint(0, 0)), view->size()), frame);
  }
  return image;
}

void VtkWidget::releaseGraphics() {
  if (!renderWindow_->GetReadyForRendering()) return;
  // Finalize() makes the context current through WindowMakeCurrentEvent.
  renderWindow_->Finalize();
  renderWindow_->SetReadyForRendering(false);
}

void VtkWidget::onRenderWindowEvent(vtkObject*, unsigned long eventId, void* callData) {
  QOpenGLContext* ctx = window_->context();
  switch (eventId) {
    case vtkCommand::WindowMakeCurrentEvent:
      // Not QOpenGLWindow::makeCurrent(), which binds the window's
      // framebuffer: VTK binds its own.
      if (ctx) ctx->makeCurrent(window_);
      break;
    case vtkCommand::WindowIsCurrentEvent: {
      const QOpenGLContext* current = QOpenGLContext::currentContext();
      *static_cast<bool*>(callData) =
          ctx && current == ctx && current->surface() == ctx->surface();
      break;
    }
    case vtkCommand::WindowIsDirectEvent:
      *static_cast<int*>(callData) = 1;
      break;
    case vtkCommand::WindowSupportsOpenGLEvent:
      *static_cast<int*>(callData) = ctx && ctx->isValid() ? 1 : 0;
      break;
    case vtkCommand::WindowFrameEvent:
    case vtkCommand::RenderEvent:
      // A render outside paintGL() (someone called Render() directly, or an
      // image capture) must still reach the screen.
      if (!inPaint_) requestRender();
      break;
    case vtkCommand::CursorChangedEvent:
      switch (*static_cast<int*>(callData)) {
        case VTK_CURSOR_HAND: window_->setCursor(Qt::PointingHandCursor); break;
        case VTK_CURSOR_CROSSHAIR: window_->setCursor(Qt::CrossCursor); break;
        case VTK_CURSOR_SIZEALL: window_->setCursor(Qt::SizeAllCursor); break;
        default: window_->unsetCursor(); break;
      }
      break;
    default:
      break;
  }
}

void VtkWidget::setEventPosition(const QPointF& pos, const QInputEvent* event, int repeatCount) {
  const double dpr = pixelRatio();
  const Qt::KeyboardModifiers mods = event->modifiers();
  interactor_->SetEventInformationFlipY(static_cast<int>(std::lround(pos.x() * dpr)),
                                        static_cast<int>(std::lround(pos.y() * dpr)),
                                        (mods & Qt::ControlModifier) ? 1 : 0,
                                        (mods & Qt::ShiftModifier) ? 1 : 0, 0, repeatCount);
  interactor_->SetAltKey((mods & Qt::AltModifier) ? 1 : 0);
}

void VtkWidget::mousePressEvent(QMouseEvent* event) {
  // QWidget routes double clicks here too; VTK marks them with a repeat count.
  setEventPosition(event->position(), event,
                   event->type() == QEvent::MouseButtonDblClick ? 1 : 0);
  switch (event->button()) {
    case Qt::LeftButton: interactor_->InvokeEvent(vtkCommand::LeftButtonPressEvent, event); break;
    case Qt::MiddleButton: interactor_->InvokeEvent(vtkCommand::MiddleButtonPressEvent, event); break;
    case Qt::RightButton: interactor_->InvokeEvent(vtkCommand::RightButtonPressEvent, event); break;
    default: break;
  }
  requestRender();
}

void VtkWidget::mouseReleaseEvent(QMouseEvent* event) {
  setEventPosition(event->position(), event);
  switch (event->button()) {
    case Qt::LeftButton: interactor_->InvokeEvent(vtkCommand::LeftButtonReleaseEvent, event); break;
    case Qt::MiddleButton: interactor_->InvokeEvent(vtkCommand::MiddleButtonReleaseEvent, event); break;
    case Qt::RightButton: interactor_->InvokeEvent(vtkCommand::RightButtonReleaseEvent, event); break;
    default: break;
  }
  requestRender();
}

void VtkWidget::mouseMoveEvent(QMouseEvent* event) {
  setEventPosition(event->position(), event);
  interactor_->InvokeEvent(vtkCommand::MouseMoveEvent, event);
  requestRender();
}

void VtkWidget::wheelEvent(QWheelEvent* event) {
  // Touchpads send many small deltas; VTK expects one event per 120-unit notch.
  wheelDelta_ += event->angleDelta().y();
  setEventPosition(event->position(), event);
  for (; wheelDelta_ >= 120; wheelDelta_ -= 120)
    interactor_->InvokeEvent(vtkCommand::MouseWheelForwardEvent, event);
  for (; wheelDelta_ <= -120; wheelDelta_ += 120)
    interactor_->InvokeEvent(vtkCommand::MouseWheelBackwardEvent, event);
  event->accept();
  requestRender();
}

void VtkWidget::enterEvent(QEnterEvent* event) {
  setEventPosition(event->position(), event);
  interactor_->InvokeEvent(vtkCommand::EnterEvent, event);
  requestRender();
}

void VtkWidget::leaveEvent(QEvent* event) {
  interactor_->InvokeEvent(vtkCommand::LeaveEvent, event);
  requestRender();
}

void VtkWidget::keyPressEvent(QKeyEvent* event) {
  const char ascii = setKeyInformation(interactor_, event);
  interactor_->InvokeEvent(vtkCommand::KeyPressEvent, event);
  // The interactor styles' shortcuts ('r' reset, 'w' wireframe...) listen to CharEvent.
  if (ascii) interactor_->InvokeEvent(vtkCommand::CharEvent, event);
  requestRender();
}

void VtkWidget::keyReleaseEvent(QKeyEvent* event) {
  setKeyInformation(interactor_, event);
  interactor_->InvokeEvent(vtkCommand::KeyReleaseEvent, event);
  requestRender();
}

QImage VtkWidget::imageAt(int width, int height) {
  if (width < 16 || height < 16 || width > kMaxWindowSide || height > kMaxWindowSide)
    throw std::invalid_argument("the view image must be 16..8192 pixels a side, got " + std::to_string(width) + "x" +
                                std::to_string(height));
  const QSize min = minimumSize(), max = maximumSize(), before = size();
  textScale_ = double(height) / std::max(1, before.height());
  drawingPicture_ = true;
  setFixedSize(width, height);  // the window grows or shrinks around it for this frame
  QCoreApplication::processEvents();
  const QImage image = grabFramebuffer();
  textScale_ = 1.0;
  setFixedSize(before);  // back at once, so the next picture starts from the view as it was
  QCoreApplication::processEvents();
  drawingPicture_ = false;
  setMinimumSize(min);
  setMaximumSize(max);
  if (image.isNull()) throw std::runtime_error("the view has no picture yet: the window is not on screen");
  return image.size() == QSize(width, height) ? image : image.scaled(width, height);
}

VtkWidget::Renderers VtkWidget::addRenderers() {
  vtkNew<render::SceneRenderer> renderer;
  renderer->GradientBackgroundOn();
  renderer->SetBackground(0.97, 0.97, 0.98);
  renderer->SetBackground2(0.80, 0.84, 0.90);
  renderWindow()->AddRenderer(renderer);
  // The colour bar has a strip of its own at the right, so it never covers the data.
  vtkNew<vtkRenderer> legend;
  legend->GradientBackgroundOn();
  legend->SetBackground(renderer->GetBackground());
  legend->SetBackground2(renderer->GetBackground2());
  legend->InteractiveOff();
  renderWindow()->AddRenderer(legend);
  // What the user grips is drawn over the scene (a layer of its own, its depth
  // cleared), so that no surface, slice or grip hides it: it sees through the
  // scene's camera and keeps to the scene's viewport.
  vtkNew<vtkRenderer> handles;
  handles->SetLayer(1);
  handles->InteractiveOff();
  handles->SetActiveCamera(renderer->GetActiveCamera());
  vtkNew<vtkCallbackCommand> follow;
  follow->SetClientData(renderer.GetPointer());
  follow->SetCallback([](vtkObject* caller, unsigned long, void* scene, void*) {
    static_cast<vtkRenderer*>(caller)->SetViewport(static_cast<vtkRenderer*>(scene)->GetViewport());
  });
  handles->AddObserver(vtkCommand::StartEvent, follow);
  renderWindow()->SetNumberOfLayers(2);
  renderWindow()->AddRenderer(handles);
  return {renderer, legend, handles};
}

}  // namespace linkscape::gui
