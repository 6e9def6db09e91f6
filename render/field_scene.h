// Fields shown in the linkage's 3-D renderer: a colour-mapped slice as a flat
// textured rectangle at its plane, the two workspace isosurfaces as
// translucent meshes, and a colour bar for the slice.
//
// Props are created once and added to a renderer once; new data only swaps
// the texture image, the plane's corners or a mesh, so updating at interactive
// rates never adds props. Coordinates are in the field's length unit.
#pragma once

#include <vtkNew.h>
#include <vtkSmartPointer.h>
#include <vtkWeakPointer.h>

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/field.h"
#include "render/colour_scale.h"
#include "render/slice_image.h"
#include "render/workspace_mesh.h"

class vtkActor;
class vtkImageData;
class vtkLookupTable;
class vtkPlaneSource;
class vtkPolyData;
class vtkRenderer;
class vtkScalarBarActor;
class vtkTextActor;
class vtkTexture;

namespace linkscape::render {

class FieldScene {
 public:
  FieldScene();
  ~FieldScene();
  FieldScene(const FieldScene&) = delete;
  FieldScene& operator=(const FieldScene&) = delete;

  // Adds every prop (slice plane, two surfaces, colour bar) to `renderer`
  // once, and turns on depth peeling there so the translucent surfaces
  // composite correctly with the opaque linkage. Depth peeling also needs a
  // render window with alpha bit planes and 0 multisamples (the window's
  // owner sets those). The colour bar goes to `legend` where given (a
  // renderer of its own beside the scene's, so it never covers the data),
  // else to `renderer`. Throws std::invalid_argument for a null renderer.
  void add_to(vtkRenderer* renderer, vtkRenderer* legend = nullptr);

  // Shows a one-sample-thick field as a rectangle at its plane, textured
  // exactly as render_slice_rgba(slice, style) (nearest-neighbour, unlit).
  // The rectangle spans the grid's cell edges along the two slice axes (first
  // axis = texture x, second = texture y). Throws std::invalid_argument as
  // render_slice_rgba (bad field or style, no axis with one sample); the
  // scene is unchanged then.
  void set_slice(const Field& slice, const SliceStyle& style);
  // Draws the next slice this far along its normal from where it was sampled
  // (0 by default): a planar device's slice, the same at every height, lies
  // just below its linkage rather than through it.
  void set_slice_offset(double along_normal) { slice_offset_ = along_normal; }
  void set_slice_visible(bool visible);
  // 0..1, default 1. Throws std::invalid_argument outside [0, 1].
  void set_slice_opacity(double opacity);

  // Shows an isosurface from extract_surface (smooth shading from its
  // "Normals"). The mesh is shallow-copied. nullptr or a mesh without cells
  // clears that surface and its light mesh.
  void set_surface(Surface which, vtkPolyData* mesh);
  // Smooths the full surfaces for display (windowed-sinc, volume-preserving,
  // `iterations` passes; 0: as extracted, the default). A surface sampled
  // on a grid shows the grid's facets and ripples; smoothing takes them off
  // the picture only: exports keep the extracted mesh. Applies from the
  // next set_surface.
  void set_surface_smoothing(int iterations);
  // The same surface with fewer triangles (extract_light_surface), drawn
  // instead of the full mesh while set_light(true); shallow-copied. Ignored
  // while the surface has no full mesh; nullptr clears it.
  void set_light_surface(Surface which, vtkPolyData* light);
  // While on, surfaces that have a light mesh draw it instead of the full one
  // (while the device is being moved: a software-rendered frame costs what
  // the surfaces' triangles cost). Default off.
  void set_light(bool on);
  // Whether the light mesh of `which` is what is drawn.
  bool drawing_light(Surface which) const;
  void set_surface_visible(Surface which, bool visible);
  // 0..1; defaults: Reach 0.15 (light grey-blue), WellConditioned 0.35
  // (green-teal). Throws std::invalid_argument outside [0, 1].
  void set_surface_opacity(Surface which, double opacity);

