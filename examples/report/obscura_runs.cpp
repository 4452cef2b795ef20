#include "obscura_runs.h"

#include "base/error.h"
#include "timing.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <map>

namespace report {

LoadedFrame loadFrame(const std::string& exrPath, const std::string& referenceLayer, bool withBounce) {
    obscura::FrameJob job;
    job.input = exrPath;
    job.preset = "blender";
    job.referenceLayer = referenceLayer;
    if (withBounce) {  // the CLI's --method ssdo --bounce (--bounce-source direct-diffuse): DiffDir and DiffCol
        job.settings.method = "ssdo";
        job.writeIndirect = true;
    }
    LoadedFrame f;
    f.passes = obscura::loadFramePasses(job, {});
    if (withBounce) {
        if (f.passes.radiance.empty() || f.passes.albedo.empty())
            throw obscura::Error("'" + exrPath + "' has no DiffDir/DiffCol for the bounce");
    }
    f.camera = obscura::resolveFrameCamera(job, f.passes);
    f.skyDepth = f.passes.plan.skyDepth;
    const std::string sidecar = exrPath.substr(0, exrPath.size() - 4) + ".json";
    std::ifstream in(sidecar);
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_discarded() || !j.contains("ao_distance")) throw obscura::Error("no ao_distance in '" + sidecar + "'");
    f.radius = j["ao_distance"].get<double>();
    return f;
}

obscura::OperatorInputs operatorInputs(const LoadedFrame& f, bool withBounce, bool depthNormals) {
    obscura::OperatorInputs in;
    in.displayWindow = f.passes.display;
    in.dataWindow = f.passes.data;
    in.depth = f.passes.depth.view();
    in.normal = f.passes.normal.view();
    in.depthKind = f.passes.plan.depthKind;
    in.normalSpace = f.passes.plan.normalSpace;
    if (depthNormals) {
        in.normal = obscura::ConstPlane{};
        in.normalSpace = obscura::NormalSpace::Depth;
    }
    in.camera = f.camera;
    if (withBounce) {
        in.radiance = f.passes.radiance.view();
        in.albedo = f.passes.albedo.view();
    }
    return in;
}

TimedOperator timeOperator(const obscura::OperatorInputs& in, const obscura::Settings& s, int runs,
                           double budgetSeconds) {
    TimedOperator out;
    obscura::OperatorOutputs result = obscura::runOperator(in, s);  // warm-up: GL context, shader compile, caches
    std::vector<double> total;
    std::vector<std::string> order;
    std::map<std::string, std::vector<double>> stages;
    double spent = 0;
    for (int run = 0; run < std::max(1, runs) && (run == 0 || spent < budgetSeconds); ++run) {
        const Clock::time_point t0 = Clock::now();
        result = obscura::runOperator(in, s);
        total.push_back(secondsSince(t0));
        spent += total.back();
        for (const obscura::StageTiming& t : result.stats.timings) {
            if (!stages.count(t.name)) order.push_back(t.name);
            stages[t.name].push_back(t.seconds);
        }
    }
    out.runs = int(total.size());
    out.medianSeconds = median(total);
    for (const std::string& name : order) out.stageMedians.emplace_back(name, median(stages[name]));
    out.deviceDetail = result.stats.device;
    out.ao = std::move(result.ao);
    out.directional = std::move(result.directional);
    out.indirect = std::move(result.indirect);
    return out;
}

obscura::ErrorMetrics nonSkyError(const obscura::Image& ao, const obscura::Image& reference, const LoadedFrame& f) {
    const obscura::Image& depth = f.passes.depth;
    const float sky = f.skyDepth;
    return obscura::compareChannels(ao.view(), 0, reference.view(), 0, [&](int x, int y) {
        const float d = *depth.at(x, y);
        return d > 0.0f && d < sky;
    });
}

} // namespace report
