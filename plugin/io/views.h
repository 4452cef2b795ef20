// Multi-view (stereo) files, as OpenEXR's multi-view convention has them: a `multiView`
// attribute lists the views, the first being the default view. In one part a channel belongs to
// a view by its name, layer.view.channel ("depth.right.Z", "right.Z"), and a name without a dot
// to the default view ("Z"); a name whose first component is a view ("right.depth.Z") is read as
// that view's too, as some writers prefix the view, and in a part that names its views so, the
// channels of no view ("depth.Z") are the default view's. In a multipart file a part belongs to a view
// by its `view` attribute, and its channels carry no view in their names.
#pragma once
#include "io/exr_file.h"

#include <map>
#include <string>
#include <vector>

namespace obscura {

// The views of a file: the multiView list of its parts, then `view` attributes the list lacks,
// in file order. Empty for a file that is not multi-view.
std::vector<std::string> fileViews(const ExrInfo& info);
// A part's `view` attribute, or "".
std::string partView(const ExrPart& part);
// The view channel `name` (of a part without a `view` attribute) belongs to; "" for none.
std::string channelView(const std::string& name, const std::vector<std::string>& views);
// The name OpenEXR gives channel `name` in views[index]: the view as the last component but one
// ("obscura.AO.Y" in right: "obscura.AO.right.Y"); a name without a dot in the default view stays.
std::string nameInView(const std::string& name, const std::vector<std::string>& views, size_t index);

// The file as one view sees it: the same parts (so part indices stay the file's), each holding
// only the view's channels, named without the view: what the layer presets then read.
struct FileView {
    std::string name;
    ExrInfo info;
    std::vector<std::map<std::string, std::string>> fileNames;  // [part]: name in `info` -> in the file

    // The file's name of channel `name` of part `part` (the name itself when it is not the view's).
    std::string fileName(int part, const std::string& name) const;
};
FileView viewOfFile(const ExrInfo& info, const std::string& view);

// "left, right", for messages.
std::string viewList(const std::vector<std::string>& views);
// Each of `requested` checked to be one of the file's views; an Error names the file's views.
void requireViews(const ExrInfo& info, const std::vector<std::string>& requested);

} // namespace obscura
