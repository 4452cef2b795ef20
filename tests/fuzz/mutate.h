// Deterministic mutants of an EXR file's bytes: bit flips, truncations and in-place edits of
// header attributes (windows, channels, compression, chunk counts, tiles) and offset tables.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace obscura::fuzz {

using Bytes = std::vector<std::uint8_t>;

// One attribute of a header, as found in the file.
struct Attribute {
    int part = 0;
    std::string name, type;
    std::size_t value = 0;   // offset of the value
    std::uint32_t size = 0;  // value size in bytes
    std::size_t sizeField = 0;
};

struct HeaderMap {
    std::vector<Attribute> attributes;
    std::size_t end = 0;  // first byte after the header(s): the offset table
    bool ok = false;      // parsed to the end
};
HeaderMap parseHeaders(const Bytes& file);

// A mutant of `seed` (an EXR file) numbered `index`; `what` says what was done.
Bytes mutateExr(const Bytes& seed, std::uint64_t index, std::string& what);
// Extreme pixel values (NaN, infinities, FLT_MAX, denormals, negative zero, huge and negative
// numbers) written over the pixel data of an uncompressed single-part scanline file of 32-bit
// floats; the file's structure stays valid. Returns false (and leaves `seed` alone) for any
// other file.
bool extremePayload(Bytes& file, std::uint64_t index, std::string& what);
// A mutant of a JSON camera sidecar.
std::string mutateJson(const std::string& json, std::uint64_t index, std::string& what);

} // namespace obscura::fuzz
