// The views of a multi-view input a frame job processes (declared in io/frame_job.h).
#include "io/frame_job.h"
#include "io/views.h"

#include <algorithm>

namespace obscura {

LayerPlan planViewLayers(const FrameJob& job, const ExrInfo& info, const std::string& view) {
    if (view.empty()) return planLayers(info, job.preset, job.layerOverrides);
    const FileView seen = viewOfFile(info, view);
    LayerPlan plan;
    try {
        plan = planLayers(seen.info, job.preset, job.layerOverrides);
    } catch (const Error& e) {  // a --layer this view lacks: said of the view
        throw FileError(info.path, "view '" + view + "': " + withoutFilePrefix(e.what(), info.path));
    }
    for (LayerBinding& b : plan.bindings)
        for (std::string& c : b.channels) c = seen.fileName(b.part, c);
    return plan;
}

std::vector<std::string> viewsToProcess(const FrameJob& job, const ExrInfo& info) {
    const std::vector<std::string> views = fileViews(info);
    std::vector<std::string> out;
    if (!job.views.empty()) {
        requireViews(info, job.views);
        for (const std::string& v : views)
            if (std::find(job.views.begin(), job.views.end(), v) != job.views.end()) out.push_back(v);
        return out;
    }
    for (const std::string& v : views) {
        try {
            const LayerPlan plan = planViewLayers(job, info, v);
            if (plan.find(Role::Depth) || plan.find(Role::Position)) out.push_back(v);
        } catch (const Error& e) {
            // A --layer override this view lacks. A view with no depth has nothing to run on
            // anyway; one with a depth would be left without its AO, so that is said.
            FrameJob plain = job;
            plain.layerOverrides.clear();
            const LayerPlan own = planViewLayers(plain, info, v);
            if (!own.find(Role::Depth) && !own.find(Role::Position)) continue;
            throw FileError(info.path, withoutFilePrefix(e.what(), info.path) +
                                           " (name the layer as this view spells it, or give --view for the others)");
        }
    }
    return out;
}

} // namespace obscura
