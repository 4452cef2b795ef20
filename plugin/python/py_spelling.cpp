#include "python/py_spelling.h"

#include "core/devices.h"
#include "core/methods.h"
#include "core/settings_schema.h"
#include "io/frame_job.h"
#include "io/layers.h"
#include "python/py_args.h"

#include <algorithm>
#include <cctype>
#include <optional>
#include <regex>
#include <vector>

namespace obscura::python {
namespace {

struct Keyword {
    std::string key;
    bool isSwitch = false;  // set with True, not a value
};

bool among(const std::string& word, std::initializer_list<const char*> words) {
    return std::any_of(words.begin(), words.end(), [&](const char* w) { return word == w; });
}

// The keyword a flag (without its dashes) is offered as, from the tables every host reads;
// nullopt for the CLI's own (frames, resume, flat: Python takes those as arguments or not at all).
std::optional<Keyword> keywordOf(const std::string& flag) {
    if (among(flag, {"flat", "frames", "resume", "keep-going", "help", "json"})) return std::nullopt;
    const std::string dashed = "--" + flag;
    for (const MethodParam* p : allMethodParams())
        if (dashed == p->flag) return Keyword{p->key, p->value == nullptr};
    for (const MethodOption& o : methodOptions())
        if (dashed == o.flag) return Keyword{o.key, among(o.key, {"bounce", "times_albedo", "relit_direct"})};
    for (const NumberSetting& s : numberSettings())
        if (dashed == s.flag) return Keyword{s.key};
    for (const NameListSetting& s : nameListSettings())
        if (dashed == s.flag) return Keyword{s.key};
    std::string key = flag;
    std::replace(key.begin(), key.end(), '-', '_');
    return Keyword{key, among(key, {"in_place", "per_element_ao"})};
}

// Whether `word` is one of the values keyword `key` takes by name ("depth" takes "inverse").
bool isChoice(const std::string& key, const std::string& word) {
    const auto in = [&](const std::vector<std::string>& words) {
        return std::find(words.begin(), words.end(), word) != words.end();
    };
    Weighting weighting;
    Falloff falloff;
    DepthEncoding encoding;
    NormalSpace normals;
    WriteMode write;
    if (key == "method") return findMethod(word) != nullptr;
    if (key == "weighting") return parse(word, weighting);
    if (key == "falloff") return parse(word, falloff);
    if (key == "depth") return parse(word, encoding);
    if (key == "normals") return parse(word, normals);
    if (key == "write") return parse(word, write);
    if (key == "device") return isDeviceName(word);
    if (key == "preset") return in(presetNames());
    if (key == "quality") {
        const std::vector<QualityPreset>& levels = qualityPresets();
        return std::any_of(levels.begin(), levels.end(), [&](const QualityPreset& q) { return word == q.name; });
    }
    if (key == "bad_pixels") return in(kBadPixelsWords);
    if (key == "bounce_source") return among(word, {"beauty", "direct-diffuse"});
    if (key == "out_type") return in(kOutTypeWords);
    if (key == "up") return in(kUpWords);
    for (const MethodParam* p : allMethodParams())
        if (key == p->key) return findNamed(*p, word) != nullptr;
    return false;
}

// A flag's value as the keyword's: ROLE=NAME a dict, A,B,... a tuple, a choice a string. `rest`
// is the text after the flag; `taken` how much of it the value used.
std::string keywordValue(const Keyword& k, const std::string& rest, size_t& taken) {
    // A layer's name is the placeholder NAME, or the user's (spaces, dots, dashes: "View
    // Layer.Depth", "BG-plate"), which runs to what ends the clause: a colon, semicolon, comma or
    // bracket, or a full stop ending the text.
    static const std::regex rolePair(R"(^ ([a-z][a-z-]*)=(NAME\b|[^:;,()]*[^:;,().\s]))");
    static const std::regex tuple(R"(^ ((?:[A-Z]+|[-0-9.e+]+)(?:,(?:[A-Z]+|[-0-9.e+]+))+))");
    static const std::regex word(R"(^ ([a-z][a-z0-9-]*))");
    static const std::regex number(R"(^ (-?[0-9][0-9.e+-]*)\b)");
    std::smatch m;
    taken = 0;
    if ((k.key == "layer" || k.key == "out_layer") && std::regex_search(rest, m, rolePair)) {
        taken = m.length(0);
        const std::string name = m.str(2) == "NAME" ? "NAME" : "'" + m.str(2) + "'";
        return "={'" + m.str(1) + "': " + name + "}";
    }
    if (std::regex_search(rest, m, tuple)) {
        taken = m.length(0);
        std::string items = m.str(1);
        for (size_t c = items.find(','); c != std::string::npos; c = items.find(',', c + 2)) items.insert(c + 1, " ");
        return "=(" + items + ")";
    }
    if (std::regex_search(rest, m, word) && isChoice(k.key, m.str(1))) {
        taken = m.length(0);
        return "='" + m.str(1) + "'";
    }
    if (!k.isSwitch && std::regex_search(rest, m, number)) {
        taken = m.length(0);
        return "=" + m.str(1);
    }
    return k.isSwitch ? "=True" : "";
}

// Whether position i lies inside a quoted span: a path, a layer or a value the message quotes
// ('shots --radius 2/x.exr'), or a library's text quotes ("..."). A quote opens after a space, a
// bracket, '=' or the start (not the apostrophe of "input's") and closes before a space, a
// punctuation mark or the end.
std::vector<bool> quotedSpans(const std::string& s) {
    std::vector<bool> inside(s.size(), false);
    auto word = [](char c) { return std::isalnum((unsigned char)c) != 0; };
    for (size_t i = 0; i < s.size(); ++i) {
        const char q = s[i];
        if ((q != '\'' && q != '"') || (i > 0 && word(s[i - 1]))) continue;
        size_t close = i + 1;
        while (close < s.size() && !(s[close] == q && (close + 1 == s.size() || !word(s[close + 1])))) ++close;
        if (close >= s.size()) break;
        std::fill(inside.begin() + (long)i, inside.begin() + (long)close + 1, true);
        i = close;
    }
    return inside;
}

} // namespace

std::string keywordSpelling(const std::string& message) {
    // A flag starts the message or follows a space, a comma or a bracket, or a slash right after
    // another flag (--fov-deg/--ortho-width): a path's "/--dir/" stays as it is, and so does
    // anything the message quotes.
    static const std::regex flag(R"((^|[\s(,/])--([a-z][a-z0-9-]*))");
    const std::vector<bool> quoted = quotedSpans(message);
    std::string out;
    size_t at = 0;
    for (std::sregex_iterator it(message.begin(), message.end(), flag), end; it != end; ++it) {
        const std::smatch& m = *it;
        const size_t start = m.position(0) + m.length(1);
        if (start < at || quoted[start]) continue;  // inside a value already rewritten, or quoted
        if (m.str(1) == "/" && (size_t)m.position(0) != at) continue;
        out += message.substr(at, start - at);
        at = m.position(0) + m.length(0);
        if (m.str(2) == "inspect") {
            out += "obscura.inspect()";
            continue;
        }
        const std::optional<Keyword> k = keywordOf(m.str(2));
        if (!k) {
            out += m.str(0).substr(m.length(1));
            continue;
        }
        size_t taken = 0;
        out += k->key + keywordValue(*k, message.substr(at), taken);
        at += taken;
    }
    return out + message.substr(at);
}

} // namespace obscura::python
