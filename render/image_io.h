// Saving what a VTK render window shows.
#pragma once

#include <filesystem>

class vtkRenderWindow;

namespace linkscape::render {

// Renders `window` and writes its colour buffer as PNG, atomically.
// Throws std::runtime_error if the file cannot be written.
void save_png(vtkRenderWindow* window, const std::filesystem::path& path);

}  // namespace linkscape::render
