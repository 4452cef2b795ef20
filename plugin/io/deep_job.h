// Deep elements as a frame job's input (docs/deep.md): one or more deep EXRs with no flat file.
// Their merge gives the passes (the flattened image, the nearest surface's depth, normals from
// it) and HBAO's deep layers; with --per-element-ao, each element's own surface gets an AO too.
#pragma once
#include "core/methods.h"
#include "io/frame_job.h"

#include <string>
#include <vector>

namespace obscura {

// What the merge gives a frame job beyond its passes.
struct DeepElementsInput {
    Image layers;                      // the merge's surfaces: HBAO's deep input
    Image colour;                      // their colours, for the bounce (readsDeepColour)
    std::vector<std::string> names;    // per element: its AO layer's suffix (elementLayerNames)
    std::vector<Image> front, elementLayers;  // per element, with --per-element-ao
};

// Why --per-element-ao (Python: per_element_ao) cannot run with the job's settings, or "": it needs
// HBAO's deep layers (a method that reads them, falloff none).
std::string perElementAoProblem(const FrameJob& job, Spelling spelling);

// The job's deep elements: job.deepElements, else the input alone when its first part is deep
// and no --flat file is given; empty for a flat input. `input`: the input's headers, read by the
// caller whenever job.deepElements is empty.
std::vector<std::string> deepElementsOf(const FrameJob& job, const ExrInfo* input);

// Reads and merges the elements. The passes describe a flat image of one part: the flattened
// channels and the depth (FramePasses::carried, written before the new layers), the first
// element's attributes (camera, colour). Errors name the file: windows or cameras that differ
// from the first element's, a file with no Z. The merge's surfaces (HBAO's deep layers) are built
// when the job reads them (readsDeepLayers), or always with `allLayers` (--inspect describes them).
FramePasses loadDeepElements(const FrameJob& job, const std::vector<std::string>& paths, DeepElementsInput& deep,
                             FrameReport& report, bool allLayers = false);

// The passes a run of `job` computes on, without writing or keeping raw channels: for deep
// elements (deepElementsOf) their merge, whose layers and counts go to `deep` and `report`; else
// the flat input's, as loadFramePasses reads them. What --inspect describes. `input`: the input's
// headers (read with deep parts allowed), where the caller has read them; else they are read here.
FramePasses loadPassesForInspection(const FrameJob& job, DeepElementsInput& deep, FrameReport& report,
                                    const ExrInfo* input = nullptr);

// --per-element-ao: the AO of each element's visible surface, with every element as occluders,
// named <ao layer>.<element name> (e.g. obscura.AO.balls.Y).
std::vector<NewChannel> elementAoLayers(const FrameJob& job, const OperatorInputs& in, const Settings& settings,
                                        const DeepElementsInput& deep, FrameReport& report);

// Each file's stem less a trailing frame number (".0001", "_0001"), other characters than
// letters, digits, '_' and '-' made '_', made unique with "_2", "_3"...
std::vector<std::string> elementLayerNames(const std::vector<std::string>& paths);

} // namespace obscura
