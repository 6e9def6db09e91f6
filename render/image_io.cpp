#include "render/image_io.h"

#include <vtkErrorCode.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkRenderWindow.h>
#include <vtkWindowToImageFilter.h>

#include <stdexcept>

#include "core/atomic_file.h"

namespace linkscape::render {

void save_png(vtkRenderWindow* window, const std::filesystem::path& path) {
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->Update();
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    vtkNew<vtkPNGWriter> writer;
    writer->SetFileName(tmp.c_str());
    writer->SetInputConnection(grab->GetOutputPort());
    writer->Write();
    if (writer->GetErrorCode() != 0)
      throw std::runtime_error("cannot write PNG '" + path.string() + "': " +
                               vtkErrorCode::GetStringFromErrorCode(writer->GetErrorCode()));
  });
}

}  // namespace linkscape::render
