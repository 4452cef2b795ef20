// read_deep: a deep EXR's surfaces as the arrays compute_ao(deep=) and compute_gi(deep=,
// deep_colour=) take, read as the CLI reads a --flat deep file (io/deep_file.h).
#include "io/deep_file.h"
#include "python/call_args.h"
#include "python/py_args.h"
#include "python/py_bind.h"
#include "python/py_job.h"

#include <limits>

namespace obscura::python {

namespace {

const char* kReadDeepDoc = R"doc(A deep EXR's surfaces as arrays, read as the CLI reads a deep file
(docs/deep.md), as a dict:

'deep' float32 (H, W, 2L): per pixel up to L = deep_layers surfaces along its ray as (front,
back) depths, nearest first (front inf past the pixel's last; back == front where no span is
known), what compute_ao(deep=) and compute_gi(deep=) take; 'colour' float32 (H, W, 3L), each
surface's un-premultiplied R, G, B (compute_gi(deep_colour=)), when colour=True and the file has
R, G and B, else None; 'layers' L; 'data_window' the pixels the arrays cover, (x0, y0, x1, y1);
'display_window'; 'samples', 'empty_pixels', 'dropped_samples', 'unsorted_pixels',
'truncated_pixels' (what the reader counted, skipped or sorted).

deep_layers: 1-16 (default 4), the most surfaces kept per pixel (the farthest are dropped).
data_window: (x0, y0, x1, y1), the window to give the arrays over, e.g. the flat passes'
read_passes(...)['data_window']: pixels the deep file does not cover have no surface (front inf)
and no colour. Default: the deep file's own. max_pixels as read_passes(). The GIL is released
while reading. Raises obscura.Error for a flat file, a file without Z or an unreadable one.)doc";

py::dict readDeepPy(const py::object& path, const py::object& layersObj, const py::object& colourObj,
                    const py::object& windowObj, const py::object& maxPixels) {
    const std::string file = pathArg(path, "path");
    const int maxLayers = layersObj.is_none() ? Settings().deepLayers : methodIntArg(layersObj, "deep_layers");
    const bool colour = !colourObj.is_none() && boolArg(colourObj, "colour");
    const bool ownWindow = windowObj.is_none();
    const Box2i window = ownWindow ? Box2i{} : boxArg(windowObj, "data_window");
    const long long limit = maxPixelsArg(maxPixels);
    DeepLayers d;
    Image planes, colours;
    Box2i data;
    {
        py::gil_scoped_release release;
        d = readDeepLayers(file, maxLayers, {}, limit, colour);
        data = ownWindow ? d.data : window;
        planes = deepPlanesOver(std::move(d.planes), d.data, data, std::numeric_limits<float>::infinity());
        if (!d.colour.empty()) colours = deepPlanesOver(std::move(d.colour), d.data, data, 0.0f);
    }
    py::dict out;
    out["deep"] = imageToArray(std::move(planes), false);
    out["colour"] = colours.empty() ? py::object(py::none()) : py::object(imageToArray(std::move(colours), false));
    out["layers"] = d.layers;
    out["data_window"] = boxToTuple(data);
    out["display_window"] = boxToTuple(d.display);
    out["samples"] = d.samples;
    out["empty_pixels"] = d.emptyPixels;
    out["dropped_samples"] = d.droppedSamples;
    out["unsorted_pixels"] = d.unsortedPixels;
    out["truncated_pixels"] = d.truncatedPixels;
    return out;
}

} // namespace

void bindDeep(py::module_& m) {
    m.def(
        "read_deep",
        [](const py::object& path, const py::args& extra, const py::object& deepLayers, const py::object& colour,
           const py::object& dataWindow, const py::object& maxPixels, const py::kwargs& unknown) {
            checkPositional("read_deep", extra, {"path"}, "deep_layers=..., colour=...");
            checkNoKeywords("read_deep", unknown);
            required("read_deep", path, "path", "the deep EXR's path");
            return readDeepPy(path, deepLayers, colour, dataWindow, maxPixels);
        },
        py::arg("path") = py::none(), py::arg("deep_layers") = py::none(), py::arg("colour") = py::none(),
        py::arg("data_window") = py::none(), py::arg("max_pixels") = py::none(), kReadDeepDoc);
}

} // namespace obscura::python
