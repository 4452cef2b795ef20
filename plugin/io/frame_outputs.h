// What a frame job writes once the operator has run: the new layers (AO, and for ssdo DO, GI
// and relit) into the output file as --write asks, tagged, and the --preview PNG.
#pragma once
#include "io/frame_job.h"

#include <string>

namespace obscura {

// One view's passes (the whole frame's for a file without views) and what the operator made of them.
struct ViewResult {
    FramePasses passes;
    OperatorOutputs out;
};

// Adds the layers each view's outputs hold as the job asks and writes job.output (copy, new or
// append; a copy copies the first view's raw channels, which hold the whole file). A view of a
// part of its own (`view` attribute) writes there, or into a part of its own that carries the
// view; a view by channel names writes its channels named in the view (layer.view.channel).
// Fills report.aoChannel, written, writeDescription and the plan's colour note. `extra`: more new
// layers (deep elements' per-element AO), written with the first view's AO.
void writeFrameOutputs(const FrameJob& job, std::vector<ViewResult>& views, FrameReport& report,
                       std::vector<NewChannel> extra = {});

// --preview: the display window's part of the AO, or for ssdo of the relit layer when it is
// written, else of the DO layer, exposed and sRGB-encoded. Returns the report's plan line.
std::string writeFramePreview(const FrameJob& job, const FramePasses& p, const OperatorOutputs& out, bool ssdo);

} // namespace obscura
