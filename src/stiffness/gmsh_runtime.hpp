// gmsh, loaded when the solid model first meshes (dlopen of its C API).
// Linking libgmsh would load ~60 libraries (FLTK, X11, OpenGL, image codecs)
// at the start of every deflex run, ~0.1 s even for `deflex path`; only
// `--method solid` needs it.
#pragma once
#include <gmshc.h>

namespace deflex::stiffness::gmshrt {

struct Api {
  decltype(&gmshInitialize) initialize;
  decltype(&gmshOptionSetNumber) option_set_number;
  decltype(&gmshModelAdd) model_add;
  decltype(&gmshModelRemove) model_remove;
  decltype(&gmshModelGetBoundingBox) get_bounding_box;
  decltype(&gmshModelOccImportShapes) occ_import_shapes;
  decltype(&gmshModelOccSynchronize) occ_synchronize;
  decltype(&gmshModelOccTranslate) occ_translate;
  decltype(&gmshModelMeshGenerate) mesh_generate;
  decltype(&gmshModelMeshGetNodes) mesh_get_nodes;
  decltype(&gmshModelMeshGetElementsByType) mesh_get_elements_by_type;
  decltype(&gmshModelMeshGetElementProperties) mesh_get_element_properties;
  decltype(&gmshLoggerGetLastError) logger_get_last_error;
  // A closed STL as a volume (the workpiece model, solid_mesh.cpp: mesh_stl).
  decltype(&gmshMerge) merge;
  decltype(&gmshModelGetEntities) get_entities;
  decltype(&gmshModelMeshClassifySurfaces) mesh_classify_surfaces;
  decltype(&gmshModelMeshCreateGeometry) mesh_create_geometry;
  decltype(&gmshModelGeoAddSurfaceLoop) geo_add_surface_loop;
  decltype(&gmshModelGeoAddVolume) geo_add_volume;
  decltype(&gmshModelGeoSynchronize) geo_synchronize;
  // A solid as a union of boxes (a staged workpiece, solid_mesh.cpp: mesh_boxes).
  decltype(&gmshModelOccAddBox) occ_add_box;
  decltype(&gmshModelOccFuse) occ_fuse;
  decltype(&gmshFree) free;
};

// Loads libgmsh once; throws deflex::Error(ErrorKind::config) naming the library
// and the Debian package when it cannot be loaded.
const Api& api();

// Throws std::runtime_error(what) when a gmsh C call reported an error.
void check(int ierr, const char* what);

}  // namespace deflex::stiffness::gmshrt
