#include "fuzz/mutate.h"

#include <algorithm>
#include <climits>
#include <cstdio>
#include <cstring>
#include <random>

namespace obscura::fuzz {
namespace {

std::int32_t get32(const Bytes& b, std::size_t at) {
    std::int32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;
}
void put32(Bytes& b, std::size_t at, std::int32_t v) {
    if (at + 4 <= b.size()) std::memcpy(b.data() + at, &v, 4);
}
void put64(Bytes& b, std::size_t at, std::uint64_t v) {
    if (at + 8 <= b.size()) std::memcpy(b.data() + at, &v, 8);
}

// a + d with two's-complement wrap-around, as the header's int32 fields hold it (no overflow).
std::int32_t wrapAdd(std::int32_t a, std::int64_t d) { return (std::int32_t)(std::uint32_t)((std::int64_t)a + d); }

// Reads a NUL-terminated string at `at`; false past the end.
bool readName(const Bytes& b, std::size_t& at, std::string& out) {
    out.clear();
    while (at < b.size() && b[at] != 0) out.push_back((char)b[at++]);
    if (at >= b.size()) return false;
    ++at;
    return true;
}

// Values that break window arithmetic in every way we know of.
std::int32_t nastyInt(std::mt19937_64& rng) {
    static const std::int32_t v[] = {0, 1, -1, 2, 7, 8, 15, 16, 255, 4096, 65535, 99999, 1 << 20, 1 << 30,
                                     INT_MAX, INT_MAX - 1, INT_MIN, INT_MIN + 1, -100000, -8};
    return rng() % 3 == 0 ? (std::int32_t)rng() : v[rng() % (sizeof v / sizeof *v)];
}

const Attribute* pick(const HeaderMap& h, std::mt19937_64& rng, const std::string& name) {
    std::vector<const Attribute*> hits;
    for (const Attribute& a : h.attributes)
        if (a.name == name) hits.push_back(&a);
    return hits.empty() ? nullptr : hits[rng() % hits.size()];
}

void editWindow(Bytes& b, const HeaderMap& h, std::mt19937_64& rng, std::string& what) {
    const Attribute* a = pick(h, rng, rng() % 3 ? "dataWindow" : "displayWindow");
    if (!a || a->size != 16) return;
    const std::size_t v = a->value;
    std::int32_t x0 = get32(b, v), y0 = get32(b, v + 4), x1 = get32(b, v + 8), y1 = get32(b, v + 12);
    switch (rng() % 6) {
    case 0: x1 = y1 = 99999; break;                                   // huge
    case 1: std::swap(x0, x1); break;                                 // inverted
    case 2: x0 = INT_MIN; x1 = INT_MAX; break;                        // width overflows
    case 3: x0 = wrapAdd(x0, (int)(rng() % 9) - 4); y1 = wrapAdd(y1, (int)(rng() % 9) - 4); break;  // off by a few
    case 4: x0 = wrapAdd(x0, 1 << 30); x1 = wrapAdd(x1, 1 << 30); break;  // far away
    default: (rng() % 2 ? x0 : y1) = nastyInt(rng); break;
    }
    put32(b, v, x0), put32(b, v + 4, y0), put32(b, v + 8, x1), put32(b, v + 12, y1);
    what += " " + a->name + "[" + std::to_string(a->part) + "]=" + std::to_string(x0) + "," + std::to_string(y0) +
            "," + std::to_string(x1) + "," + std::to_string(y1);
}

void editChannel(Bytes& b, const HeaderMap& h, std::mt19937_64& rng, std::string& what) {
    const Attribute* a = pick(h, rng, "channels");
    if (!a) return;
    // Entries: name\0, int32 type, uint8 pLinear, 3 reserved, int32 xSampling, int32 ySampling.
    std::vector<std::pair<std::string, std::size_t>> entries;
    std::size_t at = a->value;
    std::string name;
    while (at < a->value + a->size && readName(b, at, name) && !name.empty()) {
        entries.push_back({name, at});
        at += 16;
    }
    if (entries.empty()) return;
    const auto& [chName, f] = entries[rng() % entries.size()];
    switch (rng() % 5) {
    case 0: put32(b, f, (std::int32_t)(rng() % 5)); what += " type(" + chName + ")"; break;
    case 1: put32(b, f + 8, 2), put32(b, f + 12, 2); what += " sampling2(" + chName + ")"; break;
    case 2: put32(b, f + (rng() % 2 ? 8 : 12), 2); what += " sampling2x|y(" + chName + ")"; break;
    case 3: put32(b, f + 8 + 4 * (rng() % 2), nastyInt(rng)); what += " sampling?(" + chName + ")"; break;
    default: if (f + 4 < b.size()) b[f + 4] = (std::uint8_t)rng(); what += " pLinear(" + chName + ")"; break;
    }
}

void editByteAttr(Bytes& b, const HeaderMap& h, std::mt19937_64& rng, const char* name, std::string& what) {
    const Attribute* a = pick(h, rng, name);
    if (!a || a->size < 1) return;
    const std::uint8_t v = rng() % 4 ? (std::uint8_t)(rng() % 12) : (std::uint8_t)rng();
    b[a->value] = v;
    what += std::string(" ") + name + "=" + std::to_string(v);
}

void editChunkCount(Bytes& b, const HeaderMap& h, std::mt19937_64& rng, std::string& what) {
    const Attribute* a = pick(h, rng, "chunkCount");
    if (!a || a->size != 4) return;
    const std::int32_t v = rng() % 2 ? wrapAdd(get32(b, a->value), (int)(rng() % 5) - 2) : nastyInt(rng);
    put32(b, a->value, v);
    what += " chunkCount=" + std::to_string(v);
}

void editTiles(Bytes& b, const HeaderMap& h, std::mt19937_64& rng, std::string& what) {
    const Attribute* a = pick(h, rng, "tiles");
    if (!a || a->size != 9) return;
    if (rng() % 3 == 0) {
        b[a->value + 8] = (std::uint8_t)rng();
        what += " tileMode";
    } else {
        const std::int32_t v = nastyInt(rng);
        put32(b, a->value + 4 * (rng() % 2), v);
        what += " tileSize=" + std::to_string(v);
    }
}

void editOffsets(Bytes& b, const HeaderMap& h, std::mt19937_64& rng, std::string& what) {
    const std::size_t n = std::min<std::size_t>(64, (b.size() - std::min(b.size(), h.end)) / 8);
    if (n == 0) return;
    const std::size_t at = h.end + 8 * (rng() % n);
    std::uint64_t v;
    switch (rng() % 4) {
    case 0: v = 0; break;
    case 1: v = ~0ull >> (rng() % 40); break;
    case 2: v = b.size() - rng() % 16; break;
    default: v = h.end + rng() % (b.size() - h.end); break;
    }
    put64(b, at, v);
    what += " offset@" + std::to_string(at) + "=" + std::to_string(v);
}

void editAttrFrame(Bytes& b, const HeaderMap& h, std::mt19937_64& rng, std::string& what) {
    if (h.attributes.empty()) return;
    const Attribute& a = h.attributes[rng() % h.attributes.size()];
    if (rng() % 2) {
        const std::int32_t v = rng() % 2 ? (std::int32_t)a.size + (int)(rng() % 9) - 4 : nastyInt(rng);
        put32(b, a.sizeField, v);
        what += " size(" + a.name + ")=" + std::to_string(v);
    } else {
        b[a.sizeField - 2] ^= (std::uint8_t)(1u << (rng() % 8));  // last letter of the type name
        what += " typename(" + a.name + ")";
    }
}

void flipBits(Bytes& b, std::size_t lo, std::size_t hi, std::mt19937_64& rng, std::string& what) {
    if (hi <= lo) return;
    const int n = 1 + (int)(rng() % 8);
    for (int i = 0; i < n; ++i) b[lo + rng() % (hi - lo)] ^= (std::uint8_t)(1u << (rng() % 8));
    what += " flip" + std::to_string(n) + "[" + std::to_string(lo) + "," + std::to_string(hi) + ")";
}

} // namespace

HeaderMap parseHeaders(const Bytes& b) {
    HeaderMap h;
    if (b.size() < 8) return h;
    const bool multipart = (b[5] & 0x10) != 0;  // version flags bit 12
    std::size_t at = 8;
    for (int part = 0;; ++part) {
        if (multipart && at < b.size() && b[at] == 0) {  // end of the header list
            h.end = at + 1;
            break;
        }
        std::string name, type;
        for (;;) {
            if (!readName(b, at, name)) return h;
            if (name.empty()) break;
            if (!readName(b, at, type) || at + 4 > b.size()) return h;
            Attribute a{part, name, type, at + 4, (std::uint32_t)get32(b, at), at};
            if (a.value + a.size > b.size()) return h;
            h.attributes.push_back(a);
            at = a.value + a.size;
        }
        if (!multipart) {
            h.end = at;
            break;
        }
    }
    h.ok = true;
    return h;
}

Bytes mutateExr(const Bytes& seed, std::uint64_t index, std::string& what) {
    std::mt19937_64 rng(index * 0x9E3779B97F4A7C15ull + 12345);
    Bytes b = seed;
    const HeaderMap h = parseHeaders(b);
    const std::size_t headerEnd = h.ok ? h.end : std::min<std::size_t>(b.size(), 400);
    const int edits = rng() % 5 == 0 ? 2 + (int)(rng() % 2) : 1;
    for (int e = 0; e < edits; ++e) {
        switch (rng() % 11) {
        case 0: flipBits(b, 0, headerEnd, rng, what); break;
        case 1: flipBits(b, headerEnd, b.size(), rng, what); break;
        case 2: editWindow(b, h, rng, what); break;
        case 3: editChannel(b, h, rng, what); break;
        case 4: editByteAttr(b, h, rng, "compression", what); break;
        case 5: editChunkCount(b, h, rng, what); break;
        case 6: editTiles(b, h, rng, what); break;
        case 7: editOffsets(b, h, rng, what); break;
        case 8: editAttrFrame(b, h, rng, what); break;
        case 9: editByteAttr(b, h, rng, "lineOrder", what); break;
        default: {
            // Truncation: inside the header a third of the time, else anywhere.
            const std::size_t cut = rng() % 3 == 0 ? rng() % (headerEnd + 1) : rng() % b.size();
            b.resize(cut);
            what += " truncate@" + std::to_string(cut);
            e = edits;
            break;
        }
        }
    }
    if (what.empty()) flipBits(b, 0, b.size(), rng, what);
    return b;
}

bool extremePayload(Bytes& b, std::uint64_t index, std::string& what) {
    const HeaderMap h = parseHeaders(b);
    if (!h.ok || (b[5] & 0x1e) != 0) return false;  // tiled, long names, deep or multipart: not handled here
    const Attribute* compression = nullptr;
    const Attribute* channels = nullptr;
    const Attribute* dataWindow = nullptr;
    for (const Attribute& a : h.attributes) {
        if (a.name == "compression") compression = &a;
        if (a.name == "channels") channels = &a;
        if (a.name == "dataWindow") dataWindow = &a;
    }
    if (!compression || !channels || !dataWindow || b[compression->value] != 0) return false;
    for (std::size_t at = channels->value; at < channels->value + channels->size && b[at] != 0;) {
        std::string name;
        if (!readName(b, at, name) || get32(b, at) != 2 /* FLOAT */) return false;
        at += 16;
    }
    // One scanline per chunk: the offset table has one entry per line of the data window.
    const std::int32_t lines = get32(b, dataWindow->value + 12) - get32(b, dataWindow->value + 4) + 1;
    if (lines <= 0 || h.end + 8ull * lines > b.size()) return false;

    std::mt19937_64 rng(index * 0xA24BAED4963EE407ull + 99);
    static const std::uint32_t bits[] = {
        0x7fc00000u, 0xffc00000u, 0x7f800001u,  // NaNs (quiet, negative, signalling)
        0x7f800000u, 0xff800000u,               // +-infinity
        0x7f7fffffu, 0xff7fffffu,               // +-FLT_MAX
        0x00000001u, 0x80000001u, 0x00800000u,  // denormals, FLT_MIN
        0x80000000u, 0x00000000u,               // -0, 0
        0x70000000u, 0xbf800000u, 0xcb189680u,  // 1.6e29, -1, -1e7
    };
    const int n = 1 + (int)(rng() % 3);
    for (int k = 0; k < n; ++k) {
        const std::uint32_t v = bits[rng() % (sizeof bits / sizeof *bits)];
        std::uint64_t chunk;
        std::memcpy(&chunk, b.data() + h.end + 8 * (rng() % lines), 8);
        if (chunk + 8 > b.size()) return false;
        const std::int32_t size = get32(b, (std::size_t)chunk + 4);
        if (size < 4 || chunk + 8 + (std::uint64_t)size > b.size()) return false;
        const std::size_t values = (std::size_t)size / 4;
        // A few samples, or a run over a whole line of one channel.
        const std::size_t count = rng() % 2 ? 1 + rng() % 4 : values;
        const std::size_t first = rng() % values;
        for (std::size_t i = 0; i < count; ++i)
            std::memcpy(b.data() + chunk + 8 + 4 * ((first + i * (count == values ? 1 : 7)) % values), &v, 4);
        char hex[16];
        std::snprintf(hex, sizeof hex, "%08x", v);
        what += std::string(" payload@") + std::to_string(chunk) + "x" + std::to_string(count) + "=" + hex;
    }
    return true;
}

std::string mutateJson(const std::string& json, std::uint64_t index, std::string& what) {
    std::mt19937_64 rng(index * 0xD1B54A32D192ED03ull + 777);
    std::string s = json;
    switch (rng() % 6) {
    case 0: s.resize(rng() % s.size()); what = "json truncated"; break;
    case 1:
        for (int i = 0; i < 3; ++i) s[rng() % s.size()] ^= (char)(1u << (rng() % 7));
        what = "json bit flips";
        break;
    case 2: {  // a number becomes something else
        static const char* repl[] = {"1e400", "-1e400", "NaN", "null", "\"x\"", "[]", "{}", "0", "-3", "1e-320"};
        std::size_t pos = s.find_first_of("0123456789", rng() % s.size());
        if (pos == std::string::npos) pos = s.find_first_of("0123456789");
        const std::size_t end = s.find_first_of(",]}\n", pos);
        s.replace(pos, end - pos, repl[rng() % 10]);
        what = "json number replaced";
        break;
    }
    case 3: {  // a key renamed
        const std::size_t pos = s.find('"', rng() % s.size());
        if (pos != std::string::npos && pos + 1 < s.size()) s[pos + 1] = 'Q';
        what = "json key renamed";
        break;
    }
    case 4: s = rng() % 2 ? "" : "[1,2,3]"; what = "json replaced"; break;
    default: {  // a row of the matrix loses an element
        const std::size_t pos = s.find("camera_to_world");
        const std::size_t comma = pos == std::string::npos ? pos : s.find(',', pos + 20);
        if (comma != std::string::npos) s.erase(comma, s.find_first_of(",]", comma + 1) - comma);
        what = "json matrix row short";
        break;
    }
    }
    return s;
}

} // namespace obscura::fuzz
