// The command-line process's heap: transparent huge pages, grown 64 MiB at a time.
//
// A frame's buffers are touched page by page the first time. Each 4 KiB page costs a fault, and
// on a virtual machine a fault traps to the hypervisor: on the machines obscura is tested on, the
// faults were a third of a 1024 x 576 frame's time (docs/farm.md#the-processs-heap). glibc backs its
// heap with huge pages and grows it in large steps when asked by two tunables (glibc.malloc.hugetlb
// and glibc.malloc.top_pad), which it reads only as a process starts.
#pragma once

namespace obscura::cli {

// The tunables glibc is given; the user's own GLIBC_TUNABLES follow them and so win.
inline constexpr const char* kHeapTunables = "glibc.malloc.hugetlb=1:glibc.malloc.top_pad=67108864";

// Called first in main(). Without the tunables, runs this program again (same PID, arguments and
// descriptors) with them added to GLIBC_TUNABLES; in that run, gives the environment back as the
// user had it, so that nothing the CLI starts (sbatch) inherits them. Returns where nothing is to
// be done: OBSCURA_HEAP_TUNING=0, GLIBC_TUNABLES naming glibc.malloc.hugetlb already, a run
// under valgrind, a debugger or strace, or an exec that failed.
void tuneHeap(char** argv);

} // namespace obscura::cli
