#include "cli/cli.h"

int main(int argc, char** argv) { return obscura::cli::run(argc, argv); }
