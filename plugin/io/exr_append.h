// --write append: a frame at the cost of reading it. Every part of the input is copied as the
// compressed chunks it holds (OpenEXR's raw chunk copy, as `exrmultipart -combine` does: no
// decode, no encode, every attribute kept), and the new layers go in one part of their own.
#pragma once
#include "core/operator.h"
#include "io/exr_file.h"

#include <string>
#include <vector>

namespace obscura {

// Writes outPath: every part of the file `input` describes (read with allowDeep) copied chunk
// for chunk, an unnamed single part named "render" as a multipart file requires, then the one
// parts of `layers` (layersOnlyFile of the input, or parts addLayersPart added to it), each named
// its own name, or "obscura" when it has none, made unique in the input (layersPartName), holding
// `add` and `attrs` (part indices of `layers`). The new parts take the input's first part's display window,
// pixel aspect ratio, time code and chromaticities: OpenEXR allows one value of each per file.
// Checks the chunk tables first: a corrupt input leaves nothing written. Adds the stages
// "copy" (the check and the chunks) and "append" (headers, the new part, closing) to *stages.
void writeAppended(const std::string& outPath, const ExrInfo& input, const ExrPixels& layers,
                   const std::vector<NewChannel>& add, const std::vector<StringAttribute>& attrs,
                   bool allowOverwriteInput, std::vector<StageTiming>* stages = nullptr);

} // namespace obscura
