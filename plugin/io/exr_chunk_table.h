// The chunk tables of an EXR file, checked entry by entry before its chunks are copied raw, and
// the copy: a part's compressed chunks as they are, never decoded or encoded again.
#pragma once
#include "io/exr_file.h"

#include <OpenEXR/ImfForward.h>

#include <string>

namespace obscura {

// Reads each part's chunk table (after the headers of `info`, read with allowDeep) and the
// leader of every chunk it names: an offset outside the file or inside the tables, a leader
// naming another part, line block or tile than the entry's, or data running past the end of
// the file -> FileError(path, "truncated or corrupt: the chunk table of part P: ..."). OpenEXR's
// C++ API would rebuild such a table by scanning the file, and a copy would carry chunks no
// table named; its core API (3.1) refuses valid files that mix deep and flat parts.
void checkChunkTables(const std::string& path, const ExrInfo& info);

// Part p of `in` into part p of `out`, chunk for chunk (every level of a mip-mapped part, deep
// parts too). `out`'s header for p must match the input's in what the chunks encode: data window,
// channels, compression, line order, tiles.
void copyPartChunks(Imf::MultiPartInputFile& in, Imf::MultiPartOutputFile& out, int p);

} // namespace obscura