  // Colour bar for the slice at the right of the view: the style's colour
  // map over colour_range(), log10 for cond/residual on a log scale, with
  // the round ticks of colour_bar_ticks() (as the figures), titled by the
  // quantity and unit. Shown only while the slice is shown. Default on.
  void set_colour_bar_visible(bool visible);
  // Marks the ends of the colour bar beyond which the slice has values
  // drawn in the end colours (a robust automatic range clipped them): a
  // swatch with "clipped" past each such end. Taken at the next set_slice.
  void set_clipped_ends(bool low, bool high);
  // Pixel sizes (the colour bar's widest, the gap under its title) times
  // `scale`: a picture drawn larger than the screen keeps the bar's share.
  void set_pixel_scale(double scale);

  // Hides everything and drops all field data (visibility and opacity
  // settings are kept for the next data).
  void clear();

  // Introspection (mainly for tests). "Visible" means drawn: the user's flag
  // is on and there is data to draw.
  bool slice_visible() const;
  bool surface_visible(Surface which) const;
  std::size_t surface_faces(Surface which) const;
  bool colour_bar_visible() const;
  std::string colour_bar_title() const;
  // The bar's discrete entries (categorical fields: status and method by
  // name), empty for a continuous bar.
  std::vector<std::string> colour_bar_labels() const;
  // The ticks of a continuous bar.
  std::vector<double> colour_bar_ticks() const;
  std::array<bool, 2> clipped_ends() const { return {clip_low_, clip_high_}; }
  // The colour range the bar was last built for (the data's units, not log10), if any.
  std::optional<std::array<double, 2>> colour_bar_range() const { return bar_range_; }
  // The props a pick can land on: the slice and each full surface.
  vtkActor* slice_actor() const { return slice_actor_; }
  vtkActor* surface_actor(Surface which) const { return surface_actors_[index(which)]; }
  // World bounds of the slice rectangle (xmin, xmax, ymin, ymax, zmin, zmax);
  // all zero without a slice.
  std::array<double, 6> slice_bounds() const;

 private:
  static constexpr std::size_t kSurfaces = 2;
  static std::size_t index(Surface which);
  void update_visibility();
  void update_colour_bar(const Field& slice, const SliceStyle& resolved);
  void build_legend(const std::string& title, const std::vector<LegendEntry>& entries);

  // Slice: a textured plane.
  vtkNew<vtkPlaneSource> plane_;
  vtkNew<vtkTexture> texture_;
  vtkNew<vtkActor> slice_actor_;
  bool has_slice_ = false;
  double slice_offset_ = 0;
  bool slice_flag_ = true;

  // Isosurfaces: each actor draws its own copy (shallow) of the mesh; the
  // light actors share the full ones' property.
  std::array<vtkSmartPointer<vtkPolyData>, kSurfaces> meshes_, light_meshes_;
  std::array<vtkSmartPointer<vtkActor>, kSurfaces> surface_actors_, light_actors_;
  std::array<bool, kSurfaces> surface_flags_{true, true};
  bool light_ = false;
  int smoothing_ = 0;

  // Colour bar and the range it was last built for (rebuilt only on change).
  vtkSmartPointer<vtkLookupTable> lut_;
  vtkNew<vtkScalarBarActor> colour_bar_;
  bool colour_bar_flag_ = true;
  std::optional<std::array<double, 2>> bar_range_;
  bool bar_log_ = false, bar_categorical_ = false;
  bool clip_low_ = false, clip_high_ = false;
  std::array<bool, 2> clip_shown_{false, false};
  std::vector<vtkSmartPointer<vtkTextActor>> legend_entries_;  // a categorical legend, title first
  vtkWeakPointer<vtkRenderer> legend_renderer_;  // the marks the bar was last built with
  std::string bar_title_, bar_map_;
};

}  // namespace linkscape::render
