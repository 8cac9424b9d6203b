#include "integrators/path.h"

#include "integrators/path_tracing.h"

namespace smis {

Color PathIntegrator::Li(const Scene& scene, const RenderSettings& settings, Ray ray, Rng& rng,
                         LocalCounters& counters) const {
    PathState camera;
    camera.prev_p = ray.o;
    camera.first_vertex_ahead = true;
    return trace_path(scene, settings, ray, camera, rng, counters);
}

}  // namespace smis
