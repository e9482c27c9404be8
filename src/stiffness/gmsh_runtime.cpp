#include "gmsh_runtime.hpp"

#include <dlfcn.h>

#include <stdexcept>
#include <string>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::stiffness::gmshrt {
namespace {

Api load() {
  void* h = nullptr;
  for (const char* name : {"libgmsh.so.4.8", "libgmsh.so"})
    if ((h = ::dlopen(name, RTLD_NOW | RTLD_LOCAL))) break;
  if (!h)
    throw Error(ErrorKind::config, std::string("gmsh's library (libgmsh.so.4.8, Debian package libgmsh4.8) cannot be loaded: ") +
                                  ::dlerror() + "; the solid stiffness model needs it (scripts/install-deps.sh installs it)");
  auto sym = [h](auto& fn, const char* name) {
    fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(::dlsym(h, name));
    if (!fn) throw Error(ErrorKind::config, std::string("gmsh's library has no ") + name + ": not the gmsh 4.8 C API");
  };
  Api a{};
  sym(a.initialize, "gmshInitialize");
  sym(a.option_set_number, "gmshOptionSetNumber");
  sym(a.model_add, "gmshModelAdd");
  sym(a.model_remove, "gmshModelRemove");
  sym(a.get_bounding_box, "gmshModelGetBoundingBox");
  sym(a.occ_import_shapes, "gmshModelOccImportShapes");
  sym(a.occ_synchronize, "gmshModelOccSynchronize");
  sym(a.occ_translate, "gmshModelOccTranslate");
  sym(a.mesh_generate, "gmshModelMeshGenerate");
  sym(a.mesh_get_nodes, "gmshModelMeshGetNodes");
  sym(a.mesh_get_elements_by_type, "gmshModelMeshGetElementsByType");
  sym(a.mesh_get_element_properties, "gmshModelMeshGetElementProperties");
  sym(a.logger_get_last_error, "gmshLoggerGetLastError");
  sym(a.merge, "gmshMerge");
  sym(a.get_entities, "gmshModelGetEntities");
  sym(a.mesh_classify_surfaces, "gmshModelMeshClassifySurfaces");
  sym(a.mesh_create_geometry, "gmshModelMeshCreateGeometry");
  sym(a.geo_add_surface_loop, "gmshModelGeoAddSurfaceLoop");
  sym(a.geo_add_volume, "gmshModelGeoAddVolume");
  sym(a.geo_synchronize, "gmshModelGeoSynchronize");
  sym(a.occ_add_box, "gmshModelOccAddBox");
  sym(a.occ_fuse, "gmshModelOccFuse");
  sym(a.free, "gmshFree");
  return a;
}

}  // namespace

const Api& api() {
  static const Api a = load();  // thread-safe once; a failed load throws again next time
  return a;
}

void check(int ierr, const char* what) {
  if (ierr) throw std::runtime_error(what);
}

}  // namespace deflex::stiffness::gmshrt
