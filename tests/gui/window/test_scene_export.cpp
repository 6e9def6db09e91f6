// File > Export scene (glTF): the view's meshes written as glTF 2.0 and read
// back with VTK's glTF reader — as many meshes as the view draws, where the
// view draws them; a wrong extension is refused and nothing is written.
#include <QTemporaryDir>
#include <QtTest>
#include <vtkActor.h>
#include <vtkPropCollection.h>
#include <vtkBoundingBox.h>
#include <vtkCompositeDataIterator.h>
#include <vtkDataSet.h>
#include <vtkGLTFReader.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkMapper.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>
#include <vtkSmartPointer.h>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/preset.h"
#include "gui/window/mechanism_window.h"
#include "gui/window/vtk_widget.h"
#include "render/scene_export.h"

using namespace linkscape;
using linkscape::gui::MechanismWindow;

class SceneExportTest : public QObject {
  Q_OBJECT
 private slots:
  void theViewsMeshesReadBackWhereTheViewDrawsThem() {
    MechanismWindow w(load_preset("parallel-12r"));
    w.resize(1000, 700);
    w.show();
    QVERIFY(QTest::qWaitForWindowExposed(&w));
    QVERIFY(QTest::qWaitFor([&] { return w.fieldsSettled(); }, 30000));
    vtkRenderWindow* window = w.view()->renderWindow();

    // What the view draws: its visible actors with data, and their bounds.
    // The renderer's own props, not GetActors(): that also lists the parts
    // of composite props (a hidden 3-D label's quad, never laid out).
    int drawn = 0;
    vtkBoundingBox view_bounds;
    vtkRendererCollection* renderers = window->GetRenderers();
    renderers->InitTraversal();
    while (vtkRenderer* r = renderers->GetNextItem()) {
      vtkPropCollection* props = r->GetViewProps();
      props->InitTraversal();
      while (vtkProp* prop = props->GetNextProp())
        if (auto* a = vtkActor::SafeDownCast(prop); a && a->GetVisibility() && a->GetMapper() && a->GetMapper()->GetInput() &&
            a->GetMapper()->GetInput()->GetNumberOfCells() > 0) {
          ++drawn;
          view_bounds.AddBounds(a->GetBounds());
        }
    }
    QVERIFY(drawn >= 3);  // at least the links, the slice and a surface

    QTemporaryDir dir;
    const std::filesystem::path path = (dir.path() + "/scene.gltf").toStdString();
    render::write_gltf(window, path);
    vtkNew<vtkGLTFReader> reader;
    reader->SetFileName(path.c_str());
    reader->Update();
    vtkMultiBlockDataSet* scene = reader->GetOutput();
    QVERIFY(scene);
    int meshes = 0;
    vtkBoundingBox read_bounds;
    vtkSmartPointer<vtkCompositeDataIterator> it;
    it.TakeReference(scene->NewIterator());
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
      if (auto* data = vtkDataSet::SafeDownCast(it->GetCurrentDataObject()); data && data->GetNumberOfCells() > 0) {
        ++meshes;
        read_bounds.AddBounds(data->GetBounds());
      }
    // Colours travel as materials: each link's and surface's colour, and the
    // colour-mapped slice as an image texture.
    std::ifstream file(path);
    const nlohmann::json gltf = nlohmann::json::parse(file);
    QCOMPARE(gltf.at("materials").size(), gltf.at("meshes").size());
    int textured = 0, translucent = 0;
    for (const auto& material : gltf.at("materials")) {
      const auto& pbr = material.at("pbrMetallicRoughness");
      textured += pbr.contains("baseColorTexture") ? 1 : 0;
      // A translucent surface blends in a viewer too (glTF's default is opaque).
      if (pbr.at("baseColorFactor").at(3).get<double>() < 1) {
        ++translucent;
        QCOMPARE(material.value("alphaMode", std::string("OPAQUE")), std::string("BLEND"));
      }
    }
    QVERIFY(textured >= 1);
    QVERIFY(translucent >= 1);  // the 12R's workspace surfaces
    QVERIFY(gltf.at("images").size() >= 1);
    QVERIFY2(meshes >= 3, qPrintable(QString("%1 meshes read back, %2 drawn").arg(meshes).arg(drawn)));
    // The scene spans the view's own extent (to 1 % of its size).
    const double tolerance = 0.01 * view_bounds.GetDiagonalLength();
    for (int i = 0; i < 6; ++i)
      QVERIFY2(std::abs(read_bounds.GetBound(i) - view_bounds.GetBound(i)) < tolerance,
               qPrintable(QString("bound %1: %2 read, %3 drawn").arg(i).arg(read_bounds.GetBound(i)).arg(view_bounds.GetBound(i))));

    QVERIFY_THROWS_EXCEPTION(std::invalid_argument, render::write_gltf(window, (dir.path() + "/scene.obj").toStdString()));
    QVERIFY(!std::filesystem::exists((dir.path() + "/scene.obj").toStdString()));
  }
};

QTEST_MAIN(SceneExportTest)
#include "test_scene_export.moc"
