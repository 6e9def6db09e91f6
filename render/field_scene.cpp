#include "render/field_scene.h"

#include <vtkActor.h>
#include <vtkDoubleArray.h>
#include <vtkAlgorithm.h>
#include <vtkCoordinate.h>
#include <vtkImageData.h>
#include <vtkLookupTable.h>
#include <vtkPlaneSource.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataNormals.h>
#include <vtkWindowedSincPolyDataFilter.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkTextProperty.h>
#include <vtkTextActor.h>
#include <vtkTexture.h>
#include <vtkVariant.h>

#include <algorithm>
#include <stdexcept>

#include "render/colour_scale.h"

namespace linkscape::render {
namespace {

void check_opacity(const char* what, double opacity) {
  if (!(opacity >= 0 && opacity <= 1))
    throw std::invalid_argument(std::string(what) + ": expected an opacity in [0, 1], got " +
                                std::to_string(opacity));
}

// The colour bar's title: the quantity, with the length unit where it has one.
}  // namespace

FieldScene::FieldScene() {
  // Slice: one quad whose texture coordinates run 0..1 from the origin
  // corner along Point1 (first slice axis) and Point2 (second).
  plane_->SetResolution(1, 1);
  plane_->SetOutputPointsPrecision(vtkAlgorithm::DOUBLE_PRECISION);  // corners exactly at the cell edges
  vtkNew<vtkPolyDataMapper> plane_mapper;
  plane_mapper->SetInputConnection(plane_->GetOutputPort());
  plane_mapper->ScalarVisibilityOff();
  texture_->InterpolateOff();  // crisp samples
  texture_->MipmapOff();
  texture_->SetWrap(vtkTexture::ClampToEdge);  // no wrapped texels on the far edges
  slice_actor_->SetMapper(plane_mapper);
  slice_actor_->SetTexture(texture_);
  // Unlit and white, so the texture's colours reach the screen unchanged and
  // match the colour bar.
  vtkProperty* sp = slice_actor_->GetProperty();
  sp->SetColor(1, 1, 1);
  sp->SetAmbient(1);
  sp->SetDiffuse(0);
  sp->SetSpecular(0);
  sp->LightingOff();
  sp->BackfaceCullingOff();
  slice_actor_->VisibilityOff();

  // Isosurfaces: translucent, smooth-shaded from the mesh's point normals.
  const std::array<std::array<double, 3>, kSurfaces> colours = {{{0.72, 0.78, 0.90}, {0.15, 0.68, 0.58}}};
  const std::array<double, kSurfaces> opacities = {0.10, 0.22};
  for (std::size_t k = 0; k < kSurfaces; ++k) {
    meshes_[k] = vtkSmartPointer<vtkPolyData>::New();
    light_meshes_[k] = vtkSmartPointer<vtkPolyData>::New();
    vtkNew<vtkPolyDataMapper> mapper, light_mapper;
    mapper->SetInputData(meshes_[k]);
    mapper->ScalarVisibilityOff();
    light_mapper->SetInputData(light_meshes_[k]);
    light_mapper->ScalarVisibilityOff();
    surface_actors_[k] = vtkSmartPointer<vtkActor>::New();
    surface_actors_[k]->SetMapper(mapper);
    light_actors_[k] = vtkSmartPointer<vtkActor>::New();
    light_actors_[k]->SetMapper(light_mapper);
    light_actors_[k]->SetProperty(surface_actors_[k]->GetProperty());
    light_actors_[k]->PickableOff();
    light_actors_[k]->VisibilityOff();
    vtkProperty* p = surface_actors_[k]->GetProperty();
    p->SetColor(colours[k][0], colours[k][1], colours[k][2]);
    p->SetOpacity(opacities[k]);
    p->SetInterpolationToGouraud();
    p->BackfaceCullingOn();
    p->SetSpecular(0.1);
    p->SetSpecularPower(20);
    surface_actors_[k]->VisibilityOff();
  }

  // Colour bar: vertical, at the right edge of the viewport.
  lut_ = colour_lookup_table("viridis", 256);
  bar_map_ = "viridis";
  colour_bar_->SetLookupTable(lut_);
  colour_bar_->SetOrientationToVertical();
  colour_bar_->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  colour_bar_->SetPosition(0.89, 0.10);
  colour_bar_->SetWidth(0.10);
  colour_bar_->SetHeight(0.80);
  set_pixel_scale(1.0);
  colour_bar_->SetLabelFormat("%g");
  colour_bar_->SetUseCustomLabels(true);
  colour_bar_->SetBarRatio(0.3);
  colour_bar_->UnconstrainedFontSizeOn();
  for (vtkTextProperty* t : {colour_bar_->GetTitleTextProperty(), colour_bar_->GetLabelTextProperty()}) {
    t->SetColor(0.15, 0.15, 0.2);
    t->ShadowOff();
    t->ItalicOff();
    t->SetFontSize(14);
  }
  colour_bar_->GetTitleTextProperty()->BoldOn();
  colour_bar_->PickableOff();
  colour_bar_->VisibilityOff();
}

FieldScene::~FieldScene() = default;

std::size_t FieldScene::index(Surface which) {
  switch (which) {
    case Surface::Reach: return 0;
    case Surface::WellConditioned: return 1;
    case Surface::Threshold: break;  // exported, never shown in the scene
  }
  throw std::invalid_argument("field scene: unknown surface " + std::to_string(int(which)));
}

void FieldScene::add_to(vtkRenderer* renderer, vtkRenderer* legend) {
  if (!renderer) throw std::invalid_argument("field scene: expected a renderer, got null");
  // AddViewProp ignores props already present, so this is idempotent.
  // Translucent props blend in the order they were added (where depth peeling
  // is off): the slice, then the inner surface, then the outer one.
  renderer->AddViewProp(slice_actor_);
  for (Surface s : {Surface::WellConditioned, Surface::Reach}) {
    renderer->AddViewProp(surface_actors_[index(s)]);
    renderer->AddViewProp(light_actors_[index(s)]);
  }
  if (legend) {
    // The whole legend viewport is the bar's.
    colour_bar_->SetPosition(0.08, 0.06);
    colour_bar_->SetWidth(0.9);
    colour_bar_->SetHeight(0.86);
    colour_bar_->SetBarRatio(0.28);
    legend->AddViewProp(colour_bar_);
    legend_renderer_ = legend;
  } else {
    renderer->AddViewProp(colour_bar_);
    legend_renderer_ = renderer;
  }
  // Order-independent transparency for the translucent surfaces against the
  // opaque linkage and slice. Needs a render window with AlphaBitPlanes on
  // and MultiSamples 0 (set by whoever owns the window); otherwise VTK falls
  // back to sorted alpha blending.
  renderer->SetUseDepthPeeling(1);
  renderer->SetMaximumNumberOfPeels(4);
  renderer->SetOcclusionRatio(0.1);
}

void FieldScene::set_slice(const Field& slice, const SliceStyle& style) {
  // Everything that can throw comes first, so a bad call leaves the scene as it was.
  const SliceStyle resolved = resolved_style(slice, style);
  vtkSmartPointer<vtkImageData> image = render_slice_rgba(slice, resolved);
  const Grid& g = slice.grid;
  const Axis normal = slice_normal(g);
  const auto [au, av] = Grid::slice_axes(normal);
  const int n = int(normal), u = int(au), v = int(av);

  // Cell edges along u and v; the sample plane along the normal.
  Eigen::Vector3d origin = g.origin;
  origin(n) += 0.5 * g.spacing(n) + slice_offset_;
  Eigen::Vector3d p1 = origin, p2 = origin;
  p1(u) += g.dims[u] * g.spacing(u);
  p2(v) += g.dims[v] * g.spacing(v);
  plane_->SetOrigin(origin.data());
  plane_->SetPoint1(p1.data());
  plane_->SetPoint2(p2.data());

  texture_->SetInputData(image);
  has_slice_ = true;
  update_colour_bar(slice, resolved);
  update_visibility();
}

void FieldScene::update_colour_bar(const Field& slice, const SliceStyle& resolved) {
  const std::array<double, 2> range = {*resolved.min, *resolved.max};
  const bool log = uses_log_scale(resolved);
  const std::string title = field_title(slice, resolved.field);
  const std::vector<LegendEntry> legend = categorical_legend(slice, resolved);
  const bool categorical = !legend.empty();
  if (!categorical && !bar_categorical_ && bar_range_ && *bar_range_ == range && bar_log_ == log &&
      bar_title_ == title && bar_map_ == resolved.colour_map && clip_shown_ == std::array<bool, 2>{clip_low_, clip_high_})
    return;
  // A fresh table: no annotations or indexed lookup left from a categorical bar.
  lut_->DeepCopy(colour_lookup_table(resolved.colour_map, 256));
  bar_map_ = resolved.colour_map;
  colour_bar_->SetDrawBelowRangeSwatch(false);
  colour_bar_->SetDrawAboveRangeSwatch(false);
  if (categorical) {
    // One swatch per code, named.
    lut_->IndexedLookupOn();
    lut_->SetNumberOfTableValues(vtkIdType(legend.size()));
    for (std::size_t k = 0; k < legend.size(); ++k) {
      lut_->SetTableValue(vtkIdType(k), legend[k].rgb[0], legend[k].rgb[1], legend[k].rgb[2], 1.0);
      lut_->SetAnnotation(vtkVariant(legend[k].value), legend[k].label);
    }
    build_legend(title, legend);
  } else {
    colour_bar_->DrawAnnotationsOff();  // the strip has no room left of the bar; the title says what is clipped
    // The table's own range and scale make the bar's colours and tick labels
    // match normalised_value(): log10 spacing for cond and residual.
    if (log) lut_->SetScaleToLog10();
    else lut_->SetScaleToLinear();
    lut_->SetTableRange(range[0], range[1]);
    vtkNew<vtkDoubleArray> ticks;
    const std::vector<double> values =
        is_integer(resolved.field) ? integer_ticks(range[0], range[1]) : render::colour_bar_ticks(range[0], range[1], log);
    for (double t : values) ticks->InsertNextValue(t);
    colour_bar_->SetUseCustomLabels(true);
    colour_bar_->SetCustomLabels(ticks);
    // Values beyond a clipped end are drawn in the end colour: say so past that end.
    const auto low = colour_of(0, bar_map_), high = colour_of(1, bar_map_);
    lut_->SetBelowRangeColor(low[0], low[1], low[2], 1);
    lut_->SetAboveRangeColor(high[0], high[1], high[2], 1);
    lut_->SetUseBelowRangeColor(clip_low_);
    lut_->SetUseAboveRangeColor(clip_high_);
    colour_bar_->SetDrawBelowRangeSwatch(clip_low_);
    colour_bar_->SetDrawAboveRangeSwatch(clip_high_);
  }
  clip_shown_ = {clip_low_, clip_high_};
  // Long titles ("isotropic force (N)") put their unit on a second line,
  // within the bar's narrow strip at the view's edge.
  std::string shown = title;
  if (const auto unit = shown.rfind(" ("); shown.size() > 12 && unit != std::string::npos) shown[unit] = '\n';
  if (!categorical && (clip_low_ || clip_high_))
    shown += clip_low_ && clip_high_ ? "\nends clipped" : clip_high_ ? "\ntop clipped" : "\nbottom clipped";
  colour_bar_->SetTitle(shown.c_str());
  colour_bar_->Modified();
  bar_range_ = range;
  bar_log_ = log;
  bar_title_ = title;
  bar_categorical_ = categorical;
}

// A categorical legend: the title, then one name per code on its colour,
// stacked down the legend's strip (a scalar bar puts its names outside it).
void FieldScene::build_legend(const std::string& title, const std::vector<LegendEntry>& entries) {
  for (auto& a : legend_entries_)
    if (legend_renderer_) legend_renderer_->RemoveViewProp(a);
  legend_entries_.clear();
  auto add = [&](const std::string& text, const std::array<double, 3>* rgb, int row) {
    auto a = vtkSmartPointer<vtkTextActor>::New();
    a->SetInput(text.c_str());
    vtkTextProperty* t = a->GetTextProperty();
    t->SetFontSize(13);
    t->SetBold(rgb == nullptr);
    const bool dark = rgb && 0.3 * (*rgb)[0] + 0.59 * (*rgb)[1] + 0.11 * (*rgb)[2] < 0.5;
    t->SetColor(dark ? 1.0 : 0.1, dark ? 1.0 : 0.1, dark ? 1.0 : 0.15);
    if (rgb) {
      t->SetBackgroundColor((*rgb)[0], (*rgb)[1], (*rgb)[2]);
      t->SetBackgroundOpacity(1.0);
    }
    a->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    a->SetPosition(0.04, 0.92 - 0.05 * row);
    a->PickableOff();
    if (legend_renderer_) legend_renderer_->AddViewProp(a);
    legend_entries_.push_back(a);
  };
  add(title, nullptr, 0);
  for (std::size_t k = 0; k < entries.size(); ++k) add(" " + entries[k].label + " ", &entries[k].rgb, int(k) + 1);
}

void FieldScene::set_clipped_ends(bool low, bool high) {
  clip_low_ = low;
  clip_high_ = high;
}

std::vector<std::string> FieldScene::colour_bar_labels() const {
  std::vector<std::string> out;
  if (!bar_categorical_) return out;
  for (vtkIdType k = 0; k < lut_->GetNumberOfAnnotatedValues(); ++k) out.push_back(lut_->GetAnnotation(k));
  return out;
}

std::vector<double> FieldScene::colour_bar_ticks() const {
  std::vector<double> out;
  if (bar_categorical_ || !colour_bar_->GetCustomLabels()) return out;
  vtkDoubleArray* t = colour_bar_->GetCustomLabels();
  for (vtkIdType k = 0; k < t->GetNumberOfTuples(); ++k) out.push_back(t->GetValue(k));
  return out;
}

void FieldScene::set_slice_visible(bool visible) {
  slice_flag_ = visible;
  update_visibility();
}

void FieldScene::set_slice_opacity(double opacity) {
  check_opacity("slice", opacity);
  slice_actor_->GetProperty()->SetOpacity(opacity);
}

namespace {

// Shallow-copies `mesh` into `into` (cleared for null or no cells).
void take_mesh(vtkPolyData* into, vtkPolyData* mesh) {
  if (mesh && mesh->GetNumberOfCells() > 0) {
    into->ShallowCopy(mesh);
    // extract_surface marks "Normals" active; accept a mesh where it is not.
    vtkPointData* pd = into->GetPointData();
    if (!pd->GetNormals()) {
      vtkDataArray* normals = pd->GetArray("Normals");
      if (normals && normals->GetNumberOfComponents() == 3) pd->SetNormals(normals);
    }
  } else {
    into->Initialize();
  }
  into->Modified();
}

}  // namespace

void FieldScene::set_surface_smoothing(int iterations) {
  if (iterations < 0 || iterations > 200)
    throw std::invalid_argument("field scene: expected 0..200 smoothing iterations, got " + std::to_string(iterations));
  smoothing_ = iterations;
}

void FieldScene::set_surface(Surface which, vtkPolyData* mesh) {
  const std::size_t k = index(which);
  vtkSmartPointer<vtkPolyData> shown = mesh;
  if (smoothing_ > 0 && mesh && mesh->GetNumberOfCells() > 0) {
    vtkNew<vtkWindowedSincPolyDataFilter> smooth;
    smooth->SetInputData(mesh);
    smooth->SetNumberOfIterations(smoothing_);
    smooth->SetPassBand(0.1);
    smooth->BoundarySmoothingOff();  // the box's cut edges stay where they are
    smooth->NonManifoldSmoothingOn();
    smooth->NormalizeCoordinatesOn();
    vtkNew<vtkPolyDataNormals> normals;  // shading from the smoothed shape
    normals->SetInputConnection(smooth->GetOutputPort());
    normals->SplittingOff();
    normals->Update();
    shown = normals->GetOutput();
  }
  take_mesh(meshes_[k], shown);
  take_mesh(light_meshes_[k], nullptr);
  update_visibility();
}

void FieldScene::set_light_surface(Surface which, vtkPolyData* light) {
  const std::size_t k = index(which);
  take_mesh(light_meshes_[k], meshes_[k]->GetNumberOfCells() > 0 ? light : nullptr);
  update_visibility();
}

void FieldScene::set_light(bool on) {
  light_ = on;
  update_visibility();
}

bool FieldScene::drawing_light(Surface which) const {
  return light_ && surface_visible(which) && light_meshes_[index(which)]->GetNumberOfCells() > 0;
}

void FieldScene::set_surface_visible(Surface which, bool visible) {
  surface_flags_[index(which)] = visible;
  update_visibility();
}

void FieldScene::set_surface_opacity(Surface which, double opacity) {
  const std::size_t k = index(which);
  check_opacity(to_string(which).c_str(), opacity);
  surface_actors_[k]->GetProperty()->SetOpacity(opacity);
}

void FieldScene::set_colour_bar_visible(bool visible) {
  colour_bar_flag_ = visible;
  update_visibility();
}

void FieldScene::clear() {
  has_slice_ = false;
  texture_->SetInputData(nullptr);
  for (auto* meshes : {&meshes_, &light_meshes_})
    for (auto& m : *meshes) {
      m->Initialize();
      m->Modified();
    }
  update_visibility();
}

void FieldScene::update_visibility() {
  slice_actor_->SetVisibility(slice_visible());
  for (Surface s : {Surface::Reach, Surface::WellConditioned}) {
    const bool light = drawing_light(s);
    surface_actors_[index(s)]->SetVisibility(surface_visible(s) && !light);
    light_actors_[index(s)]->SetVisibility(light);
  }
  colour_bar_->SetVisibility(colour_bar_visible() && !bar_categorical_);
  for (auto& a : legend_entries_) a->SetVisibility(colour_bar_visible() && bar_categorical_);
}

bool FieldScene::slice_visible() const { return slice_flag_ && has_slice_; }

bool FieldScene::surface_visible(Surface which) const {
  return surface_flags_[index(which)] && surface_faces(which) > 0;
}

std::size_t FieldScene::surface_faces(Surface which) const {
  return std::size_t(meshes_[index(which)]->GetNumberOfCells());
}

void FieldScene::set_pixel_scale(double scale) {
  colour_bar_->SetMaximumWidthInPixels(int(std::lround(110 * scale)));
  colour_bar_->SetVerticalTitleSeparation(int(std::lround(10 * scale)));  // between the title and the top label
}

bool FieldScene::colour_bar_visible() const { return colour_bar_flag_ && slice_visible(); }

std::string FieldScene::colour_bar_title() const { return has_slice_ ? bar_title_ : std::string(); }

std::array<double, 6> FieldScene::slice_bounds() const {
  std::array<double, 6> b{};
  if (!has_slice_) return b;
  const double* actor = slice_actor_->GetBounds();  // world bounds: the actor has no transform
  std::copy(actor, actor + 6, b.begin());
  return b;
}

}  // namespace linkscape::render
