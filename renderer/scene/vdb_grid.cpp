#include "renderer/scene/vdb_grid.h"

#include <dlfcn.h>

#include <mutex>

#include "renderer/vdb/vdb_reader.h"

namespace vplab {

namespace {

/// The OpenVDB reader, opened on the first .vdb file rather than linked: libopenvdb's symbol bindings would cost
/// every process about 20-50 ms at start (docs/benchmarks.md, "The cold headless preview").
ReadVdbDenseFunction reader() {
  static std::once_flag once;
  static ReadVdbDenseFunction function = nullptr;
  static std::string problem;
  std::call_once(once, [] {
    void* module = dlopen(VPLAB_VDB_MODULE, RTLD_NOW | RTLD_LOCAL);
    if (!module) {
      const char* why = dlerror();
      problem = std::string("cannot open the OpenVDB reader " VPLAB_VDB_MODULE " (") + (why ? why : "?") + ")";
      return;
    }
    function = reinterpret_cast<ReadVdbDenseFunction>(dlsym(module, kReadVdbDenseSymbol));
    if (!function) problem = std::string("no ") + kReadVdbDenseSymbol + " in " VPLAB_VDB_MODULE;
  });
  if (!function) throw VdbError(problem);
  return function;
}

}  // namespace

std::shared_ptr<const DensityGrid> readVdbDensity(const std::string& path, const std::string& gridName) {
  VdbDense dense;
  reader()(path, gridName, dense);
  auto out = std::make_shared<DensityGrid>(DensityGrid::fromDense(dense.first, dense.size, dense.values));
  out->source = path;
  out->gridName = gridName;
  out->activeVoxels = dense.activeVoxels;
  // Over the active values (inactive voxels inside the box are 0 but not part of the grid).
  out->minValue = dense.minValue;
  out->maxValue = dense.maxValue;
  out->localFromIndex = dense.localFromIndex;
  return out;
}

}  // namespace vplab
