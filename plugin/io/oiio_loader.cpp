// Finds and loads libobscura_oiio.so (io/oiio_module.h says why it is loaded late).
#include "io/oiio_module.h"

#include "base/error.h"

#include <dlfcn.h>

#include <filesystem>
#include <vector>

namespace obscura {

namespace {

constexpr const char* kModuleFile = "libobscura_oiio.so";

// Beside the binary holding this code (the obscura executable, the Python module), then the
// install layout (bin/ -> lib/obscura/), then where this build put it.
std::vector<std::string> candidates() {
    std::vector<std::string> out;
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&oiioModule), &info) && info.dli_fname) {
        const std::filesystem::path dir = std::filesystem::path(info.dli_fname).parent_path();
        out.push_back((dir / kModuleFile).string());
        out.push_back((dir / ".." / "lib" / "obscura" / kModuleFile).string());
    }
    out.push_back(OBSCURA_OIIO_MODULE_BUILD_PATH);
    out.push_back(OBSCURA_OIIO_MODULE_INSTALL_PATH);
    return out;
}

const OiioModule* load() {
    std::string tried;
    for (const std::string& path : candidates()) {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) continue;
        void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) throw Error("cannot load the OpenImageIO module " + path + ": " + firstLineOf(dlerror()));
        auto entry = reinterpret_cast<const OiioModule* (*)()>(dlsym(handle, "obscuraOiioModule"));
        const OiioModule* m = entry ? entry() : nullptr;
        if (!m || m->abi != kOiioModuleAbi)
            throw Error("the OpenImageIO module " + path + " is from another build of obscura");
        return m;
    }
    throw Error(std::string("cannot find ") + kModuleFile + " (environment maps need it)");
}

} // namespace

const OiioModule& oiioModule() {
    static const OiioModule* module = load();  // a failed load throws, and the next call retries
    return *module;
}

} // namespace obscura
