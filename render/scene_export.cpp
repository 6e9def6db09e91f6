#include "render/scene_export.h"

#include <vtkActor.h>
#include <vtkActorCollection.h>
#include <vtkGLTFExporter.h>
#include <vtkNew.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>

#include <fstream>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "core/atomic_file.h"

namespace linkscape::render {
namespace {

// Visible actors over every renderer of `window`: a scene without any has
// nothing to export.
int visible_actors(vtkRenderWindow* window) {
  int count = 0;
  vtkRendererCollection* renderers = window->GetRenderers();
  renderers->InitTraversal();
  while (vtkRenderer* renderer = renderers->GetNextItem()) {
    vtkActorCollection* actors = renderer->GetActors();
    actors->InitTraversal();
    while (vtkActor* actor = actors->GetNextActor()) count += actor->GetVisibility() ? 1 : 0;
  }
  return count;
}

// VTK writes every material opaque (glTF's default alphaMode): the view's
// translucent surfaces would hide the device in any viewer. Each material
// whose colour has alpha < 1 blends, and every material shows both faces
// (the slice is a single open sheet).
std::string blended(const std::string& gltf) {
  nlohmann::json scene = nlohmann::json::parse(gltf);
  for (nlohmann::json& material : scene["materials"]) {
    const nlohmann::json& pbr = material["pbrMetallicRoughness"];
    if (pbr.contains("baseColorFactor") && pbr["baseColorFactor"].size() == 4 &&
        pbr["baseColorFactor"][3].get<double>() < 1.0)
      material["alphaMode"] = "BLEND";
    material["doubleSided"] = true;
  }
  return scene.dump();
}

}  // namespace

void write_gltf(vtkRenderWindow* window, const std::filesystem::path& path) {
  if (path.extension() != ".gltf")
    throw std::invalid_argument("scene export writes glTF: the file must end in .gltf, got '" + path.string() + "'");
  if (!window || visible_actors(window) == 0)
    throw std::invalid_argument("scene export: the view draws nothing to export");
  vtkNew<vtkGLTFExporter> exporter;
  exporter->SetRenderWindow(window);
  exporter->InlineDataOn();  // one self-contained file
  exporter->SaveNormalOn();
  const std::string scene = blended(exporter->WriteToString());
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out.write(scene.data(), std::streamsize(scene.size())) || !out.flush())
      throw std::runtime_error("cannot write '" + path.string() + "'");
  });
}

}  // namespace linkscape::render
