// Colour management (OpenColorIO): which colour space an input is in, conversion to and
// from the working scene-linear space, how output layers are tagged, and display previews.
//
// The config is $OCIO when set (and not empty), else the one obscura ships
// (ocio/config.ocio: share/obscura/ocio/config.ocio next to an installed binary, or the
// source tree's copy for a build-tree binary). Debian's OpenColorIO 2.1 has no built-in
// configs, hence the shipped one. The working space is the config's scene_linear role
// (lin_rec709 in the shipped config).
#pragma once
#include "base/image.h"
#include "io/exr_file.h"

#include <OpenEXR/ImfChromaticities.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenImageIO/imageio.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace obscura {

// What a file says about its colour, gathered from an EXR header or an OpenImageIO spec.
struct ColourMetadata {
    std::string colorInteropID;                       // "colorInteropID" (Color Interop Forum ids)
    std::string oiioColorSpace;                       // "oiio:ColorSpace"
    std::optional<Imf::Chromaticities> chromaticities;  // the standard attribute, when present
};
ColourMetadata colourMetadata(const Imf::Header& header);
// The same from a file OpenImageIO opened (environment maps: EXR, HDR, PNG, ...). Note that
// OpenImageIO reports "Linear" for most float files and "sRGB" for 8-bit ones when they
// carry nothing else. Defined in libobscura_oiio.so (io/oiio_module.h).
ColourMetadata colourMetadata(const OIIO::ImageSpec& spec);

struct ColourSpaceGuess {
    std::string name;     // a colour space of the config (canonical name)
    std::string source;   // "--colorspace", "colorInteropID", "oiio:ColorSpace",
                          // "chromaticities (AP1)", ..., or "default"
    std::string warning;  // non-empty when the space was assumed or metadata was ignored:
                          // one line for the caller to print or put in its report
};

class ColourManager {
public:
    // $OCIO if set and not empty, else the shipped config. Throws obscura::Error with one
    // line naming the path (and where it came from) when it cannot be loaded or has no
    // scene_linear role.
    ColourManager();
    explicit ColourManager(const std::string& configPath);
    ~ColourManager();
    ColourManager(const ColourManager&) = delete;
    ColourManager& operator=(const ColourManager&) = delete;

    // The shipped config's path: installed copy if it exists, else the source tree's ("" if neither).
    static std::string shippedConfigPath();

    const std::string& configPath() const;
    const std::string& workingSpace() const;  // canonical name of the scene_linear role's space
    const std::string& dataSpace() const;     // the data role's space, or "raw"

    // Canonical config name for a name, alias, role or common spelling ("Linear",
    // "scene_linear", "lin_ap1", "ACES - ACEScg", "Non-Color", ...); "" when unknown.
    std::string resolve(const std::string& nameOrSpelling) const;
    // resolve() or throw Error("unknown colour space 'X' for <what> (known: ...)").
    std::string require(const std::string& nameOrSpelling, const std::string& what) const;
    bool isData(const std::string& space) const;
    // The primaries and white of a config space when it is one obscura knows (Rec.709, AP1,
    // AP0, Rec.2020, P3-D65 linear); nullopt otherwise.
    std::optional<Imf::Chromaticities> chromaticitiesOf(const std::string& space) const;

    // First match wins: override (must name a space; throws Error otherwise), colorInteropID,
    // oiio:ColorSpace, the chromaticities attribute matched to a known set of primaries and
    // white (within 0.002 in x and y), else the config's linear Rec.709 space (OpenEXR's
    // meaning of a file without chromaticities; the working space when the config has no
    // such space) with a warning. An unrecognised string attribute or primaries give a
    // warning and fall through to the next source. A bare "Linear" (which OpenImageIO reports
    // for any float file) yields to chromaticities when the header has them.
    // `overrideFlag` names the override in messages (--env-colorspace for the environment map).
    ColourSpaceGuess detectColourSpace(const Imf::Header& header, const std::string& override = "") const;
    ColourSpaceGuess detectColourSpace(const ColourMetadata& meta, const std::string& override = "",
                                       const std::string& overrideFlag = "--colorspace") const;

    // Converts channels 0..2 of every pixel (further channels, e.g. alpha, are untouched)
    // in place. No-op when the spaces are the same, or either is data. Needs >= 3 channels.
    void convert(Image& img, const std::string& from, const std::string& to) const;
    void convert(const MutablePlane& plane, const std::string& from, const std::string& to) const;
    void toWorkingSpace(Image& rgb, const std::string& fromSpace) const { convert(rgb, fromSpace, workingSpace()); }
    void fromWorkingSpace(Image& rgb, const std::string& toSpace) const { convert(rgb, workingSpace(), toSpace); }

    // The space DO, GI and relit are written in, for a file whose colour passes are in
    // `inputSpace` (detectColourSpace() of the part, or --colorspace): that space when it is
    // scene-linear with primaries obscura knows, so the file's own `chromaticities` (which
    // every part of a file shares, and obscura never changes) describe the new layers as they
    // describe the beauty; else the working space.
    std::string layerSpace(const std::string& inputSpace) const;

    // Tags for new layers of output part `part`: one string attribute per name,
    // "obscura/<name>/colorspace" = `layerSpace` (colour names) or the data space ("raw",
    // data names), and for colour names "obscura/<name>/chromaticities" = "rx ry gx gy bx by
    // wx wy" when that space's primaries are known. Names are used verbatim: give RGB layers
    // by layer name ("obscura.DO", as frame_job.cpp tags them) and single channels by channel
    // name ("obscura.AO.Y"). No header attribute is touched: the standard `chromaticities`
    // belongs to the file. `note` (optional) says in which space the colour layers are.
    std::vector<StringAttribute> tagOutputPart(int part, const std::string& layerSpace,
                                               const std::vector<std::string>& colourNames,
                                               const std::vector<std::string>& dataNames,
                                               std::string* note = nullptr) const;

    // The config's default display and its default view, when not given.
    std::string defaultDisplay() const;
    std::string defaultView(const std::string& display) const;
    // Channels 0..2 of `rgbWorking` (working space) through the display/view transform,
    // written as an 8-bit PNG atomically (temp + rename). Throws Error (one line).
    void writeDisplayPreview(const std::string& path, const Image& rgbWorking,
                             const std::string& display = "", const std::string& view = "") const;
    // The same transform applied in place (channels 0..2), for hosts that show the result.
    void applyDisplayView(Image& rgbWorking, const std::string& display = "", const std::string& view = "") const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// A process-wide manager built on first use ($OCIO or the shipped config); later calls
// reuse it. Throws Error (one line) if the config cannot be loaded.
const ColourManager& colourManager();

// Threads a colour conversion may use, process-wide like OpenEXR's pool: a frame job sets its
// --threads here, so a farm task given one CPU keeps to it (0: every core).
void setColourThreads(int n);

// Convenience wrappers over colourManager().
std::string detectColourSpace(const Imf::Header& header, const std::string& override,
                              std::string* warning = nullptr);
void toWorkingSpace(Image& rgb, const std::string& fromSpace);
void fromWorkingSpace(Image& rgb, const std::string& toSpace);
// The OpenColorIO config obscura loads: $OCIO, else the one shipped with it (`origin` says
// which); throws obscura::Error when neither exists.
std::string colourConfigPath(std::string* origin = nullptr);
void writeDisplayPreview(const std::string& path, const Image& rgbWorking);

} // namespace obscura
