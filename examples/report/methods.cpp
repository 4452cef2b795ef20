#include "methods.h"

#include "core/methods.h"
#include "reference/integrators.h"

#include <algorithm>

namespace report {

const std::vector<std::string>& registeredMethods() {
    static const std::vector<std::string> variants = [] {
        std::vector<std::string> v;
        for (const obscura::MethodInfo& m : obscura::methods()) {
            if (obscura::methodOutputs(m.name, "do")) continue;  // SSDO's variants below
            v.push_back(m.name);
            if (std::string(m.name) == "hbao")
                v.insert(v.end(), {"hbao+horizon", "hbao+open", "hbao+clamp", "hbao+deep", "hbao+bounce",
                                        "hbao+deep+bounce"});
            if (std::string(m.name) == "rtao") v.insert(v.end(), {"rtao+sheet", "rtao+thick"});
            // Disc AO with one of its corrections switched (docs/discs.md).
            if (std::string(m.name) == "discs") v.insert(v.end(), {"discs+vis", "discs-blend", "discs-nopoly", "discs-sum"});
        }
        v.insert(v.end(), {"ssdo", "ssdo+bounce", "ssdo-noint"});
        return v;
    }();
    return variants;
}

std::string operatorMethod(const std::string& method) {
    if (isSsdoMethod(method)) return "ssdo";
    if (method.rfind("discs", 0) == 0) return "discs";  // discs+vis, discs-blend, discs-nopoly, discs-sum
    return method.substr(0, method.find('+'));
}

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

bool isSsdoMethod(const std::string& method) { return method == "ssdo" || method == "ssdo+bounce" || method == "ssdo-noint"; }

bool hasBounce(const std::string& method) {
    const std::string suffix = "+bounce";
    if (method.size() > suffix.size() && method.compare(method.size() - suffix.size(), suffix.size(), suffix) == 0)
        return true;  // "ssdo+bounce", or another method's bounce variant ("hbao+bounce")
    // A method of the table whose only business is GI (an AO method that can also bounce needs a variant).
    return !isSsdoMethod(method) && obscura::methodOutputs(method, "gi") && !obscura::methodOutputs(method, "ao");
}

bool hasDirectional(const std::string& method) { return obscura::methodOutputs(operatorMethod(method), "do"); }

bool isLit(const std::string& method) { return hasBounce(method) || hasDirectional(method); }

bool usesDeep(const std::string& method) { return method == "hbao+deep" || method == "hbao+deep+bounce"; }

bool anyMethod(const std::vector<std::string>& methods, bool (*test)(const std::string&)) {
    return std::any_of(methods.begin(), methods.end(), test);
}

int ssdoSamplesForPreset(const std::string& preset) {
    obscura::Settings s;
    s.method = "ssdo";
    return obscura::applyQualityPreset(preset, s) ? s.ssdoSamples : 0;
}

void configureMethod(const std::string& method, const std::string& preset, obscura::Settings& s) {
    if (!isSsdoMethod(method)) {
        s.method = operatorMethod(method);
        obscura::applyQualityPreset(preset, s);
        if (method == "rtao+thick") s.thickness = 0.2f * s.radius;
        if (method == "rtao+sheet") s.thickness = 0.0f;
        if (method == "hbao+horizon") {
            s.thickness = obscura::kThicknessInfinite;
            s.border = obscura::kBorderOpen;
        }
        if (method == "hbao+open") s.border = obscura::kBorderOpen;
        if (method == "hbao+clamp") s.border = obscura::kBorderClamp;
        if (method == "discs+vis") s.discsPasses = 2;
        if (method == "discs-blend") s.discsBlendLevels = true;
        if (method == "discs-nopoly") s.discsNoPolygon = true;
        if (method == "discs-sum") s.discsSum = true;
        s.bounce = hasBounce(method);
        return;
    }
    s.method = "ssdo";
    obscura::applyQualityPreset(preset, s);
    s.interleave = method == "ssdo-noint" ? 1 : 2;
    s.blur = 0;  // 0 = the operator's automatic blur, as wide as the interleaving block (none for interleave 1)
    s.bounce = hasBounce(method);
}

AoDefinition definitionFor(const std::string& method, const AoDefinition& chosen) {
    if (!isSsdoMethod(method)) return chosen;
    AoDefinition d;
    parseDefinition("cosine_linear", d);
    return d;
}

} // namespace report
