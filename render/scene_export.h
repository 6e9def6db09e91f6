// The view's 3-D scene as glTF 2.0, for presentations (Blender, three.js,
// slide tools with 3-D models): the meshes the view draws — the linkage, the
// slice, the workspace surfaces — with their colours, in the device's length
// unit. Text, colour bars and handles are not part of it (glTF holds meshes).
#pragma once

#include <filesystem>

class vtkRenderWindow;

namespace linkscape::render {

// One .gltf file with its buffers inline, written atomically. Throws
// std::invalid_argument for a path not ending in .gltf or a window that draws
// no mesh, std::runtime_error when it cannot be written.
void write_gltf(vtkRenderWindow* window, const std::filesystem::path& path);

}  // namespace linkscape::render
