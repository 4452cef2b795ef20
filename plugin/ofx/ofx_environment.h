// The environment map an instance lights SSDO with: plugin/io's reader (the CLI's and
// Python's), converted to the working space, cached per instance by path, modification time
// and size, so an edited file is re-read and instances share nothing.
#pragma once
#include "base/image.h"

#include <memory>
#include <mutex>
#include <string>

namespace obscura::ofx {

struct EnvironmentCache {
    std::mutex mutex;
    std::string path;
    long long mtimeNs = 0, size = -1;
    std::shared_ptr<const Image> image;
};

// The map at `path`, from `cache` while the file is unchanged; throws for a missing file.
std::shared_ptr<const Image> environmentFor(EnvironmentCache& cache, const std::string& path);

} // namespace obscura::ofx
