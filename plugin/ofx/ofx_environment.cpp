// The per-instance environment map cache (ofx_environment.h).
#include "ofx_environment.h"

#include "base/error.h"
#include "io/environment_map.h"
#include "io/exr_file.h"

#include <sys/stat.h>

namespace obscura::ofx {

std::shared_ptr<const Image> environmentFor(EnvironmentCache& cache, const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw FileError(path, "the environment map does not exist");
    const long long mtime = (long long)st.st_mtim.tv_sec * 1000000000LL + st.st_mtim.tv_nsec;
    std::lock_guard<std::mutex> lock(cache.mutex);
    if (!cache.image || cache.path != path || cache.mtimeNs != mtime || cache.size != (long long)st.st_size) {
        cache.image.reset();
        // The CLI's default --max-pixels: the header's size is checked before allocating.
        cache.image = std::make_shared<const Image>(readEnvironmentMap(path, "", kDefaultMaxPixels).rgb);
        cache.path = path;
        cache.mtimeNs = mtime;
        cache.size = (long long)st.st_size;
    }
    return cache.image;
}

} // namespace obscura::ofx
