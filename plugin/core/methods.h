// The occlusion methods, registered once. The operator dispatches through this table, and
// the hosts build their method choices, method flags, OFX parameters and Python keywords
// from it, so adding a method touches no `if (method == ...)` chain.
#pragma once
#include "settings.h"

#include <string>
#include <vector>

namespace obscura {

struct OperatorInputs;
struct OperatorOutputs;
struct MethodRun;

// A word a numeric parameter also accepts ("auto", "inf"), its value, and the finite number
// that stands for it where a host stores plain numbers (OFX).
struct NamedValue {
    const char* word;
    double value;
    double hostValue;
};

// A method's own numeric or switch parameter, with the range every host enforces. A
// parameter that several methods share is listed under the first of them only.
struct MethodParam {
    const char* key;     // Python keyword and OFX parameter name ("ssao_samples")
    const char* flag;    // CLI flag ("--ssao-samples")
    const char* value;   // CLI value placeholder ("N"); nullptr: a switch, no value
    const char* help;
    double min, max;     // inclusive; ignored for switches
    int Settings::*intField = nullptr;      // exactly one of the three is set
    float Settings::*floatField = nullptr;
    bool Settings::*boolField = nullptr;
    std::vector<NamedValue> named = {};     // words it accepts besides numbers in [min, max]
    std::vector<const char*> alsoFor = {};  // other methods that read it (listed under this one only)
    bool ofx = true;                        // false: it sets an input OpenFX clips cannot carry (deep samples)
};

// What a quality level sets for this method (applied with every other method's levels,
// each to its own fields; the hosts apply it under the flags or keywords given).
struct MethodPreset {
    const char* quality;   // "low", "medium", "high", "ultra"
    const char* summary;   // for --help: "8 samples"
    void (*apply)(Settings&);
};

struct MethodInfo {
    const char* name;
    const char* description;            // one line
    const char* kernels;                // the kernels/ files (or CPU code) that compute it
    bool cpu, gl;                       // devices it runs on
    std::vector<const char*> reads;     // passes: "depth", "normal", "beauty", ...; "deep": deep layers if given
    std::vector<const char*> outputs;   // "ao", "do", "gi", "relit"
    std::vector<MethodPreset> presets;
    std::vector<MethodParam> params;
    // Samples (or rays) per pixel at these settings: the cost reports divide by.
    int (*samplesPerPixel)(const Settings&);
    // Texels a method reads beyond the screen cap (maxRadiusPixels) of a pixel, past the 2 every
    // method's texel snapping takes: what a host rendering tiles adds to its apron (nullptr: 0).
    int (*extraApron)(const Settings&);
    // Fills `out` (out.ao is preallocated to 1); throws obscura::Error.
    void (*run)(const MethodRun&);
    // Its blur's weights also fall within BLUR_REACH R across the surface (kernels/kernel_params.glsl):
    // where R spans a few pixels, a blur of pixels alone averages over most of R. Off where the
    // blur's work is the method's noise (docs/notes/2026-11-29-blur-reach.md).
    bool blurWithinReach = false;
    // Its value at a pixel depends on the whole frame (discs build their hierarchy over all of
    // it), so a host rendering tiles gives every tile the whole frame, not a window and an apron.
    bool readsWholeFrame = false;
};

const std::vector<MethodInfo>& methods();
// nullptr for an unknown name.
const MethodInfo* findMethod(const std::string& name);
// Whether `method` makes `output` ("ao", "do", "gi"); false for an unknown method.
bool methodOutputs(const std::string& method, const char* output);
// Whether `method` reads `pass` ("depth", "deep", ...); false for an unknown method.
bool methodReads(const std::string& method, const char* pass);
// "hbao, ssdo, ssao, rtao" (or with `sep`); with `reading`, only the methods that read that pass.
std::string methodNames(const char* sep = ", ", const char* reading = nullptr);
// Every method's own parameter, in table order (the hosts' extra flags and keywords).
std::vector<const MethodParam*> allMethodParams();
// The parameters `method` reads: its own, then those other methods share with it.
std::vector<const MethodParam*> paramsOf(const std::string& method);
// The named value spelled `word`, or nullptr.
const NamedValue* findNamed(const MethodParam& p, const std::string& word);
// A host's plain number (OFX) as the parameter's value: a named value's hostValue maps back to it,
// and so does a number outside the range nearer to that hostValue than to any other word's.
double fromHostValue(const MethodParam& p, double hostValue);
// The message for a value outside the parameter's range, or "" when it is inside. A named
// value's number passes only with `named` (Settings hold them; hosts parse them as words).
std::string checkParam(const MethodParam& p, double value, bool named = false);
// A setting some hosts offer that only some methods read. Its value is parsed by the host (a
// path, a colour, a list), so it is not a MethodParam; the table says who reads it, so every
// host refuses it alike for a method that would ignore it.
struct MethodOption {
    const char* key;                   // Python keyword ("bounce")
    const char* flag;                  // CLI flag ("--bounce")
    const char* ofx;                   // OpenFX parameter, nullptr where the node has none
    std::vector<const char*> methods;  // the methods that read it
};
const std::vector<MethodOption>& methodOptions();
// How a refusal names things: the CLI's flags (--bounce, --method ssdo) or the keywords of
// Python and OpenFX (bounce, method='ssdo').
enum class Spelling { Flag, Key };
// The methods that read the setting `name` (a MethodParam or MethodOption, by key, flag or
// OpenFX name); empty when every method reads it or no table entry has that name.
std::vector<std::string> methodsReading(const std::string& name);
// "" when `method` reads setting `name`, else the one-line refusal naming the methods that do:
// "--bounce is read by --method ssdo only, not by --method hbao".
std::string settingRefusal(const std::string& method, const std::string& name, Spelling spelling);
// "" when `method` writes `output` ("ao", "do", "gi", "relit"), else the refusal naming who does.
std::string outputRefusal(const std::string& method, const std::string& output, Spelling spelling);

// Applies every method's level `quality` to `s`; false for an unknown level.
bool applyMethodPresets(const std::string& quality, Settings& s);

} // namespace obscura
