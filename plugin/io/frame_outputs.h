// What a frame job writes once the operator has run: the new layers (AO, and for ssdo DO, GI
// and relit) into the output file as --write asks, tagged, and the --preview PNG.
#pragma once
#include "io/frame_job.h"

#include <string>

namespace obscura {

// Adds the layers `out` holds as the job asks and writes job.output (copy, new or append);
// fills report.written, writeDescription and the plan's colour note. `extra`: more new layers
// (deep elements' per-element AO), written as the AO is.
void writeFrameOutputs(const FrameJob& job, FramePasses& p, const OperatorOutputs& out, FrameReport& report,
                       std::vector<NewChannel> extra = {});

// --preview: the display window's part of the AO, or for ssdo of the relit layer when it is
// written, else of the DO layer, exposed and sRGB-encoded. Returns the report's plan line.
std::string writeFramePreview(const FrameJob& job, const FramePasses& p, const OperatorOutputs& out, bool ssdo);

} // namespace obscura
