#include "cli.h"
namespace obscura::cli {
int run(int, char**) { return 0; }
} // namespace obscura::cli
