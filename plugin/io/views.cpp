#include "io/views.h"

#include "base/error.h"

#include <OpenEXR/ImfStandardAttributes.h>

#include <algorithm>

namespace obscura {

namespace {

std::vector<std::string> components(const std::string& name) {
    std::vector<std::string> out;
    size_t start = 0;
    for (size_t dot; (dot = name.find('.', start)) != std::string::npos; start = dot + 1)
        out.push_back(name.substr(start, dot - start));
    out.push_back(name.substr(start));
    return out;
}

bool contains(const std::vector<std::string>& list, const std::string& s) {
    return std::find(list.begin(), list.end(), s) != list.end();
}

std::string joined(const std::vector<std::string>& parts) {
    std::string out;
    for (const std::string& p : parts) out += (out.empty() ? "" : ".") + p;
    return out;
}

// `name` without the view component channelView found in it.
std::string withoutView(const std::string& name, const std::vector<std::string>& views) {
    std::vector<std::string> c = components(name);
    if (c.size() < 2) return name;
    if (contains(views, c[c.size() - 2])) c.erase(c.end() - 2);
    else if (contains(views, c[0])) c.erase(c.begin());
    return joined(c);
}

} // namespace

std::string partView(const ExrPart& part) { return part.header.hasView() ? part.header.view() : ""; }

std::vector<std::string> fileViews(const ExrInfo& info) {
    std::vector<std::string> views;
    for (const ExrPart& part : info.parts)
        if (Imf::hasMultiView(part.header))
            for (const std::string& v : Imf::multiViewAttribute(part.header).value())
                if (!v.empty() && !contains(views, v)) views.push_back(v);
    for (const ExrPart& part : info.parts) {
        const std::string v = partView(part);
        if (!v.empty() && !contains(views, v)) views.push_back(v);
    }
    return views;
}

std::string channelView(const std::string& name, const std::vector<std::string>& views) {
    if (views.empty()) return "";
    const std::vector<std::string> c = components(name);
    if (c.size() == 1) return views[0];
    if (contains(views, c[c.size() - 2])) return c[c.size() - 2];
    return contains(views, c[0]) ? c[0] : "";
}

std::string nameInView(const std::string& name, const std::vector<std::string>& views, size_t index) {
    std::vector<std::string> c = components(name);
    if (c.size() == 1 && index == 0) return name;
    c.insert(c.end() - 1, views.at(index));
    return joined(c);
}

std::string FileView::fileName(int part, const std::string& n) const {
    const auto& names = fileNames.at(part);
    const auto it = names.find(n);
    return it == names.end() ? n : it->second;
}

namespace {
// Whether a part names a view's layers with the view as a prefix ("right.depth.Z"): a writer that
// prefixes the other views leaves the default view's channels as they are ("depth.Z"), which
// OpenEXR's rule gives no view. (Layers named OpenEXR's way beside them, such as an earlier run's
// "obscura.AO.left.Y", do not change that.)
bool prefixesViews(const ExrPart& part, const std::vector<std::string>& views) {
    for (const ExrChannel& ch : part.channels) {
        const std::vector<std::string> c = components(ch.name);
        // "right.Z" is both forms; "right.depth.Z" the prefix's alone.
        if (c.size() >= 3 && contains(views, c[0]) && !contains(views, c[c.size() - 2])) return true;
    }
    return false;
}
} // namespace

FileView viewOfFile(const ExrInfo& info, const std::string& view) {
    const std::vector<std::string> views = fileViews(info);
    FileView out;
    out.name = view;
    out.info = info;
    out.fileNames.resize(info.parts.size());
    for (size_t p = 0; p < info.parts.size(); ++p) {
        ExrPart& part = out.info.parts[p];
        const std::string whole = partView(part);
        std::vector<ExrChannel> kept;
        for (const ExrChannel& ch : part.channels) {
            // A part of a view holds that view's channels under their own names.
            if (!whole.empty()) {
                if (whole == view) kept.push_back(ch);
                continue;
            }
            if (channelView(ch.name, views) != view) continue;
            ExrChannel renamed = ch;
            renamed.name = withoutView(ch.name, views);
            if (out.fileNames[p].count(renamed.name)) continue;  // "Z" and "left.Z" in one file: the first
            out.fileNames[p][renamed.name] = ch.name;
            kept.push_back(renamed);
        }
        // The default view of a part that prefixes the others also holds the channels of no view,
        // after its own (which win a name both have).
        if (whole.empty() && !views.empty() && view == views[0] && prefixesViews(info.parts[p], views))
            for (const ExrChannel& ch : info.parts[p].channels)
                if (channelView(ch.name, views).empty() && !out.fileNames[p].count(ch.name)) {
                    out.fileNames[p][ch.name] = ch.name;
                    kept.push_back(ch);
                }
        std::sort(kept.begin(), kept.end(), [](const ExrChannel& a, const ExrChannel& b) { return a.name < b.name; });
        part.channels = std::move(kept);
    }
    return out;
}

std::string viewList(const std::vector<std::string>& views) {
    std::string out;
    for (const std::string& v : views) out += (out.empty() ? "" : ", ") + v;
    return out;
}

void requireViews(const ExrInfo& info, const std::vector<std::string>& requested) {
    const std::vector<std::string> views = fileViews(info);
    for (const std::string& v : requested)
        if (!contains(views, v))
            throw FileError(info.path, "no view '" + v + "'; " +
                                           (views.empty() ? std::string("the file has no views (no multiView attribute or view parts)")
                                                          : "the file's views: " + viewList(views)));
}

} // namespace obscura
