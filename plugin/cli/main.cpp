#include "cli/cli.h"
#include "cli/heap_tuning.h"

int main(int argc, char** argv) {
    obscura::cli::tuneHeap(argv);
    return obscura::cli::run(argc, argv);
}
