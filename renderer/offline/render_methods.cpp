#include "renderer/offline/render_methods.h"

#include <cassert>
#include <utility>

#include "renderer/offline/lightcuts_renderer.h"
#include "renderer/offline/lvl_renderer.h"
#include "renderer/offline/mrcs_renderer.h"
#include "renderer/offline/path_tracer.h"
#include "renderer/offline/vrl_renderer.h"

namespace vplab {

namespace {

template <Method M>
VplRenderResult renderWithVpls(const OfflineScene& offline, const VplSet& vpls, const Settings& settings,
                               RenderControl* control, OnPass onPass) {
  return renderVpl(offline, vpls, M, settings, control, std::move(onPass));
}

VplRenderResult renderReferenceMethod(const OfflineScene& offline, const VplSet&, const Settings& settings,
                                      RenderControl* control, OnPass onPass) {
  VplRenderResult r;
  static_cast<ProgressiveResult&>(r) = renderReference(offline, settings, control, std::move(onPass));
  return r;
}

VplRenderResult renderVrlMethod(const OfflineScene& offline, const VplSet& vpls, const Settings& settings,
                                RenderControl* control, OnPass onPass) {
  return renderVrl(offline, vpls, settings, control, std::move(onPass));
}

VplRenderResult renderVblMethod(const OfflineScene& offline, const VplSet&, const Settings& settings,
                                RenderControl* control, OnPass onPass) {
  return renderVbl(offline, settings, control, std::move(onPass));
}

VplRenderResult renderLvlMethod(const OfflineScene& offline, const VplSet& vpls, const Settings& settings,
                                RenderControl* control, OnPass onPass) {
  return renderLvl(offline, vpls, settings, control, std::move(onPass));
}

template <Method M>
VplRenderResult renderLightcutsMethod(const OfflineScene& offline, const VplSet& vpls, const Settings& settings,
                                      RenderControl* control, OnPass onPass) {
  return renderLightcuts(offline, vpls, M, settings, control, std::move(onPass));
}

VplRenderResult renderMrcsMethod(const OfflineScene& offline, const VplSet& vpls, const Settings& settings,
                                 RenderControl* control, OnPass onPass) {
  return renderMrcs(offline, vpls, settings, control, std::move(onPass));
}

}  // namespace

const std::vector<RenderMethod>& renderMethods() {
  static const std::vector<RenderMethod> methods = {
      {Method::Reference, "path-traced reference", "Kajiya 1986; Veach 1997 (MIS)",
       "unidirectional path tracing with next-event estimation: the ground truth", false, false, false,
       renderReferenceMethod},
      {Method::Vpl, "VPLs, bound b", "Keller 1997",
       "every VPL with exact visibility and G_b = min(G, b): splotches without a bound, darkening with one", true, true,
       false, renderWithVpls<Method::Vpl>},
      {Method::VplKK, "VPLs + Kollig-Keller", "Kollig & Keller 2004; Raab et al. 2008 in media",
       "the bound's residual path-traced back, recursively: unbiased, at a path tracer's cost", true, true, false,
       renderWithVpls<Method::VplKK>},
      {Method::Vsl, "virtual spherical lights", "Hasan et al. 2009",
       "each VPL's flux spread over a sphere of radius r: no splotches, blurred sharp indirect light", true, false,
       false, renderWithVpls<Method::Vsl>},
      {Method::VplAbc, "VPLs + approximate compensation", "Engelhardt et al. 2012",
       "one residual bounce in media, locally homogeneous, no local visibility: most of the energy, no recursion", true,
       true, true, renderWithVpls<Method::VplAbc>},
      {Method::Vrl, "virtual ray lights", "Novak et al. 2012a",
       "the light paths' media segments light the media: no clamp, weak singularities, unbiased", true, false, true,
       renderVrlMethod},
      {Method::Vbl, "progressive virtual beam lights", "Novak et al. 2012b",
       "VRLs thickened to beams that shrink pass after pass: smooth first, converging to the reference", false, false,
       true, renderVblMethod},
      {Method::Lvl, "global + local virtual lights", "Davidovic et al. 2010",
       "bounded VPLs plus local lights per pixel tile carrying the residual: Kollig-Keller's vertices shared by a tile",
       true, true, false, renderLvlMethod},
      {Method::Lightcuts, "lightcuts", "Walter et al. 2005",
       "vpl's bounded sum through a cut of a light tree, refined until each node's error bound is under "
       "--lightcut-error of the estimate: sublinear in the VPLs",
       true, true, false, renderLightcutsMethod<Method::Lightcuts>},
      {Method::LightcutsKK, "lightcuts + Kollig-Keller", "Walter et al. 2005; Kollig & Keller 2004",
       "the lightcut sum plus vpl-kk's exact compensation of the residual (not accelerated)", true, true, false,
       renderLightcutsMethod<Method::LightcutsKK>},
      {Method::Mrcs, "matrix row-column sampling", "Hasan et al. 2007",
       "vpl's bounded sum over one representative per VPL cluster, the clusters from --mrcs-rows pixels rendered "
       "against every VPL: VPLs that light none of those pixels are lost",
       true, true, false, renderMrcsMethod},
  };
  return methods;
}

const RenderMethod& renderMethod(Method id) {
  for (const RenderMethod& m : renderMethods())
    if (m.id == id) return m;
  assert(false && "every Method has a row");
  return renderMethods().front();
}

std::string renderMethodNames(bool withReference) {
  std::string names;
  for (const RenderMethod& m : renderMethods()) {
    if (m.id == Method::Reference && !withReference) continue;
    names += (names.empty() ? "" : "|") + std::string(toString(m.id));
  }
  return names;
}

}  // namespace vplab
