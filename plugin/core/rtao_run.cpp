#include "core/error.h"
#include "core/method_runs.h"

namespace obscura {

void runRtaoMethod(const MethodRun&) { throw Error("--method rtao is not built yet"); }

} // namespace obscura
