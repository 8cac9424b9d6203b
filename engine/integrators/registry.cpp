// Maps the integrator names exposed in Blender (scene.smis.integrator) to their implementations.
#include <functional>
#include <map>
#include <stdexcept>

#include "integrators/integrator.h"
#include "integrators/path.h"

namespace smis {

std::unique_ptr<Integrator> make_integrator(const RenderSettings& settings) {
    static const std::map<std::string, std::function<std::unique_ptr<Integrator>()>> factories = {
        {"PATH", [] { return std::make_unique<PathIntegrator>(); }},
    };
    auto it = factories.find(settings.integrator);
    if (it == factories.end()) throw std::invalid_argument("unknown integrator '" + settings.integrator + "'");
    return it->second();
}

}  // namespace smis
