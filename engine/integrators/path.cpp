#include "integrators/path.h"

#include "integrators/path_tracing.h"
#include "integrators/volume.h"

namespace smis {

Color PathIntegrator::Li(const Scene& scene, const RenderSettings& settings, Ray ray, Sampler& sampler,
                         LocalCounters& counters) const {
    Rng& rng = sampler.rng();
    PathState camera = camera_path_state(ray.o);
    camera.first_vertex_ahead = true;
    camera.medium = scene.camera_medium();
    if (settings.camera_volume_only) {  // benchmarks: the camera ray's single scattering alone
        if (!scene.has_media()) return Color(0.0f);
        RayMedia media;
        SurfaceHit hit;
        intersect_through(scene, ray, camera.medium, &hit, &media);
        return single_scattering(scene, ray, media, rng, counters);
    }
    return trace_path(scene, settings, ray, camera, rng, counters, &sampler);
}

}  // namespace smis
