#pragma once
// The CPU images the GL tests compare the preview with (exact VPL renders, references, single scattering), rendered
// once per test run. Kept in the process; and, when the environment variable VPLAB_TEST_IMAGE_CACHE names a folder
// (scripts/test.sh makes one for each run of the suite), on disk for the run's other processes: CTest runs each test
// in a process of its own, the OSMesa twin of an EGL test asks for the same images, and the sanitized build asks for
// the Release build's. The CPU renders are deterministic at any thread count, so a cached image is the one the process
// would have rendered itself; under the sanitizers the CPU code keeps its own tests (docs/benchmarks.md, "The test
// suite in CI").

#include <functional>
#include <string>

#include "renderer/image/image.h"
#include "renderer/settings.h"

namespace vplab {
class OfflineScene;
struct Scene;
struct VplSet;
}  // namespace vplab

namespace vplab::test {

/// A digest of everything a CPU render of `scene` with `settings` (and the VPLs, when given) depends on: the geometry,
/// materials, lights, media and camera, every setting, every VPL and VRL. Two inputs that render differently differ.
std::string renderInputs(const Scene& scene, const Settings& settings, const VplSet* vpls = nullptr);

/// The image `render` gives for `what` (the method, the component, the sampler: what renderInputs() does not say) on
/// those inputs, rendered the first time any process of the run asks for it. Processes asking at once wait for the
/// one that renders (a lock file beside the image). A cached file that cannot be read is rendered again.
const Image& cachedCpu(const std::string& what, const std::string& inputs, const std::function<Image()>& render);

/// The disk half of cachedCpu(): the image stored under `key` in `folder`, or `render`'s, stored there first.
Image imageInFolder(const std::string& folder, const std::string& key, const std::function<Image()>& render);

/// renderVpl(l, vpls, method, settings).image, cached.
const Image& cachedVplRender(const OfflineScene& l, const VplSet& vpls, Method method, const Settings& settings);
/// renderReference(l, settings).image, cached.
const Image& cachedReference(const OfflineScene& l, const Settings& settings);

}  // namespace vplab::test
