#include "methods.h"

#include "reference/integrators.h"

namespace report {

bool parseDefinition(const std::string& name, AoDefinition& out) {
    for (int layer = 0; layer < reference::kAoLayers; ++layer) {
        const std::string layerName = reference::kAoLayerNames[layer];  // "AO_cosine_none"
        if (layerName != "AO_" + name) continue;
        const size_t underscore = name.find('_');
        out.name = name;
        out.referenceLayer = layer;
        return obscura::parse(name.substr(0, underscore), out.weighting) &&
               obscura::parse(name.substr(underscore + 1), out.falloff);
    }
    return false;
}

} // namespace report
